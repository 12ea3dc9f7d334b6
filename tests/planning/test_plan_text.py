"""Plan texts read against a compiled problem: every malformed line is named, nothing is run."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import UnreadableText
from ocplus_plan.planning.compile import compile as compile_state
from ocplus_plan.planning.plan_text import plan_from_text, read_plan_text
from ocplus_plan.planning.validate import validate_plan
from ocplus_plan.sim import make_rules, new_state

TINY = {"name": "tiny", "game_map": [[1, 3, 6, 1], [5, 0, 0, 7], [1, 1, 1, 1]],
        "agent_spawn_points": [[1, 1]]}
#: a plan for the tiny kitchen's first order (written as a planner prints it)
PLAN = """; a plan for o0
(pick a0 tomato0 tomato_0_1 s_1_1)
(move a0 s_1_1 s_1_2)
(put_board a0 tomato0 board_0_2 s_1_2)
(chop a0 tomato0 board_0_2 s_1_2)
(move a0 s_1_2 s_1_1)
(pick a0 plate0 plate_1_0 s_1_1)
(move a0 s_1_1 s_1_2)
(plate_take a0 tomato0 board_0_2 s_1_2 plate0 k_tomato c_empty c_tomato)
(DELIVER1 a0 plate0 c_tomato c_empty o0 o_none delivery_1_3 s_1_2 plate_1_0 tomato0 tomato_0_1)
; cost = 9 (general cost)
"""


@pytest.fixture(scope="module")
def problem():
    state = new_state(make_rules("easy", map=TINY, n_agents=1, recipes=["tomato"]), 0)
    return compile_state(state, None, encoding="classical", max_orders=1).problem


def test_a_planners_plan_reads_back_valid(problem):
    plan, steps = plan_from_text(PLAN, problem, temporal=False)
    assert len(steps) == 9 and validate_plan(problem, plan, use_val=False).ok


def test_time_stamped_lines_keep_start_and_duration(problem):
    steps = read_plan_text("0.000: (pick a0 tomato0 tomato_0_1 s_1_1) [1.000]\n"
                           "1.001: (move a0 s_1_1 s_1_2) [1]", problem)
    assert [(s["start"], s["duration"]) for s in steps] == [(0.0, 1.0), (1.001, 1.0)]


@pytest.mark.parametrize("text, message", [
    ("(fly a0 s_1_1)", "line 1: unknown action 'fly'"),
    ("\n(move a0 s_1_1)", "line 2: move takes 3 arguments"),
    ("(move a0 s_1_1 s_9_9)", "line 1: move: unknown object 's_9_9'"),
    ("(move tomato0 s_1_1 s_1_2)", "line 1: move: 'tomato0' is a item, but parameter a needs"),
    ("1e999: (move a0 s_1_1 s_1_2) [1]", "line 1: the start time '1e999' is not a finite"),
    ("x: (move a0 s_1_1 s_1_2)", "line 1: 'x: \\(move a0 s_1_1 s_1_2\\)' is not a plan step"),
    ("(move a0 s_1_1 s_1_2) [1]", "line 1: a \\[duration\\] needs a start time"),
    ("(move a0 s_1_1 s_1_2)\n0.0: (move a0 s_1_2 s_1_1) [1]", "line 2: .* without a time"),
    ("(move a0 s_1_1 s_1_2)\nSure! Here is the plan.", "line 2: 'Sure! Here is the plan.'"),
    ("(move a0 (s_1_1) s_1_2)", "line 1: .* is not a plan step"),
    ("(move a0 s_1_1 \"s_1_2\")", "line 1: '\"s_1_2\"' is not a PDDL name"),
    ("()", "line 1: '\\(\\)' names no action"),
])
def test_a_malformed_line_is_named(problem, text, message):
    with pytest.raises(UnreadableText, match=message):
        read_plan_text(text, problem)


def test_a_huge_plan_is_refused_unread(problem):
    with pytest.raises(UnreadableText, match="more than the limit of 1000"):
        read_plan_text("(move a0 s_1_1 s_1_2)\n" * 100, problem, max_chars=1000)


def test_a_temporal_plan_must_be_time_stamped(problem):
    with pytest.raises(UnreadableText, match="'START: \\(action ...\\) \\[DURATION\\]'"):
        read_plan_text("(move a0 s_1_1 s_1_2)", problem, temporal=True)

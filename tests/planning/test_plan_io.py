"""IPC plan files: both formats read, every malformed line refused with its number."""

from __future__ import annotations

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.errors import UnreadableText
from ocplus_plan.planning import compile
from ocplus_plan.planning.plan_io import MAX_PLAN_BYTES, format_plan, parse_plan, read_plan
from ocplus_plan.sim import make_rules, new_state

from .test_engines import tiny_classical, tiny_temporal

# the easy kitchen's first moves (seed 0): a0 stands at s_1_1
MOVE = "(move a0 s_1_1 s_1_2)"


@pytest.fixture(scope="module")
def kitchen():
    return compile(new_state(make_rules("easy"), 0), encoding="classical").problem


@pytest.fixture(scope="module")
def kitchen_temporal():
    return compile(new_state(make_rules("easy"), 0), encoding="temporal").problem


def test_sequential_lines_numbered_or_not_with_comments_and_any_case(kitchen):
    plan = parse_plan(f"; by some planner\n0: {MOVE}\n\n(MOVE A0 S_1_2 S_1_4) [1]\n"
                      "; cost = 2 (unit cost)\n", kitchen)
    assert [str(a) for a in plan.actions] == ["move(a0, s_1_1, s_1_2)", "move(a0, s_1_2, s_1_4)"]


def test_time_stamped_lines_for_a_temporal_problem(kitchen_temporal):
    plan = parse_plan(f"0.000: {MOVE} [1.000]\n1.001: (move a0 s_1_2 s_1_4) [2]\n",
                      kitchen_temporal)
    assert [(float(t), float(d)) for t, _, d in plan.timed_actions] == [(0.0, 1.0),
                                                                         (1.001, 2.0)]


def test_a_temporal_line_without_a_duration_names_the_line(kitchen_temporal):
    with pytest.raises(UnreadableText, match=r"line 2: move is durative: give its duration"):
        parse_plan(f"0: {MOVE} [1]\n1: {MOVE}\n", kitchen_temporal)


@pytest.mark.parametrize("line, message", [
    ("(fly a0 s_1_1 s_1_2)", "unknown action 'fly'"),
    ("(move a0 s_1_1)", "move takes 3 arguments"),
    ("(move a0 s_1_1 s_9_9)", "unknown object 's_9_9'"),
    ("(move a0 tomato0 s_1_2)", "'tomato0' is a item"),
    ("x1: (move a0 s_1_1 s_1_2)", "is not a plan step"),
    ("nan: (move a0 s_1_1 s_1_2)", "is not a plan step"),
    ("-1: (move a0 s_1_1 s_1_2)", "is not a plan step"),
    ("0: (move a0 s_1_1 s_1_2) [fast]", "is not a plan step"),
    ("move a0 s_1_1 s_1_2", "is not a plan step"),
    ("(move a0 (s_1_1) s_1_2)", "is not a plan step"),
    ("()", "names no action"),
    ("(move a0 s_1_1 __import__('os'))", "is not a plan step"),
    ("(move a0 s_1_1 s.1.2)", "not a PDDL name"),
])
def test_a_malformed_line_is_refused_with_its_number(kitchen, line, message):
    with pytest.raises(UnreadableText, match=message) as info:
        parse_plan(f"{MOVE}\n{line}\n", kitchen, "my.plan")
    assert "my.plan, line 2" in str(info.value) and info.value.line == 2


def test_a_huge_time_is_refused(kitchen_temporal):
    with pytest.raises(UnreadableText, match="line 1: the start time '1e999' is not a finite"):
        parse_plan(f"1e999: {MOVE} [1]\n", kitchen_temporal)


def test_a_huge_file_is_refused_without_reading_it(tmp_path, kitchen):
    path = tmp_path / "huge.plan"
    path.write_bytes(b"(move a0 s_1_1 s_1_2)\n" * (MAX_PLAN_BYTES // 20))
    with pytest.raises(UnreadableText, match="bytes; a plan file has at most"):
        read_plan(path, kitchen)


def test_a_binary_file_names_the_line_of_the_first_bad_byte(tmp_path, kitchen):
    path = tmp_path / "bin.plan"
    path.write_bytes(b"(move a0 s_1_1 s_1_2)\n\xff\xfe\n")
    with pytest.raises(UnreadableText, match="line 2: not UTF-8"):
        read_plan(path, kitchen)


def test_a_missing_file_is_a_plan_format_error(tmp_path, kitchen):
    with pytest.raises(UnreadableText, match="no such plan file"):
        read_plan(tmp_path / "nope.plan", kitchen)


def test_written_plans_read_back_to_the_same_text():
    problem = tiny_classical()
    plan = parse_plan("(move l0 l2)\n(move l2 l3)\n", problem)
    text = format_plan(plan, "two moves")
    assert text == "; two moves\n0: (move l0 l2)\n1: (move l2 l3)\n"
    assert format_plan(parse_plan(text, problem), "two moves") == text


def test_written_temporal_plans_keep_exact_times():
    problem = tiny_temporal()
    plan = parse_plan("0: (move l0 l1) [2]\n0: (cook) [3]\n2.001: (move l1 l2) [3]\n", problem)
    text = format_plan(plan)
    assert text == ("0.000: (move l0 l1) [2.000]\n0.000: (cook) [3.000]\n"
                    "2.001: (move l1 l2) [3.000]\n")
    assert format_plan(parse_plan(text, problem)) == text

"""TamerLite through planning/_tamerlite.py: its grounding join and kitchen solves.

Skips with the reason when tamerlite (the planners extra) is not installed.
"""

from __future__ import annotations

import itertools
import warnings

import pytest

pytest.importorskip("unified_planning")
pytest.importorskip("tamerlite", reason="tamerlite is not installed: pip install -e '.[planners]'")

from ocplus_plan.planning import compile
from ocplus_plan.planning._tamerlite import static_groundings
from ocplus_plan.planning.engines import availability, solve
from ocplus_plan.sim import make_rules, new_state, transition

warnings.filterwarnings("ignore", message=".*rustamer.*")


def _require() -> None:
    avail = availability("tamerlite")
    if not avail.ok:
        pytest.skip(f"tamerlite unavailable: {avail.reason}")


def test_static_join_keeps_exactly_the_tuples_whose_static_facts_hold() -> None:
    """Brute force over every parameter tuple of the small actions of the easy kitchen."""
    problem = compile(new_state(make_rules("easy"), 0), encoding="temporal").problem
    groundings = static_groundings(problem)
    statics = problem.get_static_fluents()
    initial = problem.initial_values
    em = problem.environment.expression_manager
    checked = 0
    for action in problem.actions:
        if len(action.parameters) > 4:
            continue
        conds = [c for group in action.conditions.values() for c in group
                 if c.is_fluent_exp() and c.fluent() in statics]
        expected = set()
        for objs in itertools.product(*(problem.objects(p.type) for p in action.parameters)):
            subs = {em.ParameterExp(p): em.ObjectExp(o) for p, o in zip(action.parameters, objs)}
            if all(initial[c.substitute(subs)].is_true() for c in conds):
                expected.add(tuple(em.ObjectExp(o) for o in objs))
        assert set(groundings[action]) == expected, action.name
        checked += 1
    assert checked >= 10


def test_tamerlite_solves_the_easy_kitchen_with_one_and_two_cooks() -> None:
    _require()
    for n in (1, 2):
        state = new_state(make_rules("easy", n_agents=n), 4)
        result = solve(compile(state, encoding="temporal", max_orders=1).problem, "tamerlite",
                       timeout=30)
        assert result.status == "solved", result.reason
        assert result.validated is True, result.validation_detail
        assert {s["action"] for s in result.steps} >= {"chop", "deliver1"}


def test_a_steak_on_the_pan_needs_timed_literals_which_tamerlite_lacks() -> None:
    _require()
    state = new_state(make_rules("medium"), 0)
    for a in (2, 2, 1, 2, 4):  # pick the steak, step down, put it on the pan, wait
        transition(state, [a])
    result = solve(compile(state, encoding="temporal", max_orders=1).problem, "tamerlite",
                   timeout=10)
    assert result.status == "unsupported" and "TIMED_EFFECTS" in result.reason

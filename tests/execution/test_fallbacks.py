"""Fallbacks on failure, not only on proof: a configuration that keeps timing out on a
kitchen makes the pipeline try every cook, then the default planner."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from ocplus_plan.execution.planning_step import FAILURES_BEFORE_FALLBACK, compile_and_solve
from ocplus_plan.execution.spec import DEFAULT_PLANNER
from ocplus_plan.sim import make_rules, new_state

pytest.importorskip("ocplus_plan.planning.compile")


def _timeouts(monkeypatch):
    from ocplus_plan.planning import engines

    asked = []

    def solve(problem, planner, timeout=None, validate=False):
        asked.append(planner)
        return SimpleNamespace(status="timeout", plan=None, reason="cpu limit", cpu_time=0.0)

    monkeypatch.setattr(engines, "solve", solve)
    return asked


def test_a_one_cook_problem_that_keeps_timing_out_is_given_up_for_every_cook(monkeypatch):
    _timeouts(monkeypatch)
    state = new_state(make_rules("easy", n_agents=2, horizon=50), 0)
    pipeline = compile_and_solve("fast-downward", plan_cooks="one")
    modelled = []
    once = pipeline.solve_once
    pipeline.solve_once = lambda s, m, *a: modelled.append(m) or once(s, m, *a)
    for _ in range(FAILURES_BEFORE_FALLBACK):
        assert pipeline(state, (0, 1), "initial").status == "timeout"
    assert pipeline.proven.info()["failure_fallbacks"] >= 1
    assert [0] in modelled and modelled[-1] is None  # then asked with both cooks at once
    modelled.clear()
    pipeline(state, (0, 1), "initial")
    assert [0] not in modelled  # and from then on


def test_a_planner_that_keeps_failing_hands_over_to_the_default_planner(monkeypatch):
    asked = _timeouts(monkeypatch)
    state = new_state(make_rules("easy", n_agents=1, horizon=50), 0)
    pipeline = compile_and_solve("fast-downward")
    for _ in range(FAILURES_BEFORE_FALLBACK + 1):
        pipeline(state, (0,), "initial")
    names = asked
    assert names[-1] == DEFAULT_PLANNER and "fast-downward" in names
    assert pipeline.proven.info()["default_planner_fallbacks"] >= 1


#: one lane (row 1): two cooks who can never pass each other
LANE = {"name": "lane", "max_n_agent": 2, "agent_spawn_points": [[1, 1], [1, 5]],
        "game_map": [[1, 3, 1, 6, 1, 5, 1], [7, 0, 0, 0, 0, 0, 1], [1, 1, 1, 1, 1, 1, 1]]}


def _granularities(pipeline):
    asked = []
    once = pipeline.solve_once
    pipeline.solve_once = lambda s, m, n, gran: asked.append(gran) or once(s, m, n, gran)
    return asked


def test_cooks_in_one_lane_are_planned_with_cells_then_stations_when_that_fails(monkeypatch):
    _timeouts(monkeypatch)
    state = new_state(make_rules("easy", map=LANE, n_agents=2, horizon=50), 0)
    pipeline = compile_and_solve("fast-downward")
    asked = _granularities(pipeline)
    assert pipeline(state, (0, 1), "initial").status == "timeout"
    # every open order, then the oldest, with cells; then the oldest with stations
    assert asked == ["cells", "cells", "stations"]
    asked.clear()
    pipeline(state, (0,), "initial")  # one driven cook: nobody of ours to pass
    assert set(asked) == {"stations"}


def test_cooks_on_an_open_floor_are_planned_with_stations(monkeypatch):
    _timeouts(monkeypatch)
    state = new_state(make_rules("easy", n_agents=2, horizon=50), 0)
    pipeline = compile_and_solve("fast-downward")
    asked = _granularities(pipeline)
    pipeline(state, (0, 1), "initial")
    assert asked and set(asked) == {"stations"}


@pytest.mark.parametrize("reason", ["stall_all", "deadlock"])
def test_a_lasting_stall_and_a_deadlock_are_planned_with_cells(monkeypatch, reason):
    """On an open floor too: the stations abstraction lets cooks jump past each other, so a
    cook and a partner that wait for each other to pass get the same plan again from it;
    a lasting stall falls back to stations when no cells plan comes in time."""
    _timeouts(monkeypatch)
    state = new_state(make_rules("easy", n_agents=2, horizon=50), 0)
    pipeline = compile_and_solve("fast-downward")
    asked = _granularities(pipeline)
    pipeline(state, (0, 1), reason)
    assert asked[0] == "cells"
    if reason == "stall_all":
        assert asked == ["cells", "stations"]

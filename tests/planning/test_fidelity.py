"""Fidelity: plans of the model replayed in the simulator do what the model predicts.

A small sample here (the full 200-state run per preset is experiments/fidelity.py).
Planner tests skip with the availability reason when the planner is missing.
"""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import availability, solve
from ocplus_plan.planning.fidelity import replay, sample_states
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

R, D, L, U, S = (int(a) for a in Action)


@pytest.fixture(autouse=True)
def _private_cwd(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Fast Downward writes output.sas into the working directory: keep runs apart
    monkeypatch.chdir(tmp_path)


def _need(planner: str) -> None:
    avail = availability(planner)
    if not avail.ok:
        pytest.skip(f"{planner} unavailable: {avail.reason}")


def test_sampling_is_reproducible_and_varied() -> None:
    a = sample_states("medium", 6, seed=3)
    b = sample_states("medium", 6, seed=3)
    assert [s.state_hash() for s in a] == [s.state_hash() for s in b]
    assert len({s.t for s in a}) > 1


def test_replay_reports_a_world_that_disagrees_with_the_model() -> None:
    from unified_planning.plans import SequentialPlan

    state = new_state(make_rules("medium"), 0)
    compiled = compile(state)
    moved = state.copy()
    transition(moved, [L])  # the simulator's agent is no longer where the model says
    result = replay(compiled, SequentialPlan([]), moved)
    assert not result.ok and result.category == "initial" and "a0" in result.mismatch


@pytest.mark.parametrize("preset", ["easy", "medium"])
def test_fast_downward_plans_are_faithful_on_sampled_states(preset: str) -> None:
    _need("fast-downward")
    for state in sample_states(preset, 5, seed=11):
        compiled = compile(state)
        result = solve(compiled.problem, "fast-downward", timeout=60, use_val=False)
        assert result.status == "solved", result.reason
        assert result.validated
        rep = replay(compiled, result.plan, state)
        assert rep.ok, (state.t, rep.category, rep.mismatch)
        assert sorted(rep.served) == sorted(compiled.goal_orders)
        assert rep.steps == result.cost  # cost = simulator steps of the sequential replay


def test_rescue_of_a_steak_already_on_the_pan_is_faithful() -> None:
    _need("fast-downward")
    state = new_state(make_rules("medium"), 0)
    for a in [L, L, D, L] + [S] * 8:  # the steak has been on the pan for 9 ticks
        transition(state, [a])
    compiled = compile(state, max_orders=1)
    result = solve(compiled.problem, "fast-downward", timeout=60, use_val=False)
    assert result.status == "solved", result.reason
    first = compiled.map_back(result.plan.actions[0])
    assert first.kind == "rescue"
    rep = replay(compiled, result.plan, state)
    assert rep.ok, rep.mismatch


def test_temporal_plan_with_a_cooking_steak_is_valid() -> None:
    _need("kairos")
    state = new_state(make_rules("medium"), 0)
    for a in [L, L, D, L, S]:
        transition(state, [a])
    compiled = compile(state, encoding="temporal", max_orders=1)
    assert compiled.problem.timed_effects
    result = solve(compiled.problem, "kairos", timeout=60, use_val=False)
    if result.status == "timeout":
        pytest.skip("kairos timed out on a loaded machine")
    assert result.status == "solved", result.reason
    assert result.validated
    steps = [compiled.map_back(ai, start, dur) for start, ai, dur in result.plan.timed_actions]
    assert any(s.kind in ("take_off", "cook") for s in steps)
    assert any(s.kind == "deliver" for s in steps)

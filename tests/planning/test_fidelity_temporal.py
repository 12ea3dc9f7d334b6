"""The temporal fidelity replay: happenings on the model side, planned steps in the simulator.

Hand-built time-triggered plans test the happening logic and the time conventions
(no planner needed); a few sampled states are solved by Kairos and replayed
(skipped with the reason when Kairos is missing).
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from unified_planning.plans import ActionInstance, TimeTriggeredPlan

from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import availability, solve
from ocplus_plan.planning.fidelity import sample_states
from ocplus_plan.planning.fidelity_temporal import (
    ModelState,
    apply_happening,
    happenings,
    replay_temporal,
)
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, ItemState
from ocplus_plan.sim.rules import with_overrides

R, D, L, U, S = (int(a) for a in Action)
EPS = Fraction(1, 1000)


def _holding_steak_by_the_pan():
    """Medium, seed 0: the cook stands on (3, 1) next to the pan (3, 0), holding the steak."""
    state = new_state(make_rules("medium"), 0)
    for a in (L, L, D):
        transition(state, [a])
    return state


def _steak_on_the_pan_for(ticks: int):
    state = _holding_steak_by_the_pan()
    for a in [L] + [S] * (ticks - 1):
        transition(state, [a])
    return state


def _plan(compiled, *timed):
    """A TimeTriggeredPlan from (start, action name, object names, duration) tuples."""
    problem = compiled.problem
    return TimeTriggeredPlan([
        (Fraction(start), ActionInstance(problem.action(name),
                                         tuple(problem.object(o) for o in objs)),
         Fraction(duration))
        for start, name, objs, duration in timed])


def _cook(compiled, start, duration, taker_after=EPS):
    return _plan(
        compiled,
        (start, "cook", ("a0", "a0", "steak0", "pan_3_0", "s_3_1", "s_3_1"), duration),
        (start + EPS, "pan_put_done", ("a0",), 1),
        (start + duration + taker_after, "pan_take_done", ("a0", "steak0", "pan_3_0"), 1),
    )


def test_happenings_are_ground_and_ordered_ends_then_literals_then_starts() -> None:
    state = _steak_on_the_pan_for(9)  # window opens at 1, closes (burnt) at 12
    compiled = compile(state, encoding="temporal", max_orders=1)
    plan = _plan(compiled, (0, "move", ("a0", "s_3_1", "s_4_1"), 1),
                 (1, "move", ("a0", "s_4_1", "s_3_1"), 1))
    hs = happenings(compiled.problem, plan)
    assert [(h.time, h.rank, h.index) for h in hs] == [
        (0, 2, 0), (1, 0, 0), (1, 1, -1), (1, 2, 1), (2, 0, 1), (12, 1, -1)]
    first_end = hs[1]
    assert {str(e.fluent) for e in first_end.effects} == {
        "agent_at(a0, s_4_1)", "vacant(s_3_1)", "idle(a0)"}
    assert all(e.condition is None for e in first_end.effects)


def test_model_state_applies_effects_and_reports_a_false_condition() -> None:
    state = _holding_steak_by_the_pan()
    compiled = compile(state, encoding="temporal", max_orders=1)
    problem = compiled.problem
    fl = {f.name: f for f in problem.fluents}
    at = fl["agent_at"](problem.object("a0"), problem.object("s_4_1"))
    plan = _plan(compiled, (0, "move", ("a0", "s_3_1", "s_4_1"), 1),
                 (Fraction(1, 2), "move", ("a0", "s_4_1", "s_3_1"), 1))
    model = ModelState(problem)
    start, second_start, end = happenings(problem, plan)[:3]
    assert apply_happening(model, start) == ""
    assert not model.evaluate(at)
    # the second move starts before the first one ends: the agent is not there yet
    assert "agent_at(a0, s_4_1)" in apply_happening(model, second_start)
    assert apply_happening(model, end) == ""
    assert model.evaluate(at)


def test_a_hand_built_cook_envelope_replays_faithfully_at_both_duration_bounds() -> None:
    state = _holding_steak_by_the_pan()
    compiled = compile(state, encoding="temporal", max_orders=1)
    lo, hi = state.rules.cook_time, state.rules.burn_time - 1
    for start, duration in ((0, lo), (Fraction(7, 10), hi), (Fraction(1, 2), Fraction(25, 2))):
        rep = replay_temporal(compiled, _cook(compiled, start, duration), state)
        assert rep.ok, (start, duration, rep.mismatch)
        assert rep.actions == 3


def test_the_envelope_keeps_each_bumping_agent_busy_for_its_step() -> None:
    state = _holding_steak_by_the_pan()
    compiled = compile(state, encoding="temporal", max_orders=1)
    # moving away right after putting the steak on: the put is the cook's step
    plan = _plan(
        compiled,
        (0, "cook", ("a0", "a0", "steak0", "pan_3_0", "s_3_1", "s_3_1"), 10),
        (EPS, "move", ("a0", "s_3_1", "s_4_1"), 1),
    )
    rep = replay_temporal(compiled, plan, state)
    assert not rep.ok and rep.category == "model" and "idle(a0)" in rep.mismatch
    # after pan_put_done the agent is free again
    plan = _plan(
        compiled,
        (0, "cook", ("a0", "a0", "steak0", "pan_3_0", "s_3_1", "s_3_1"), 12),
        (EPS, "pan_put_done", ("a0",), 1),
        (1 + 2 * EPS, "move", ("a0", "s_3_1", "s_4_1"), 1),
        (2 + 3 * EPS, "move", ("a0", "s_4_1", "s_3_1"), 1),
        (12 + EPS, "pan_take_done", ("a0", "steak0", "pan_3_0"), 1),
    )
    rep = replay_temporal(compiled, plan, state)
    assert rep.ok, rep.mismatch


def test_a_duration_outside_the_cook_window_is_a_model_mismatch() -> None:
    state = _holding_steak_by_the_pan()
    compiled = compile(state, encoding="temporal", max_orders=1)
    rep = replay_temporal(compiled, _cook(compiled, 0, state.rules.burn_time), state)
    assert not rep.ok and rep.category == "model" and "duration" in rep.mismatch


@pytest.mark.parametrize("end, expected", [(11, ItemState.COOKED), (12, ItemState.BURNT)])
def test_timed_literals_hold_from_the_simulator_state_of_their_time(end: int,
                                                                   expected: ItemState) -> None:
    # 9 ticks on the pan: burnt after burn_time - 9 + 1 = 12 more steps, the literal's time
    state = _steak_on_the_pan_for(9)
    compiled = compile(state, encoding="temporal", max_orders=1)
    walk = compiled.spots.distance(state.geo.flat(3, 1), state.geo.flat(3, 5))
    plan = _plan(compiled, (end - walk, "move", ("a0", "s_3_1", "s_3_5"), walk))
    rep = replay_temporal(compiled, plan, state)
    assert rep.ok, rep.mismatch
    assert rep.steps == end
    copy = state.copy()
    for _ in range(end):
        transition(copy, [S])
    assert copy.item_state[state.geo.item_names.index("steak0")] == expected


def test_take_off_inside_the_window_is_faithful_and_before_it_is_not_allowed() -> None:
    state = _steak_on_the_pan_for(9)
    compiled = compile(state, encoding="temporal", max_orders=1)
    args = ("a0", "steak0", "pan_3_0", "s_3_1")
    assert replay_temporal(compiled, _plan(compiled, (1, "take_off", args, 1)), state).ok
    early = replay_temporal(compiled, _plan(compiled, (Fraction(1, 2), "take_off", args, 1)),
                            state)
    assert not early.ok and early.category == "model" and "window" in early.mismatch


def test_replay_reports_a_simulator_that_disagrees_with_the_plan() -> None:
    state = new_state(make_rules("medium"), 0)
    compiled = compile(state, encoding="temporal")
    moved = state.copy()
    transition(moved, [L])  # the simulator's agent is no longer where the model says
    rep = replay_temporal(compiled, TimeTriggeredPlan([]), moved)
    assert not rep.ok and rep.category == "initial" and "a0" in rep.mismatch


def test_a_slower_simulator_is_an_effect_mismatch_at_the_end_of_the_chop() -> None:
    state = _steak_on_the_pan_for(9)
    compiled = compile(state, encoding="temporal", max_orders=1)
    # take the onion to the board and chop it (3 steps), in a simulator that needs 4
    d1 = compiled.numbers[("dist", ("s_3_1", "s_5_4"))]
    d2 = compiled.numbers[("dist", ("s_5_4", "s_3_5"))]
    t = d1
    timed = [(0, "move", ("a0", "s_3_1", "s_5_4"), d1),
             (t, "pick", ("a0", "onion0", "onion_6_4", "s_5_4"), 1),
             (t + 1, "move", ("a0", "s_5_4", "s_3_5"), d2),
             (t + 1 + d2, "put_board", ("a0", "onion0", "board_3_6", "s_3_5"), 1),
             (t + 2 + d2, "chop", ("a0", "onion0", "board_3_6", "s_3_5"), 3)]
    plan = _plan(compiled, *timed)
    assert replay_temporal(compiled, plan, state).ok
    slow = state.copy()
    slow.rules = with_overrides(slow.rules, chop_steps=4)
    rep = replay_temporal(compiled, plan, slow)
    assert not rep.ok and rep.category == "effect" and "onion0" in rep.mismatch


@pytest.fixture
def _private_cwd(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)


@pytest.mark.usefixtures("_private_cwd")
@pytest.mark.parametrize("preset, max_orders", [("easy", None), ("medium", 1)])
def test_kairos_plans_are_faithful_on_sampled_states(preset: str, max_orders: int | None) -> None:
    avail = availability("kairos")
    if not avail.ok:
        pytest.skip(f"kairos unavailable: {avail.reason}")
    for state in sample_states(preset, 3, seed=5):
        compiled = compile(state, encoding="temporal", max_orders=max_orders)
        result = solve(compiled.problem, "kairos", timeout=60, use_val=False)
        if result.status == "timeout":
            pytest.skip("kairos timed out on a loaded machine")
        assert result.status == "solved", result.reason
        rep = replay_temporal(compiled, result.plan, state)
        assert rep.ok, (state.t, rep.category, rep.mismatch)
        assert sorted(rep.served) == sorted(compiled.goal_orders)


@pytest.mark.usefixtures("_private_cwd")
def test_kairos_plans_with_anticipated_switches_hold_while_the_layout_switches() -> None:
    """One cook on MapC: the plan waits for the layouts its walks need; replayed with the
    layout switching live, it is faithful up to the episode's horizon."""
    avail = availability("kairos")
    if not avail.ok:
        pytest.skip(f"kairos unavailable: {avail.reason}")
    state = new_state(make_rules("hard", n_agents=1), 0)
    compiled = compile(state, encoding="temporal", max_orders=1, anticipate_switches=True)
    result = solve(compiled.problem, "kairos", timeout=90, use_val=False)
    if result.status == "timeout":
        pytest.skip("kairos timed out on a loaded machine")
    assert result.status == "solved", result.reason
    assert any(str(ai.actual_parameters[-1]) == "layout1" for _, ai, _ in
               result.plan.timed_actions if ai.action.name == "move")
    rep = replay_temporal(compiled, result.plan, state, until_horizon=True)
    assert rep.ok, (rep.category, rep.mismatch)
    if not rep.outlasted:
        assert sorted(rep.served) == sorted(compiled.goal_orders)
    # the same plan with the layout frozen at layout 0 breaks: the switches are real
    frozen = replay_temporal(compiled, result.plan, state, freeze_layout=True, until_horizon=True)
    assert not frozen.ok


@pytest.mark.usefixtures("_private_cwd")
def test_advance_replays_a_temporal_plan_to_the_state_it_leaves() -> None:
    """``advance`` (what chained planning starts the next order from) takes a Kairos plan:
    the copy has the order served at the plan's end, the original is untouched."""
    from ocplus_plan.planning.fidelity import advance

    avail = availability("kairos")
    if not avail.ok:
        pytest.skip(f"kairos unavailable: {avail.reason}")
    state = new_state(make_rules("medium", n_agents=1), 0)
    first = state.orders[0].order_id
    compiled = compile(state, encoding="temporal", max_orders=1)
    result = solve(compiled.problem, "kairos", timeout=60, use_val=False)
    if result.status == "timeout":
        pytest.skip("kairos timed out on a loaded machine")
    after = advance(compiled, result.plan, state)
    assert after is not None and after is not state
    assert first not in {o.order_id for o in after.orders}
    assert state.t == 0 and first in {o.order_id for o in state.orders}
    end = max(float(start) + float(dur or 0) for start, _, dur in result.plan.timed_actions)
    assert after.t == int(end)

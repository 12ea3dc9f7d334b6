"""The judge's realisation of a temporal plan with waits (``planning/fidelity_waits.py``):
hand-drawn one-lane kitchens where one cook must wait for the other to step aside, or
cannot pass at all; a cook envelope keeps the steak on the pan its planned ticks; a bump
the kitchen ignores fails its step; and Kairos' plan for ``suites/v1`` temporal p11."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from unified_planning.plans import ActionInstance, TimeTriggeredPlan

from ocplus_plan.planning import compile
from ocplus_plan.planning.fidelity_judge import judge
from ocplus_plan.planning.fidelity_temporal import replay_temporal
from ocplus_plan.planning.fidelity_waits import realise_timed
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, ItemState, Where

from .test_fidelity_temporal import _plan

R, D, L, U, S = (int(a) for a in Action)
EPS = Fraction(1, 1000)
ROOT = Path(__file__).resolve().parents[2]
P11 = ROOT / "suites/v1/temporal/p11"
#: Kairos' plan for p11 as the league kept it (the set's reference is now kairos-anytime's
#: offline plan, which needs no waits)
P11_KAIROS = ROOT / ("experiments/results/league/v1-full_all-planners_cpu30_code-7c4d842/"
                     "plans/kairos/temporal-p11.temporal.plan")


def _lane(niche: bool) -> dict:
    """A one-lane corridor (row 1) from the tomato, board and plate to the delivery at
    (1, 6); with ``niche``, the floor cell (2, 3) below it lets a cook step aside."""
    return {"name": "lane", "game_map": [
        [1, 3, 6, 5, 1, 1, 1],
        [1, 0, 0, 0, 0, 0, 7],
        [1, 1, 1, 0 if niche else 1, 1, 1, 1],
        [1, 1, 1, 1, 1, 1, 1]], "max_n_agent": 2, "agent_spawn_points": [[1, 1], [1, 4]]}


def _dish_in_hand(niche: bool):
    """Cook 0 at (1, 2) holds a plate with a chopped tomato (the one order's dish);
    cook 1 stands at (1, 4), on the only way to the delivery."""
    rules = make_rules("easy", map=_lane(niche), n_agents=2)
    state = new_state(rules, 0)
    for a in [U, R, U] + [U] * rules.chop_steps + [R, U, L, U]:
        transition(state, [a, S])
    assert [state.geo.rc(p) for p in state.agent_pos] == [(1, 2), (1, 4)]
    return state


def _deliver(niche: bool):
    state = _dish_in_hand(niche)
    compiled = compile(state, encoding="temporal", max_orders=1)
    plan = _plan(compiled, (0, "move", ("a0", "s_1_2", "s_1_5"), 3),
                 (3 + EPS, "deliver1", ("a0", "plate0", "c_tomato", "c_empty", "o0", "o_none",
                                        "delivery_1_6", "s_1_5", "plate_0_3", "tomato0",
                                        "tomato_0_1"), 1))
    return compiled, plan, state


def test_a_cook_in_the_way_steps_aside_and_the_other_waits():
    compiled, plan, state = _deliver(niche=True)
    strict = replay_temporal(compiled, plan, state)
    assert not strict.ok and strict.category == "blocked"  # the model walks through cook 1
    verdict = judge(compiled, plan, state)
    assert verdict.faithful, verdict.reason
    assert verdict.how == "timed with waits" and verdict.waits > 0
    assert verdict.served == [0] and verdict.steps > 4  # later than the planned 4 steps
    assert state.agent_rc(1) == (1, 4)  # the state given is not changed


def test_cooks_walking_head_on_in_one_lane_pass_by_the_niche():
    # both walk at time 0, towards each other; the plan's later step (cook 1's) gives way
    compiled, plan, state = _deliver(niche=True)
    timed = list(plan.timed_actions)
    walk = ActionInstance(compiled.problem.action("move"), tuple(
        compiled.problem.object(o) for o in ("a1", "s_1_4", "s_1_1")))
    plan = TimeTriggeredPlan([timed[0], (Fraction(0), walk, Fraction(3)), timed[1]])
    done = realise_timed(compiled, plan, state)
    assert done.ok and done.served == [0], done.reason
    assert done.final is not None and done.final.agent_rc(1) == (1, 1)
    assert done.waits > 0


def test_a_cook_that_cannot_be_passed_refuses_the_walk():
    compiled, plan, state = _deliver(niche=False)
    verdict = judge(compiled, plan, state)
    assert not verdict.faithful and verdict.failed_step == 0  # the move
    assert "stuck" in verdict.reason and verdict.served == []


def _holding_steak_by_the_pan():
    """Medium, seed 0: the cook stands on (3, 1) next to the pan (3, 0), holding the steak."""
    state = new_state(make_rules("medium"), 0)
    for a in (L, L, D):
        transition(state, [a])
    return state


def _cook(compiled, duration):
    return _plan(compiled,
                 (0, "cook", ("a0", "a0", "steak0", "pan_3_0", "s_3_1", "s_3_1"), duration),
                 (EPS, "pan_put_done", ("a0",), 1),
                 (duration + EPS, "pan_take_done", ("a0", "steak0", "pan_3_0"), 1))


def test_a_cook_envelope_keeps_the_steak_on_the_pan_its_planned_ticks():
    state = _holding_steak_by_the_pan()
    compiled = compile(state, encoding="temporal", max_orders=1)
    steak = compiled.names.items["steak0"]
    done = realise_timed(compiled, _cook(compiled, state.rules.cook_time), state)
    final = done.final
    assert final is not None and final.item_state[steak] == ItemState.COOKED
    assert final.item_where[steak] == Where.HAND and done.failed_step is None


def test_a_bump_the_kitchen_ignores_fails_its_step():
    # cook 0 holds the dish; bumping the empty board with it does nothing in the kitchen
    # (the model would refuse the step too: the realisation does not read the model)
    state = _dish_in_hand(niche=True)
    compiled = compile(state, encoding="temporal", max_orders=1)
    plan = _plan(compiled, (0, "put_board", ("a0", "tomato0", "board_0_2", "s_1_2"), 1))
    done = realise_timed(compiled, plan, state)
    assert not done.ok and done.failed_step == 0 and "did nothing" in done.reason


def test_kairos_plan_for_temporal_p11_is_realised_with_waits():
    """Two cooks: cook 0's walk from (4, 1) to (2, 1) runs through (3, 1), where cook 1
    waits at the pan; VAL accepts it, the timed replay is blocked, the kitchen serves it
    once cook 1 steps aside and goes back to take the steak off."""
    from ocplus_plan.eval.suite import load_instance
    from ocplus_plan.planning.plan_io import read_plan

    instance = load_instance(P11)
    compiled = instance.compiled("temporal")
    plan = read_plan(P11_KAIROS, compiled.problem)
    assert not replay_temporal(compiled, plan, instance.state).ok
    verdict = judge(compiled, plan, instance.state)
    assert verdict.faithful and verdict.how == "timed with waits", verdict.reason
    assert verdict.waits > 0 and verdict.served == list(compiled.goal_orders)

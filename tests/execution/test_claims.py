"""Items a partner keeps taking up are left out of our plans (:mod:`ocplus_plan.execution.claims`),
on a hand-drawn kitchen: our cook holds a plate of chopped tomato, which the younger open
order asks for; the older one wants chopped lettuce on it too, and the only lettuce is the
one the partner keeps picking up and putting down."""

from __future__ import annotations

import pytest

from ocplus_plan.execution.claims import (CLAIM_PICKUPS, CLAIM_RECENT, CLAIM_STEPS, PartnerClaims,
                                          withhold)
from ocplus_plan.execution.executive import Executive, PlanOutcome
from ocplus_plan.execution.partner import Prediction, plan_around
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import Item, ItemState, Where
from ocplus_plan.sim.records import Order

# board and lettuce crate on top, tomato crate left, window right, plate crate below;
# our cook 0 right, the partner 1 left
KITCHEN = {"name": "claims", "max_n_agent": 2,
           "game_map": [[1, 6, 1, 4, 1],
                        [3, 0, 0, 0, 7],
                        [1, 5, 1, 1, 1]],
           "agent_spawn_points": [[1, 3], [1, 1]]}
LETTUCE_AT = (2, 3)  # a plain counter below our cook


def _kitchen():
    """(state, lettuce, plate): cook 0 holds the plate with the chopped tomato on it; the
    chopped lettuce lies on the counter at LETTUCE_AT; the open orders are tomato +
    lettuce (oldest), then tomato."""
    state = new_state(make_rules("easy", map=KITCHEN, n_agents=2,
                                 recipes=["tomato", "tomato+lettuce"], horizon=60), 0)
    kind = state.geo.item_kind
    tomato, lettuce, plate = (next(i for i in range(state.n_items) if kind[i] == k)
                              for k in (Item.TOMATO, Item.LETTUCE, Item.PLATE))
    for item in (tomato, lettuce, plate):
        state.cell_item[state.item_loc[item]] = -1
    state.item_where[plate], state.item_loc[plate] = int(Where.HAND), 0
    state.agent_hand[0] = plate
    state.item_where[tomato], state.item_loc[tomato] = int(Where.PLATE), plate
    state.item_state[tomato] = state.item_state[lettuce] = int(ItemState.CHOPPED)
    counter = state.geo.flat(*LETTUCE_AT)
    state.item_where[lettuce], state.item_loc[lettuce] = int(Where.CELL), counter
    state.cell_item[counter] = lettuce
    state.orders = [Order(0, (Item.TOMATO, Item.LETTUCE), 0, -1), Order(1, (Item.TOMATO,), 0, -1)]
    return state, lettuce, plate


def _pickups(claims, state, lettuce, steps):
    """The partner takes the lettuce up in each of ``steps`` and puts it down in between."""
    for t in range(max(steps) + 2):
        state.t = t
        state.agent_hand[1] = lettuce if t in steps else -1
        claims.see(state, (0,))


def test_an_item_a_partner_takes_up_again_and_again_is_claimed():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, [2, 4, 6][:CLAIM_PICKUPS])
    assert claims.claimed(state.t) == {lettuce: 1}


def test_a_partner_predicted_by_its_own_policy_claims_nothing():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, [2, 4, 6][:CLAIM_PICKUPS])
    assert claims.claimed(state.t, {1: Prediction(1, None, by_policy=True)}) == {}
    assert claims.claimed(state.t, {1: Prediction(1, None)}) == {lettuce: 1}


def test_one_pickup_fewer_claims_nothing():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, [2, 4, 6, 8][:CLAIM_PICKUPS - 1])
    assert claims.claimed(state.t) == {}


def test_pickups_older_than_the_window_are_forgotten():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, [2, 4, 6][:CLAIM_PICKUPS])
    state.t += CLAIM_STEPS
    claims.see(state, (0,))
    assert claims.claimed(state.t) == {}


def test_a_partner_that_has_held_the_item_a_while_since_is_carrying_it_not_claiming_it():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, [2, 4, 6][:CLAIM_PICKUPS])
    last = state.t  # the partner takes it up once more now, and holds it on
    for t in range(last, last + CLAIM_RECENT + 2):
        state.t = t
        state.agent_hand[1] = lettuce
        claims.see(state, (0,))
        assert bool(claims.claimed(t)) is (t - last <= CLAIM_RECENT)


def test_holding_an_item_for_many_steps_is_one_pickup():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    _pickups(claims, state, lettuce, list(range(2, 12)))
    assert claims.claimed(state.t) == {}


def test_our_own_cooks_pickups_claim_nothing():
    state, lettuce, _plate = _kitchen()
    claims = PartnerClaims()
    for t in range(8):
        state.t = t
        state.agent_hand[0] = lettuce if t % 2 else -1
        claims.see(state, (0,))
    assert claims.claimed(state.t) == {}


def test_a_withheld_item_has_no_place_its_cell_is_free_and_its_orders_wait():
    state, lettuce, _plate = _kitchen()
    problem = withhold(state.copy(), {lettuce: 1})
    counter = state.geo.flat(*LETTUCE_AT)
    assert problem.item_where[lettuce] == int(Where.HAND) and problem.item_loc[lettuce] == 1
    assert problem.cell_item[counter] == -1 and problem.agent_hand[1] == -1
    assert [o.order_id for o in problem.orders] == [1, 0]  # the one we can make first
    assert state.cell_item[counter] == lettuce and [o.order_id for o in state.orders] == [0, 1]


def test_a_claimed_item_in_its_partners_hand_leaves_both_out():
    state, lettuce, _plate = _kitchen()
    state.cell_item[state.item_loc[lettuce]] = -1
    state.item_where[lettuce], state.item_loc[lettuce] = int(Where.HAND), 1
    state.agent_hand[1] = lettuce
    problem = withhold(state.copy(), {lettuce: 1})
    assert problem.agent_hand[1] == -1 and problem.item_where[lettuce] == int(Where.HAND)


def test_the_plan_asks_again_with_the_claimed_item_when_none_comes_without_it():
    state, lettuce, _plate = _kitchen()
    seen = []

    def planner(s, agents, reason):
        seen.append(s.item_where[lettuce])
        if s.item_where[lettuce] == int(Where.HAND):
            return PlanOutcome("unsolvable", [], 0.0, "no lettuce")
        return PlanOutcome("solved", [], 0.0)

    outcome = plan_around(planner, state, (0,), "taken", {1: Prediction(1, None)},
                          {lettuce: 1})
    assert outcome.ok and seen[-1] == int(Where.CELL) and int(Where.HAND) in seen


def test_the_executive_plans_without_an_item_its_partner_keeps_taking_up():
    state, lettuce, _plate = _kitchen()
    asked = []

    def planner(s, agents, reason):
        asked.append((s.t, s.item_where[lettuce]))
        return PlanOutcome("solved", [], 0.0)

    ex = Executive(planner)
    ex.reset(state, [0])
    ex.partner_model = lambda s: {1: Prediction(1, None)}
    counter = state.item_loc[lettuce]
    for t in range(2 * CLAIM_PICKUPS):  # up, down, up, down, ...
        state.t = t
        up = t % 2 == 0
        state.agent_hand[1] = lettuce if up else -1
        state.item_where[lettuce], state.item_loc[lettuce] = \
            (int(Where.HAND), 1) if up else (int(Where.CELL), counter)
        state.cell_item[counter] = -1 if up else lettuce
        ex.act(state)
    ex._replan(state, "taken")
    assert asked[0] == (0, int(Where.HAND))  # in the partner's hand: not claimed yet
    assert asked[-1] == (state.t, int(Where.HAND))  # lying on the counter, but claimed
    assert ex.info()["claimed_plans"] >= 1


def test_with_the_lettuce_claimed_our_cook_serves_the_plate_it_holds():
    from ocplus_plan.planning.engines import availability

    if not availability("fast-downward").ok:
        pytest.skip(availability("fast-downward").reason)
    from ocplus_plan.execution.planning_step import compile_and_solve
    from ocplus_plan.execution.spec import DEFAULT_PLANNER

    state, lettuce, plate = _kitchen()
    pipeline = compile_and_solve(DEFAULT_PLANNER)
    free = plan_around(pipeline, state, (0,), "taken", {1: Prediction(1, None)})
    assert free.ok and any(lettuce in s.items for s in free.steps)  # it plates the lettuce
    claimed = plan_around(pipeline, state, (0,), "taken", {1: Prediction(1, None)},
                          {lettuce: 1})
    assert claimed.ok and [s.kind for s in claimed.steps][:1] == ["deliver"]
    assert all(lettuce not in s.items for s in claimed.steps)
    assert plate in claimed.steps[0].items

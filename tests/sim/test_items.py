"""One behaviour per test: chopping, cooking and burning, plating, delivery, trash,
washing, respawn. Map G (3x7):

    row 0:  counter steak counter pan  counter tomato counter
    row 1:  plate   .     .       .    .       .      delivery
    row 2:  counter trash board   sink counter counter counter
"""

from __future__ import annotations

import pytest

from ocplus_plan.sim import Item, ItemState, Where
from ocplus_plan.sim.codes import Action

from .conftest import kitchen
from .helpers import give, item_of, kinds, on_plate, place, run, set_pos

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))
G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]


def g_kitchen(**kw):
    kw.setdefault("recipes", ["tomato+steak"])
    return kitchen(G, [[1, 1]], preset="medium", **kw)


def test_chopping_takes_exactly_chop_steps_interactions():
    rules, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    give(s, 0, tomato)
    set_pos(s, 0, (1, 2))
    ev, rw = run(s, D)  # put on the board below
    assert s.item_where[tomato] == Where.CELL and "putdown" in kinds(ev)
    for k in range(1, rules.chop_steps):
        ev, rw = run(s, D)
        assert s.item_state[tomato] == ItemState.FRESH and s.item_progress[tomato] == k
        assert kinds(ev) == ["chop"]
    ev, rw = run(s, D)
    assert s.item_state[tomato] == ItemState.CHOPPED and kinds(ev) == ["chop_done"]
    assert rw[-1][0] == pytest.approx(rules.rewards.subtask_finished + rules.rewards.step_penalty)
    run(s, D)  # a chopped vegetable on the board is picked up
    assert s.agent_hand[0] == tomato


def test_chop_steps_is_a_parameter():
    rules, s = g_kitchen(chop_steps=5)
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 2))
    set_pos(s, 0, (1, 2))
    run(s, *[D] * 4)
    assert s.item_state[tomato] == ItemState.FRESH
    run(s, D)
    assert s.item_state[tomato] == ItemState.CHOPPED


def test_only_fresh_vegetables_go_on_a_board():
    rules, s = g_kitchen()
    steak, tomato = item_of(s, Item.STEAK), item_of(s, Item.TOMATO)
    give(s, 0, steak)
    set_pos(s, 0, (1, 2))
    run(s, D)
    assert s.agent_hand[0] == steak
    s.item_state[tomato] = int(ItemState.CHOPPED)
    place(s, steak, (0, 2))
    give(s, 0, tomato)
    run(s, D)
    assert s.agent_hand[0] == tomato


def test_steak_cooks_by_itself_and_burns_exactly_after_burn_time_ticks():
    rules, s = g_kitchen()
    steak = item_of(s, Item.STEAK)
    ev, _ = run(s, U, R, R)  # pick the steak, walk under the pan
    assert s.agent_hand[0] == steak
    ev, _ = run(s, U)  # on the pan; the pan ticks in the same step
    assert s.item_progress[steak] == 1 and s.item_state[steak] == ItemState.RAW
    run(s, *[L] * (rules.cook_time - 2))  # walk away: it cooks with nobody present
    assert s.item_state[steak] == ItemState.RAW
    ev, rw = run(s, S)
    assert s.item_progress[steak] == rules.cook_time and s.item_state[steak] == ItemState.COOKED
    assert "cook_done" in kinds(ev)
    run(s, *[S] * (rules.burn_time - rules.cook_time))
    assert s.item_progress[steak] == rules.burn_time and s.item_state[steak] == ItemState.COOKED
    assert s.stats["burns"] == 0
    ev, rw = run(s, S)
    assert s.item_state[steak] == ItemState.BURNT and kinds(ev) == ["burnt"]
    assert s.stats["burns"] == 1
    assert rw[-1][0] == pytest.approx(rules.rewards.burned_penalty + rules.rewards.step_penalty)
    run(s, *[S] * 5)
    assert s.stats["burns"] == 1  # burns once


def test_a_steak_taken_off_the_pan_keeps_its_state_and_stops_ticking():
    rules, s = g_kitchen()
    steak = item_of(s, Item.STEAK)
    place(s, steak, (0, 3))
    s.item_progress[steak] = rules.cook_time - 1
    set_pos(s, 0, (1, 3))
    run(s, S)
    assert s.item_state[steak] == ItemState.COOKED
    run(s, U)  # picked up before the pan ticks
    assert s.agent_hand[0] == steak and s.item_progress[steak] == rules.cook_time
    run(s, *[S] * 30)
    assert s.item_state[steak] == ItemState.COOKED


def burnt_steak_in_hand(**kw):
    rules, s = g_kitchen(**kw)
    steak = item_of(s, Item.STEAK)
    place(s, steak, (0, 3))
    s.item_state[steak] = int(ItemState.COOKED)
    s.item_progress[steak] = rules.burn_time
    set_pos(s, 0, (1, 3))
    run(s, S)
    assert s.item_state[steak] == ItemState.BURNT
    run(s, U)
    assert s.agent_hand[0] == steak
    return rules, s, steak


def test_burnt_steak_is_refused_by_a_plate():
    rules, s, steak = burnt_steak_in_hand()
    plate = item_of(s, Item.PLATE)
    set_pos(s, 0, (1, 1))
    run(s, L)  # bump the plate on its counter
    assert s.agent_hand[0] == steak and s.plate_contents(plate) == []


def test_a_held_plate_does_not_take_burnt_steak_from_the_pan():
    rules, s, steak = burnt_steak_in_hand()
    plate = item_of(s, Item.PLATE)
    place(s, steak, (0, 3))
    give(s, 0, plate)
    run(s, U)
    assert s.plate_contents(plate) == [] and s.cell_item[s.geo.flat(0, 3)] == steak


def test_burnt_steak_is_refused_at_delivery_bare_or_on_a_plate():
    rules, s, steak = burnt_steak_in_hand(recipes=["steak"])
    set_pos(s, 0, (1, 5))
    ev, rw = run(s, R)
    assert kinds(ev) == ["wrong_delivery"] and s.agent_hand[0] == steak
    assert rw[-1][0] == pytest.approx(rules.rewards.wrong_delivery + rules.rewards.step_penalty)
    plate = item_of(s, Item.PLATE)
    on_plate(s, steak, plate)  # smuggled onto the plate: still refused
    give(s, 0, plate)
    ev, _ = run(s, R)
    assert kinds(ev) == ["wrong_delivery"] and s.agent_hand[0] == plate
    assert s.stats["dishes_served"] == 0 and s.stats["wrong_deliveries"] == 2


def test_plating_works_in_both_directions():
    rules, s = g_kitchen()
    tomato, steak, plate = item_of(s, Item.TOMATO), item_of(s, Item.STEAK), item_of(s, Item.PLATE)
    s.item_state[tomato] = int(ItemState.CHOPPED)
    give(s, 0, tomato)
    ev, _ = run(s, L)  # held ingredient onto the plate lying on its counter
    assert s.plate_contents(plate) == [tomato] and s.agent_hand[0] == -1
    s.item_state[steak] = int(ItemState.COOKED)
    s.item_progress[steak] = rules.cook_time
    place(s, steak, (0, 3))
    run(s, L)  # pick up the plate (with its tomato)
    assert s.agent_hand[0] == plate
    run(s, R, R, U)  # held plate takes the cooked steak from the pan
    assert sorted(s.plate_contents(plate)) == sorted([tomato, steak])


def test_raw_ingredients_and_dirty_plates_take_nothing():
    rules, s = g_kitchen()
    tomato, plate = item_of(s, Item.TOMATO), item_of(s, Item.PLATE)
    give(s, 0, tomato)
    run(s, L)
    assert s.plate_contents(plate) == [] and s.agent_hand[0] == tomato
    s.item_state[tomato] = int(ItemState.CHOPPED)
    s.item_state[plate] = int(ItemState.DIRTY)
    run(s, L)
    assert s.plate_contents(plate) == [] and s.agent_hand[0] == tomato


def served_plate(s, recipe_items):
    plate = item_of(s, Item.PLATE)
    for i in recipe_items:
        kind = Item(s.geo.item_kind[i])
        s.item_state[i] = int(ItemState.COOKED if kind == Item.STEAK else ItemState.CHOPPED)
        on_plate(s, i, plate)
    give(s, 0, plate)
    set_pos(s, 0, (1, 5))
    return plate


def test_a_correct_delivery_completes_the_order_and_respawns_everything():
    rules, s = g_kitchen()
    tomato, steak = item_of(s, Item.TOMATO), item_of(s, Item.STEAK)
    first = s.orders[0]
    plate = served_plate(s, [tomato, steak])
    ev, rw = run(s, R)
    assert "delivery" in kinds(ev) and s.stats["dishes_served"] == 1
    assert rw[-1][0] == pytest.approx(rules.rewards.correct_delivery + rules.rewards.step_penalty)
    assert first not in s.orders and len(s.orders) == rules.n_orders  # replaced at once
    for item, home in ((tomato, (0, 5)), (steak, (0, 1)), (plate, (1, 0))):
        assert s.cell_item[s.geo.flat(*home)] == item
    assert s.item_state[tomato] == ItemState.FRESH and s.item_state[plate] == ItemState.CLEAN
    assert s.agent_hand[0] == -1


def test_the_oldest_matching_order_is_completed_first():
    rules, s = g_kitchen(recipes=["tomato", "steak"], n_orders=3, seed=3)
    tomato = item_of(s, Item.TOMATO)
    from ocplus_plan.sim.state import Order

    s.orders = [Order(10, (Item.STEAK,), 0, -1), Order(11, (Item.TOMATO,), 0, -1),
                Order(12, (Item.TOMATO,), 0, -1)]
    served_plate(s, [tomato])
    ev, _ = run(s, R)
    assert [o.order_id for o in s.orders][:2] == [10, 12]


def test_a_wrong_set_or_an_empty_plate_is_refused_and_nothing_is_consumed():
    rules, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    plate = served_plate(s, [tomato])  # tomato alone; the order wants tomato+steak
    orders = list(s.orders)
    ev, _ = run(s, R)
    assert kinds(ev) == ["wrong_delivery"] and s.agent_hand[0] == plate
    assert s.plate_contents(plate) == [tomato] and s.orders == orders


def test_dirty_plate_cycle_deliver_wash_reuse():
    rules, s = g_kitchen(dirty_plates=True)
    tomato, steak = item_of(s, Item.TOMATO), item_of(s, Item.STEAK)
    plate = served_plate(s, [tomato, steak])
    run(s, R)
    assert s.cell_item[s.geo.flat(1, 0)] == plate and s.item_state[plate] == ItemState.DIRTY
    set_pos(s, 0, (1, 1))
    run(s, L)  # pick up the dirty plate
    assert s.agent_hand[0] == plate
    s.item_state[tomato] = int(ItemState.CHOPPED)
    place(s, tomato, (0, 0))
    run(s, U)  # a dirty plate takes nothing
    assert s.plate_contents(plate) == []
    run(s, R, R, D)  # into the sink
    assert s.cell_item[s.geo.flat(2, 3)] == plate
    for k in range(1, rules.wash_steps):
        ev, _ = run(s, D)
        assert kinds(ev) == ["wash"] and s.item_state[plate] == ItemState.DIRTY
    ev, rw = run(s, D)
    assert kinds(ev) == ["wash_done"] and s.item_state[plate] == ItemState.CLEAN
    assert rw[-1][0] == pytest.approx(rules.rewards.subtask_finished + rules.rewards.step_penalty)
    run(s, D)
    assert s.agent_hand[0] == plate


def test_trash_sends_an_ingredient_back_fresh_to_its_spawn_tile():
    rules, s, steak = burnt_steak_in_hand()
    set_pos(s, 0, (1, 1))
    ev, _ = run(s, D)
    assert kinds(ev) == ["trash", "respawn"] and s.agent_hand[0] == -1
    assert s.cell_item[s.geo.flat(0, 1)] == steak
    assert s.item_state[steak] == ItemState.RAW and s.item_progress[steak] == 0


def test_trash_empties_a_held_plate_which_stays_in_the_hand():
    rules, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    plate = served_plate(s, [tomato])
    set_pos(s, 0, (1, 1))
    run(s, D)
    assert s.agent_hand[0] == plate and s.plate_contents(plate) == []
    assert s.cell_item[s.geo.flat(0, 5)] == tomato and s.item_state[tomato] == ItemState.FRESH


def test_a_blocked_respawn_waits_until_its_tile_is_free():
    rules, s = g_kitchen()
    tomato, steak = item_of(s, Item.TOMATO), item_of(s, Item.STEAK)
    give(s, 0, tomato)
    place(s, steak, (0, 5))  # something else lies on the tomato's spawn tile
    ev, _ = run(s, D)  # trash the tomato
    assert "respawn_waiting" in kinds(ev) and s.item_where[tomato] == Where.WAITING
    run(s, R, R, R)
    assert s.item_where[tomato] == Where.WAITING  # still occupied
    ev, _ = run(s, R, U)  # take the steak off the tile: the tomato appears in that step
    assert s.agent_hand[0] == steak and "respawn" in kinds(ev)
    assert s.cell_item[s.geo.flat(0, 5)] == tomato and s.item_state[tomato] == ItemState.FRESH


def test_only_empty_counters_take_a_put_down_and_pans_only_steak():
    rules, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    give(s, 0, tomato)
    set_pos(s, 0, (1, 3))
    run(s, U)  # a pan takes only steak
    assert s.agent_hand[0] == tomato
    run(s, R, U)  # an empty counter takes anything
    assert s.cell_item[s.geo.flat(0, 4)] == tomato

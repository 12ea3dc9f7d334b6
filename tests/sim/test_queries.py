"""sim.queries: one test per query, and the bump query against the step on sampled states."""

from __future__ import annotations

from collections import Counter

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import Item, ItemState, make_rules
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.queries import (
    Bump,
    bump_effect,
    bumps_needed,
    direction,
    distances,
    grid_neighbors,
    interaction_spots,
    is_plateable,
    plate_fits,
    stations_cut_off,
    ticks_until_burnt,
    ticks_until_cooked,
    walk_actions,
    walkable_in_any_layout,
    walks,
)
from ocplus_plan.sim.state import geometry_for

from .conftest import kitchen
from .helpers import give, item_of, kinds, on_plate, place, run, sampled_states, set_pos

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))
#: Map G of test_items (3x7): steak, pan, tomato on top; plate, window at the ends of the
#: floor row; trash, board, sink below
G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]
#: a corridor whose middle cell (1, 3) is a block in the main layout and floor after a switch
WALL = [[1, 3, 1, 6, 1, 5, 1], [7, 0, 0, -1, 0, 0, 1], [1, 1, 1, 1, 1, 1, 1]]
OPEN = [[1, 3, 1, 6, 1, 5, 1], [7, 0, 0, 0, 0, 0, 1], [1, 1, 1, 1, 1, 1, 1]]
#: bump effect -> the event kinds the step reports for it (NOTHING: none of them)
EVENTS = {
    Bump.PICK_UP: {"pickup"}, Bump.PUT_DOWN: {"putdown"},
    Bump.ONTO_PLATE: {"plate_add"}, Bump.TAKE_ONTO_PLATE: {"plate_add"},
    Bump.CHOP: {"chop", "chop_done"}, Bump.WASH: {"wash", "wash_done"},
    Bump.DELIVER: {"delivery", "wrong_delivery"}, Bump.TRASH: {"trash"},
}
ACTS = {"pickup", "putdown", "plate_add", "chop", "chop_done", "wash", "wash_done", "delivery",
        "wrong_delivery", "trash"}


def g_kitchen(**kw):
    kw.setdefault("recipes", ["tomato+steak"])
    return kitchen(G, [[1, 1]], preset="medium", **kw)


def test_grid_neighbors_are_in_action_order():
    nbrs = grid_neighbors(2, 3)
    assert nbrs[0] == (1, 3, -1, -1)  # right, down, left (off), up (off)
    assert nbrs[4] == (5, -1, 3, 1)
    assert geometry_for(make_rules("easy")).neighbors == grid_neighbors(*make_rules("easy").layout.shape)


def test_walks_distances_first_actions_and_order():
    _, s = kitchen(OPEN, [[1, 1]])
    geo, walk = s.geo, s.geo.walkables[0]
    start = geo.flat(1, 1)
    found = walks(geo.neighbors, walk, [start])
    assert found.dist[geo.flat(1, 5)] == 4 and found.dist[geo.flat(0, 0)] == -1
    assert found.first[geo.flat(1, 5)] == R and found.first[start] == -1
    assert found.order[0] == start and found.parent[geo.flat(1, 2)] == start
    assert distances(geo.neighbors, walk, [start], blocked=[geo.flat(1, 3)])[geo.flat(1, 4)] == -1
    # several sources: the nearest counts; a source needs not be walkable
    board = geo.flat(0, 3)
    assert distances(geo.neighbors, walk, [board])[geo.flat(1, 1)] == 3
    assert distances(geo.neighbors, walk, [start, geo.flat(1, 5)])[geo.flat(1, 4)] == 1
    with pytest.raises(ConfigError, match="outside"):
        walks(geo.neighbors, walk, [999])


def test_walk_actions_lead_the_simulator_to_the_goal():
    _, s = kitchen(OPEN, [[1, 1]])
    geo, walk = s.geo, s.geo.walkables[0]
    goal = geo.flat(1, 5)
    actions = walk_actions(geo.neighbors, walk, s.agent_pos[0], goal)
    assert actions == [R, R, R, R]
    run(s, *actions)
    assert s.agent_pos[0] == goal
    assert walk_actions(geo.neighbors, walk, goal, goal) == []
    assert walk_actions(geo.neighbors, walk, goal, geo.flat(1, 1), blocked=[geo.flat(1, 3)]) is None


def test_interaction_spots_are_the_walkable_neighbours():
    _, s = kitchen(OPEN, [[1, 1]])
    geo = s.geo
    assert interaction_spots(geo.neighbors, geo.walkables[0], geo.flat(0, 3)) == [geo.flat(1, 3)]
    assert interaction_spots(geo.neighbors, geo.walkables[0], geo.flat(2, 0)) == []


def test_walkable_in_any_layout_joins_the_layouts():
    _, s = kitchen(WALL, [[1, 1]], switch=OPEN)
    geo = s.geo
    middle = geo.flat(1, 3)
    assert not geo.walkables[0][middle] and geo.walkables[1][middle]
    anywhere = walkable_in_any_layout(geo)
    assert anywhere[middle] and anywhere[geo.flat(1, 1)] and not anywhere[geo.flat(0, 3)]
    assert walkable_in_any_layout(geo) is anywhere  # cached per geometry


def test_direction_moves_into_the_neighbour():
    _, s = kitchen(OPEN, [[1, 2]])
    geo, here = s.geo, s.agent_pos[0]
    for action, rc in ((R, (1, 3)), (L, (1, 1)), (U, (0, 2)), (D, (2, 2))):
        assert direction(geo, here, geo.flat(*rc)) == action
    assert direction(geo, here, here) == S
    run(s, direction(geo, here, geo.flat(1, 3)))
    assert s.agent_pos[0] == geo.flat(1, 3)
    with pytest.raises(ConfigError, match="not adjacent"):
        direction(geo, here, geo.flat(1, 5))


def test_bump_effect_names_each_interaction():
    _, s = g_kitchen()
    geo = s.geo
    tomato, steak, plate = (item_of(s, k) for k in (Item.TOMATO, Item.STEAK, Item.PLATE))
    board, pan, sink, trash, window = (geo.flat(*rc) for rc in ((2, 2), (0, 3), (2, 3), (2, 1), (1, 6)))
    assert bump_effect(s, -1, geo.flat(0, 5)) == Bump.PICK_UP  # the tomato on its spawn tile
    assert bump_effect(s, -1, board) == Bump.NOTHING
    give(s, 0, tomato)
    assert bump_effect(s, tomato, board) == Bump.PUT_DOWN
    assert bump_effect(s, tomato, pan) == Bump.NOTHING  # a vegetable never goes on the pan
    assert bump_effect(s, tomato, trash) == Bump.TRASH
    assert bump_effect(s, tomato, window) == Bump.DELIVER  # refused, but a delivery attempt
    place(s, tomato, (2, 2))
    assert bump_effect(s, -1, board) == Bump.CHOP
    s.item_state[tomato] = int(ItemState.CHOPPED)
    assert bump_effect(s, -1, board) == Bump.PICK_UP
    give(s, 0, plate)
    assert bump_effect(s, plate, board) == Bump.TAKE_ONTO_PLATE
    assert bump_effect(s, plate, trash) == Bump.NOTHING  # an empty plate: nothing to throw
    on_plate(s, tomato, plate)
    assert bump_effect(s, plate, trash) == Bump.TRASH
    place(s, plate, (1, 0))
    give(s, 0, steak)
    assert bump_effect(s, steak, pan) == Bump.PUT_DOWN
    s.item_state[steak] = int(ItemState.COOKED)
    assert bump_effect(s, steak, geo.flat(1, 0)) == Bump.ONTO_PLATE
    s.item_state[plate] = int(ItemState.DIRTY)
    assert bump_effect(s, steak, geo.flat(1, 0)) == Bump.NOTHING  # a dirty plate takes nothing
    place(s, steak, (0, 3))
    give(s, 0, plate)
    assert bump_effect(s, plate, sink) == Bump.PUT_DOWN
    place(s, plate, (2, 3))
    assert bump_effect(s, -1, sink) == Bump.WASH


def test_bump_effect_agrees_with_the_step_on_sampled_states():
    """For every agent and every cell it could bump: what the query predicts is what the
    step does when that agent bumps it alone (the others stay)."""
    seen: Counter[Bump] = Counter()
    for preset in ("easy", "medium", "hard"):
        for state in sampled_states(preset, 2, 40, seed=11, max_steps=199):
            geo = state.geo
            walk = geo.walkables[state.layout_index]
            for a in range(state.n_agents):
                held = state.agent_hand[a]
                for cell in range(len(walk)):
                    if walk[cell]:
                        continue
                    spots = [p for p in interaction_spots(geo.neighbors, walk, cell)
                             if p not in state.agent_pos or p == state.agent_pos[a]]
                    if not spots:
                        continue
                    effect = bump_effect(state, held, cell)
                    seen[effect] += 1
                    copy = state.copy()
                    copy.agent_pos[a] = spots[0]
                    joint = [S] * copy.n_agents
                    joint[a] = direction(geo, spots[0], cell)
                    ev, _ = run(copy, joint)
                    done = {e.kind for e in ev if e.agent == a} & ACTS
                    expected = EVENTS.get(effect, set())
                    assert bool(done) == bool(expected) and done <= expected, \
                        (preset, state.t, a, geo.rc(cell), effect, done)
    # the samples reach every kind of bump (WORK belongs to bump-driven processes beyond the
    # shipped ones: tests/sim/test_processes.py)
    assert all(seen[b] for b in Bump if b != Bump.WORK), seen


def test_bumps_needed_is_what_the_step_counts():
    rules, s = g_kitchen(chop_steps=4, wash_steps=2)
    assert bumps_needed(rules, Bump.CHOP) == 4 and bumps_needed(rules, Bump.WASH) == 2
    assert bumps_needed(rules, Bump.PICK_UP) == 1
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 2))
    set_pos(s, 0, (1, 2))
    ev, _ = run(s, *[D] * bumps_needed(rules, Bump.CHOP))
    assert kinds(ev)[-1] == "chop_done" and s.item_state[tomato] == ItemState.CHOPPED


def test_ticks_until_cooked_and_burnt_are_what_the_pan_does():
    rules, s = g_kitchen(cook_time=4, burn_time=7)
    steak = item_of(s, Item.STEAK)
    place(s, steak, (0, 3))
    set_pos(s, 0, (1, 1))
    assert ticks_until_cooked(rules, 0) == 4 and ticks_until_burnt(rules, 0) == 8
    run(s, *[S] * (ticks_until_cooked(rules, 0) - 1))
    assert s.item_state[steak] == ItemState.FRESH
    assert ticks_until_cooked(rules, s.item_progress[steak]) == 1
    run(s, S)
    assert s.item_state[steak] == ItemState.COOKED and ticks_until_cooked(rules, 4) == 0
    left = ticks_until_burnt(rules, s.item_progress[steak])
    run(s, *[S] * (left - 1))
    assert s.item_state[steak] == ItemState.COOKED
    ev, _ = run(s, S)
    assert s.item_state[steak] == ItemState.BURNT and "burnt" in kinds(ev)
    assert ticks_until_burnt(rules, s.item_progress[steak]) == 0


def test_is_plateable_only_for_processed_ingredients():
    _, s = g_kitchen()
    tomato, steak, plate = (item_of(s, k) for k in (Item.TOMATO, Item.STEAK, Item.PLATE))
    assert not is_plateable(s, tomato) and not is_plateable(s, steak) and not is_plateable(s, plate)
    s.item_state[tomato] = int(ItemState.CHOPPED)
    s.item_state[steak] = int(ItemState.COOKED)
    assert is_plateable(s, tomato) and is_plateable(s, steak)
    s.item_state[steak] = int(ItemState.BURNT)
    assert not is_plateable(s, steak)


def test_plate_fits_is_multiset_inclusion():
    tomato, steak = int(Item.TOMATO), int(Item.STEAK)
    recipe = Counter([tomato, tomato, steak])
    assert plate_fits(Counter(), recipe)
    assert plate_fits(Counter([tomato, tomato]), recipe)
    assert plate_fits(Counter([tomato, tomato, steak]), recipe)
    assert not plate_fits(Counter([tomato, tomato, tomato]), recipe)
    assert not plate_fits(Counter([int(Item.ONION)]), recipe)


def test_a_cook_standing_in_front_of_a_station_cuts_it_off() -> None:
    # lettuce (row 0) is bumped only from the floor cell below it, where cook 1 stands
    grid = [[1, 4, 1, 1, 1],
            [5, 0, 0, 0, 7],
            [1, 6, 1, 3, 1]]
    rules, state = kitchen(grid, [[1, 3], [1, 1]])
    geo = state.geo
    cut = stations_cut_off(geo, 0, geo.flat(1, 1), [geo.flat(1, 3)])
    assert sorted(geo.rc(c) for c in cut) == [(0, 1), (1, 0), (2, 1)]  # lettuce, plate, board


def test_a_cook_in_a_one_lane_way_cuts_off_what_lies_beyond() -> None:
    grid = [[1, 4, 1, 1, 1, 1],
            [5, 0, 0, 0, 0, 7],
            [1, 6, 1, 0, 0, 1],
            [1, 1, 1, 3, 1, 1]]
    rules, state = kitchen(grid, [[1, 4], [1, 2]])
    geo = state.geo
    cut = stations_cut_off(geo, 0, geo.flat(1, 2), [geo.flat(1, 4)])
    assert sorted(geo.rc(c) for c in cut) == [(0, 1), (1, 0), (2, 1)]  # lettuce, plate, board
    # in the two-cell-wide part a cook standing still is walked around
    assert stations_cut_off(geo, 0, geo.flat(2, 4), [geo.flat(1, 1)]) == []

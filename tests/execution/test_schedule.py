"""Scheduling a sequential plan over the cooks (execution/schedule.py).

Hand-built plans on easy_open (5x7: tomato (0,2), lettuce (0,4), onion (4,4), plate (2,0),
boards (1,6) and (3,6), window (4,2)); then real Fast Downward plans on sampled states,
checked for the properties the executive relies on.
"""

from __future__ import annotations

import random
import warnings
from dataclasses import replace

import pytest

from ocplus_plan.execution.plans import PlanStep
from ocplus_plan.sim.codes import ItemState
from ocplus_plan.execution.schedule import (
    KEEP,
    RELEASE,
    TAKE,
    dish_orders,
    plate_carries,
    plate_stays_home,
    plate_trips,
    schedule,
    segments,
    station_stays,
)
from ocplus_plan.sim import make_rules, new_state, transition

warnings.simplefilter("ignore", UserWarning)


def _state(n_agents: int = 2):
    return new_state(make_rules("easy", n_agents=n_agents), 0)


def _cell(state, r: int, c: int) -> int:
    return state.geo.flat(r, c)


def _item_at(state, r: int, c: int) -> int:
    return state.cell_item[_cell(state, r, c)]


def _chop_job(state, agent: int, spawn: tuple[int, int], board: tuple[int, int], first: int):
    """Fetch a vegetable to a board and chop it: two segments (carry, chop)."""
    veg = _item_at(state, *spawn)
    return [
        (PlanStep(first, agent, "pickup", _cell(state, *spawn), (veg,)), TAKE, 1),
        (PlanStep(first + 1, agent, "putdown", _cell(state, *board), (veg,)), RELEASE, 1),
        (PlanStep(first + 2, agent, "chop", _cell(state, *board), (veg,)), KEEP,
         state.rules.chop_steps),
    ]


def _steak_then_chop(state):
    """medium_kitchen, one cook: the steak (2,0) onto the pan (3,0), off it to the counter
    (1,0), then the tomato (0,2) fetched and chopped on board (1,6). (plan, pan cell)"""
    steak = _item_at(state, 2, 0)
    pan, counter = _cell(state, 3, 0), _cell(state, 1, 0)
    return [
        (PlanStep(0, 0, "pickup", _cell(state, 2, 0), (steak,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", pan, (steak,)), RELEASE, 1),
        (PlanStep(2, 0, "pickup", pan, (steak,)), TAKE, 1),
        (PlanStep(3, 0, "putdown", counter, (steak,)), RELEASE, 1),
        *_chop_job(state, 0, (0, 2), (1, 6), 4),
    ], pan


def test_independent_jobs_of_one_cook_are_shared_between_two():
    state = _state(2)
    plan = _chop_job(state, 0, (0, 2), (1, 6), 0) + _chop_job(state, 0, (0, 4), (3, 6), 3)
    out = schedule(plan, state, (0, 1))
    assert sorted((s.kind, s.target) for s in out) == sorted((s.kind, s.target) for s, _, _ in plan)
    cooks = {s.agent for s in out}
    assert cooks == {0, 1}, "the second job goes to the idle cook"
    # each job stays with one cook: the put and the chop follow the pick on the same board
    for board in ((1, 6), (3, 6)):
        assert len({s.agent for s in out if s.target == _cell(state, *board)}) == 1


def test_one_cook_chops_while_its_steak_cooks():
    """medium_kitchen: steak (2,0), pan (3,0), tomato (0,2), board (1,6), counter (1,0).
    The plan cooks first and chops after; with a 20-step cook the schedule fills the wait
    with the chopping (it is back at the pan when the steak is done)."""
    state = new_state(make_rules("medium", n_agents=1, cook_time=20, burn_time=30), 0)
    plan, pan = _steak_then_chop(state)
    out = schedule(plan, state, (0,))
    kinds = [(s.kind, s.target) for s in out]
    assert {s.agent for s in out} == {0}
    assert kinds.index(("chop", _cell(state, 1, 6))) < kinds.index(("pickup", pan)), kinds
    assert kinds.index(("putdown", pan)) < kinds.index(("pickup", pan))
    # with the default 10-step cook the chop would delay the steak: the plan's order stays
    state = new_state(make_rules("medium", n_agents=1), 0)
    assert [(s.kind, s.target) for s in schedule(plan, state, (0,))] == \
        [(s.kind, s.target) for s, _, _ in plan]


def test_a_cook_holding_an_item_does_its_own_segment_first():
    state = _state(2)
    tomato = _item_at(state, 0, 2)
    state.agent_hand[0] = tomato  # only the hands matter to the scheduler
    plan = [
        (PlanStep(0, 0, "putdown", _cell(state, 3, 6), (tomato,)), RELEASE, 1),
        (PlanStep(1, 0, "chop", _cell(state, 3, 6), (tomato,)), KEEP, 3),
    ]
    segs = segments(plan, state)
    assert segs[0].pinned == 0 and segs[1].pinned is None and segs[1].deps == {0}
    out = schedule(plan, state, (0, 1))
    assert out[0].agent == 0 and out[0].kind == "putdown"


def test_lookahead_chops_while_the_steak_cooks_when_that_ends_sooner():
    """One cook, a 14-step cook: fetching and chopping the tomato does not fit in the wait
    (the plain rule waits at the pan and chops last), but doing it first and taking the
    steak a little later (long before it burns) ends the plan sooner: the lookahead does."""
    state = new_state(make_rules("medium", n_agents=1, cook_time=14, burn_time=29), 0)
    plan, pan = _steak_then_chop(state)
    plain = schedule(plan, state, (0,), lookahead=0)
    ahead = schedule(plan, state, (0,))
    def kinds(out):
        return [(s.kind, s.target) for s in out]
    chop, take = ("chop", _cell(state, 1, 6)), ("pickup", pan)
    assert kinds(plain).index(chop) > kinds(plain).index(take)
    assert kinds(ahead).index(chop) < kinds(ahead).index(take)
    assert max(s.start for s in ahead) < max(s.start for s in plain)
    # the steak is still taken before it burns (29 ticks after it went on the pan)
    put = next(s.start for s in ahead if s.kind == "putdown" and s.target == pan)
    assert next(s.start for s in ahead if (s.kind, s.target) == take) < put + 29


def test_lookahead_never_lets_a_steak_burn_for_a_shorter_plan():
    """With the steak burning right after it is cooked, nothing is done in between."""
    state = new_state(make_rules("medium", n_agents=1, cook_time=14, burn_time=15), 0)
    plan, pan = _steak_then_chop(state)
    out = [(s.kind, s.target) for s in schedule(plan, state, (0,))]
    assert out.index(("pickup", pan)) < out.index(("chop", _cell(state, 1, 6)))


def test_station_stays_follow_an_item_from_put_to_take():
    state = _state(2)
    plan = _chop_job(state, 0, (0, 2), (1, 6), 0) + _chop_job(state, 0, (0, 4), (1, 6), 3)
    tomato, lettuce = plan[0][0].items[0], plan[3][0].items[0]
    plan.insert(3, (PlanStep(9, 0, "pickup", _cell(state, 1, 6), (tomato,)), TAKE, 1))
    plan.insert(4, (PlanStep(10, 0, "putdown", _cell(state, 2, 1), (tomato,)), RELEASE, 1))
    stays = station_stays(plan, state)
    assert [(s.station, s.steps, s.first, s.last) for s in stays] == [
        (_cell(state, 1, 6), [1, 2, 3], 1, 3),
        (_cell(state, 1, 6), [6, 7], 6, len(plan)),  # the lettuce stays on the board
    ]
    assert lettuce not in plan[3][0].items


def test_two_vegetables_planned_on_one_board_are_chopped_on_two():
    """The planner put both vegetables on board (1,6), one after the other; two cooks
    chop them at the same time when one of them moves to the free board (3,6) (8 chops
    each, so waiting for the board costs more than the longer walk to the other)."""
    state = new_state(make_rules("easy", n_agents=2, chop_steps=8), 0)
    plan = _chop_job(state, 0, (0, 2), (1, 6), 0)
    tomato = plan[0][0].items[0]
    plan += [
        (PlanStep(3, 0, "pickup", _cell(state, 1, 6), (tomato,)), TAKE, 1),
        (PlanStep(4, 0, "putdown", _cell(state, 2, 6), (tomato,)), RELEASE, 1),
        *_chop_job(state, 0, (0, 4), (1, 6), 5),
    ]
    fixed = schedule(plan, state, (0, 1), swap_stations=False)
    moved = schedule(plan, state, (0, 1))
    boards = {s.target for s in moved if s.kind == "chop"}
    assert boards == {_cell(state, 1, 6), _cell(state, 3, 6)}
    def end(out):
        return max(s.start + (state.rules.chop_steps if s.kind == "chop" else 1) for s in out)
    assert end(moved) < end(fixed)
    # a stay moves whole: each vegetable is put, chopped and taken on one board
    for veg in (tomato, plan[5][0].items[0]):
        assert len({s.target for s in moved if veg in s.items and s.target in boards}) == 1


def test_resource_order_is_kept():
    """A step that touches a board after another step touched it stays after it."""
    state = _state(2)
    plan = _chop_job(state, 0, (0, 2), (1, 6), 0)
    tomato = plan[0][0].items[0]
    plate = _item_at(state, 2, 0)
    plan += [
        (PlanStep(3, 1, "pickup", _cell(state, 2, 0), (plate,)), TAKE, 1),
        (PlanStep(4, 1, "plate", _cell(state, 1, 6), (tomato, plate)), KEEP, 1),
        (PlanStep(5, 1, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1),
    ]
    out = schedule(plan, state, (0, 1), swap_stations=False)
    board = [s.kind for s in out if s.target == _cell(state, 1, 6)]
    assert board == ["putdown", "chop", "plate"]
    assert [s.index for s in out] == list(range(len(out)))
    starts = [s.start for s in out]
    assert starts == sorted(starts)


def test_segments_that_would_interleave_leave_the_plan_alone():
    """Cook 0 takes the plate, cook 1 then needs the board cook 0 uses later in the same
    segment, and cook 0 needs the board after cook 1: no segment can go first."""
    state = _state(2)
    plate, tomato = _item_at(state, 2, 0), _item_at(state, 0, 2)
    board = _cell(state, 1, 6)
    plan = [
        (PlanStep(0, 0, "pickup", _cell(state, 2, 0), (plate,)), TAKE, 1),
        (PlanStep(1, 0, "bump", board, ()), KEEP, 1),
        (PlanStep(2, 1, "chop", board, (tomato,)), KEEP, 3),
        (PlanStep(3, 0, "plate", board, (tomato, plate)), KEEP, 1),
        (PlanStep(4, 0, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1),
    ]
    segs = segments(plan, state)
    assert 1 in segs[0].deps and 0 in segs[1].deps  # a cycle
    assert schedule(plan, state, (0, 1)) == [s for s, _, _ in plan]
    assert schedule(plan, state, (0, 1), fallback=False) is None  # or it says so


def _fd():
    try:
        from ocplus_plan.planning.engines import availability
    except ImportError as exc:  # pragma: no cover
        return False, str(exc)
    a = availability("fast-downward")
    return a.ok, a.reason


FD_OK, FD_WHY = _fd()


@pytest.mark.skipif(not FD_OK, reason=f"fast-downward unavailable: {FD_WHY}")
@pytest.mark.parametrize("preset", ["easy", "medium"])
def test_scheduled_fast_downward_plans_keep_every_step_and_every_resource_order(preset):
    from ocplus_plan.agents.planner import hand_effects, steps_from_record
    from ocplus_plan.planning.compile import compile as compile_state
    from ocplus_plan.planning.engines import solve

    rng = random.Random(7)
    for seed in range(3):
        state = new_state(make_rules(preset, n_agents=2), seed)
        for _ in range(rng.randrange(0, 25)):
            transition(state, [rng.randrange(5), rng.randrange(5)])
        compiled = compile_state(state, max_orders=1)
        result = solve(compiled.problem, "fast-downward", timeout=20, validate=False)
        assert result.status == "solved", result.reason
        entries = []
        for ai in result.plan.actions:
            record = compiled.map_back(ai)
            steps = steps_from_record(record, state, len(entries))
            entries += [(s, e, b) for s, (e, b) in zip(steps, hand_effects(record))]
        # the planner's own steps (plating variants and other stations change steps)
        out = schedule(entries, state, (0, 1), carry_to_plates=False, swap_stations=False)
        def key(s):
            return (s.kind, s.target, s.items)

        assert sorted(map(key, out)) == sorted(key(s) for s, _, _ in entries)
        resources = {r for s, _, _ in entries for r in [("c", s.target)] + [("i", i) for i in s.items]}
        for res in resources:
            def touching(seq, res=res, key=key):
                return [key(s) for s in seq if (res[0] == "c" and s.target == res[1])
                        or (res[0] == "i" and res[1] in s.items)]
            assert touching(out) == touching([s for s, _, _ in entries]), res
        # every cook's queue is whole segments: its hand is empty between them
        for a in (0, 1):
            holding = state.agent_hand[a] >= 0
            effects = {key(s): e for s, e, _ in entries}
            for s in (s for s in out if s.agent == a):
                e = effects[key(s)]
                if e == TAKE:
                    assert not holding, f"cook {a} would pick up with full hands"
                    holding = True
                elif e == RELEASE:
                    holding = False


def _two_dishes(state):
    """Onion served first in the plan, then the lettuce, which lies chopped on board (1,6)."""
    from ocplus_plan.sim.codes import ItemState

    lettuce, onion, plate = _item_at(state, 0, 4), _item_at(state, 4, 4), _item_at(state, 2, 0)
    board, window, plate_tile = _cell(state, 1, 6), _cell(state, 4, 2), _cell(state, 2, 0)
    state.cell_item[_cell(state, 0, 4)] = -1
    state.cell_item[board] = lettuce
    state.item_loc[lettuce] = board
    state.item_state[lettuce] = int(ItemState.CHOPPED)
    return [
        *_chop_job(state, 0, (4, 4), (3, 6), 0),
        (PlanStep(3, 0, "pickup", _cell(state, 3, 6), (onion,)), TAKE, 1),
        (PlanStep(4, 0, "plate", plate_tile, (onion, plate)), KEEP, 1),
        (PlanStep(5, 0, "pickup", plate_tile, (plate,)), TAKE, 1),
        (PlanStep(6, 0, "deliver", window, (plate, onion)), RELEASE, 1),
        (PlanStep(7, 0, "pickup", plate_tile, (plate,)), TAKE, 1),
        (PlanStep(8, 0, "plate", board, (lettuce, plate)), KEEP, 1),
        (PlanStep(9, 0, "deliver", window, (plate, lettuce)), RELEASE, 1),
    ]


def test_a_dish_whose_ingredients_are_ready_is_served_first():
    from ocplus_plan.sim.state import conservation_problems

    state = _state(2)
    plan = _two_dishes(state)
    assert not conservation_problems(state)
    orders = dish_orders(plan, state)
    assert len(orders) == 2 and orders[0] == plan
    assert sorted(map(id, orders[1])) == sorted(map(id, plan)), "the same steps, reordered"
    out = schedule(plan, state, (0, 1))
    served = [s.items[1] for s in out if s.kind == "deliver"]
    assert served == [plan[-1][0].items[1], plan[6][0].items[1]], "lettuce first, then onion"
    kept = schedule(plan, state, (0, 1), reorder_dishes=False)
    def end(out):
        return max(s.start for s in out)
    assert end(out) < end(kept)


def test_dishes_keep_their_order_when_they_share_an_ingredient_or_plates_come_back_dirty():
    state = _state(2)
    plan = _two_dishes(state)
    onion = plan[0][0].items[0]
    # the second dish serves the respawned onion again: it must wait for the first
    twice = plan[:-1] + [(replace(plan[-1][0], items=(plan[-1][0].items[0], onion)),
                          RELEASE, 1)]
    assert dish_orders(twice, state) == [twice]
    dirty = _state(2)
    dirty.rules = replace(dirty.rules, dirty_plates=True)  # only the scheduler reads it here
    plan = _two_dishes(dirty)
    assert dish_orders(plan, dirty) == [plan]


def test_a_plate_scooping_the_steak_off_the_pan_waits_until_it_is_cooked():
    """medium_kitchen: steak (2,0) onto the pan (3,0); the plate (4,0) comes for it."""
    state = new_state(make_rules("medium", n_agents=2), 0)
    steak, plate = _item_at(state, 2, 0), _item_at(state, 4, 0)
    pan = _cell(state, 3, 0)
    plan = [
        (PlanStep(0, 0, "pickup", _cell(state, 2, 0), (steak,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", pan, (steak,)), RELEASE, 1),
        (PlanStep(2, 0, "pickup", _cell(state, 4, 0), (plate,)), TAKE, 1),
        (PlanStep(3, 0, "plate", pan, (steak, plate)), KEEP, 1),
    ]
    out = {s.kind: s.start for s in schedule(plan, state, (0, 1))}
    assert out["plate"] >= out["putdown"] + 1 + state.rules.cook_time


def _chopped(state, spawn: tuple[int, int], board: tuple[int, int]) -> int:
    """Move the vegetable at ``spawn`` onto ``board``, chopped; its item id."""
    veg = _item_at(state, *spawn)
    state.cell_item[_cell(state, *spawn)] = -1
    state.cell_item[_cell(state, *board)] = veg
    state.item_loc[veg] = _cell(state, *board)
    state.item_state[veg] = int(ItemState.CHOPPED)
    return veg


def _plate_to_board(state):
    """easy_open: the plate (2,0) goes to the chopped tomato on board (1,6) and out."""
    tomato = _chopped(state, (0, 2), (1, 6))
    plate = _item_at(state, 2, 0)
    return [
        (PlanStep(0, 0, "pickup", _cell(state, 2, 0), (plate,)), TAKE, 1),
        (PlanStep(1, 0, "plate", _cell(state, 1, 6), (tomato, plate)), KEEP, 1),
        (PlanStep(2, 0, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1),
    ]


def test_a_plate_trip_runs_from_its_pickup_through_its_scoops_to_the_window():
    state = _state(1)
    plan = _plate_to_board(state)
    trips = plate_trips(plan, state)
    assert [(t.pickup, t.scoops, t.deliver) for t in trips] == [(0, [1], 2)]


def test_a_scooped_ingredient_can_be_carried_to_the_plate_instead():
    state = _state(1)
    plan = _plate_to_board(state)
    tomato, plate = plan[1][0].items
    (variant,) = plate_carries(plan, plate_trips(plan, state)[0], state)
    assert [(s.kind, s.target, s.items, e) for s, e, _ in variant] == [
        ("pickup", _cell(state, 1, 6), (tomato,), TAKE),
        ("plate", _cell(state, 2, 0), (tomato, plate), RELEASE),
        ("pickup", _cell(state, 2, 0), (plate,), TAKE),
        ("deliver", _cell(state, 4, 2), (plate, tomato), RELEASE),
    ]


def test_the_schedule_carries_to_the_plate_when_that_ends_sooner():
    """The cook stands by the board (1,6), far from the plate (2,0), and the window (4,2) is
    near the plate: fetching the plate to the board and back walks twice what bringing
    the tomato to the plate does."""
    state = _state(1)
    state.agent_pos[0] = _cell(state, 1, 5)
    plan = _plate_to_board(state)
    kept = schedule(plan, state, (0,), carry_to_plates=False)
    out = schedule(plan, state, (0,))
    assert [s.kind for s in kept] == ["pickup", "plate", "deliver"]
    assert [s.kind for s in out] == ["pickup", "plate", "pickup", "deliver"]
    assert max(s.start for s in out) < max(s.start for s in kept)


def _plate_moved_for_the_tomato(state):
    """The plate goes from (2,0) to the counter (0,5) by the boards, the chopped tomato is
    brought to it there, and it is picked up again. (plan, tomato, plate, home, away)"""
    tomato = _chopped(state, (0, 2), (1, 6))
    plate, home, away = _item_at(state, 2, 0), _cell(state, 2, 0), _cell(state, 0, 5)
    return [
        (PlanStep(0, 0, "pickup", home, (plate,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", away, (plate,)), RELEASE, 1),
        (PlanStep(2, 0, "pickup", _cell(state, 1, 6), (tomato,)), TAKE, 1),
        (PlanStep(3, 0, "plate", away, (tomato, plate)), RELEASE, 1),
        (PlanStep(4, 0, "pickup", away, (plate,)), TAKE, 1),
    ], tomato, plate, home, away


def test_a_plate_moved_next_to_the_boards_may_stay_home():
    """The plate moves to the boards, gets the tomato there and is served: the variant
    leaves it at (2,0)."""
    state = _state(2)
    trip, tomato, plate, home, _ = _plate_moved_for_the_tomato(state)
    plan = trip + [(PlanStep(5, 0, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1)]
    (variant,) = plate_stays_home(plan, state)
    assert [(s.kind, s.target) for s, _, _ in variant] == [
        ("pickup", _cell(state, 1, 6)), ("plate", home), ("pickup", home),
        ("deliver", _cell(state, 4, 2))]
    # something else put on the plate's counter meanwhile: the plate cannot stay there
    onion = _item_at(state, 4, 4)
    blocked = plan[:2] + [(PlanStep(9, 1, "pickup", _cell(state, 4, 4), (onion,)), TAKE, 1),
                          (PlanStep(10, 1, "putdown", home, (onion,)), RELEASE, 1)] + plan[2:]
    assert plate_stays_home(blocked, state) == []


@pytest.mark.skipif(not FD_OK, reason=f"fast-downward unavailable: {FD_WHY}")
@pytest.mark.parametrize("preset", ["easy", "medium"])
def test_plating_variants_of_fast_downward_plans_serve_the_same_dishes(preset):
    """With plating changes on, the schedule of a real plan delivers the same plates with
    the same ingredients, and played in its scheduled order every step finds its cell as
    it needs it."""
    from ocplus_plan.agents.planner import plan_entries
    from ocplus_plan.execution.schedule import _cells_agree
    from ocplus_plan.planning.compile import compile as compile_state
    from ocplus_plan.planning.engines import solve

    rng = random.Random(11)
    for seed in range(3):
        state = new_state(make_rules(preset, n_agents=2), seed)
        for _ in range(rng.randrange(0, 25)):
            transition(state, [rng.randrange(5), rng.randrange(5)])
        compiled = compile_state(state, max_orders=None, agents=[0])
        result = solve(compiled.problem, "fast-downward", timeout=20, validate=False)
        assert result.status == "solved", result.reason
        entries = plan_entries(compiled, result.plan, state)
        out = schedule(entries, state, (0, 1))
        def dishes(steps):
            return sorted(tuple(sorted(s.items)) for s in steps if s.kind == "deliver")

        assert dishes(out) == dishes(s for s, _, _ in entries)
        assert _cells_agree([(s, KEEP, 1) for s in out], state)


def test_a_steak_served_earlier_in_the_plan_cooks_again_from_raw():
    """medium_kitchen: a cooked steak lies on the pan (3,0); the plan serves it, then cooks
    the respawned steak (same item, back raw at (2,0)): its second take waits a whole cook."""
    state = new_state(make_rules("medium", n_agents=1), 0)
    steak, plate = _item_at(state, 2, 0), _item_at(state, 4, 0)
    pan, spawn = _cell(state, 3, 0), _cell(state, 2, 0)
    state.cell_item[spawn], state.cell_item[pan] = -1, steak
    state.item_loc[steak] = pan
    state.item_state[steak] = int(ItemState.COOKED)
    state.item_progress[steak] = state.rules.cook_time
    plan = [
        (PlanStep(0, 0, "pickup", _cell(state, 4, 0), (plate,)), TAKE, 1),
        (PlanStep(1, 0, "plate", pan, (steak, plate)), KEEP, 1),
        (PlanStep(2, 0, "deliver", _cell(state, 6, 2), (plate, steak)), RELEASE, 1),
        (PlanStep(3, 0, "pickup", spawn, (steak,)), TAKE, 1),
        (PlanStep(4, 0, "putdown", pan, (steak,)), RELEASE, 1),
        (PlanStep(5, 0, "pickup", _cell(state, 4, 0), (plate,)), TAKE, 1),
        (PlanStep(6, 0, "plate", pan, (steak, plate)), KEEP, 1),
        (PlanStep(7, 0, "deliver", _cell(state, 6, 2), (plate, steak)), RELEASE, 1),
    ]
    out = schedule(plan, state, (0,))
    put = next(s.start for s in out if (s.kind, s.target) == ("putdown", pan))
    take = next(s.start for s in out if s.target == pan and s.start > put)
    assert take >= put + 1 + state.rules.cook_time


def test_a_plate_that_wanders_from_counter_to_counter_may_stay_home_throughout():
    """The plate goes (2,0) -> (0,5) (the tomato is brought there) -> back to (2,0) (the
    onion is brought there) and out: one variant drops both moves."""
    state = _state(2)
    onion = _chopped(state, (4, 4), (3, 6))
    trip, tomato, plate, home, _ = _plate_moved_for_the_tomato(state)
    plan = trip + [
        (PlanStep(5, 0, "putdown", home, (plate,)), RELEASE, 1),
        (PlanStep(6, 0, "pickup", _cell(state, 3, 6), (onion,)), TAKE, 1),
        (PlanStep(7, 0, "plate", home, (onion, plate)), RELEASE, 1),
        (PlanStep(8, 0, "pickup", home, (plate,)), TAKE, 1),
        (PlanStep(9, 0, "deliver", _cell(state, 4, 2), (plate, tomato, onion)), RELEASE, 1),
    ]
    variants = [[(s.kind, s.target) for s, _, _ in v] for v in plate_stays_home(plan, state)]
    assert [("pickup", _cell(state, 1, 6)), ("plate", home), ("pickup", _cell(state, 3, 6)),
            ("plate", home), ("pickup", home), ("deliver", _cell(state, 4, 2))] in variants


def test_a_plate_fetched_for_a_scoop_and_put_back_need_not_move_at_all():
    """The plate leaves (2,0) for the tomato on board (1,6) and is put back at (2,0): the
    tomato may as well come to it, and the plate's pick-up and put-down go."""
    state = _state(1)
    tomato = _chopped(state, (0, 2), (1, 6))
    plate, home = _item_at(state, 2, 0), _cell(state, 2, 0)
    plan = [
        (PlanStep(0, 0, "pickup", home, (plate,)), TAKE, 1),
        (PlanStep(1, 0, "plate", _cell(state, 1, 6), (tomato, plate)), KEEP, 1),
        (PlanStep(2, 0, "putdown", home, (plate,)), RELEASE, 1),
        (PlanStep(3, 0, "pickup", home, (plate,)), TAKE, 1),
        (PlanStep(4, 0, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1),
    ]
    (trip,) = plate_trips(plan, state)
    assert (trip.pickup, trip.scoops, trip.deliver) == (0, [1], 2)
    (variant,) = plate_carries(plan, trip, state)
    assert [(s.kind, s.target) for s, _, _ in variant] == [
        ("pickup", _cell(state, 1, 6)), ("plate", home), ("pickup", home),
        ("deliver", _cell(state, 4, 2))]


def test_work_that_serves_no_order_is_dropped():
    """The tomato is served, and the onion is fetched to a board and left there: no later
    step needs it, so it goes (before the delivery in plan order or after it). A plan that
    delivers nothing is left whole."""
    from ocplus_plan.execution.schedule import without_idle_work

    state = _state(1)
    plan = _plate_to_board(state)
    onion = _item_at(state, 4, 4)
    junk = [(PlanStep(3, 0, "pickup", _cell(state, 4, 4), (onion,)), TAKE, 1),
            (PlanStep(4, 0, "putdown", _cell(state, 3, 6), (onion,)), RELEASE, 1)]
    assert without_idle_work(junk + plan, state) == plan
    assert without_idle_work(plan + junk, state) == plan
    assert without_idle_work(junk, state) == junk
    # a chop that the delivered dish needs is kept, with the carry before it
    state = _state(1)
    job = _chop_job(state, 0, (0, 2), (1, 6), 0)
    tomato, plate = job[0][0].items[0], _item_at(state, 2, 0)
    served = job + [
        (PlanStep(3, 0, "pickup", _cell(state, 2, 0), (plate,)), TAKE, 1),
        (PlanStep(4, 0, "plate", _cell(state, 1, 6), (tomato, plate)), KEEP, 1),
        (PlanStep(5, 0, "deliver", _cell(state, 4, 2), (plate, tomato)), RELEASE, 1),
    ]
    assert without_idle_work(served, state) == served


def test_an_ingredient_parked_on_a_counter_may_go_straight_to_its_board():
    """The tomato goes from its tile (0,2) to the counter (0,3), later from there to the
    board (1,6): one variant puts it on the board at once."""
    from ocplus_plan.execution.schedule import unparked

    state = _state(1)
    tomato = _item_at(state, 0, 2)
    counter, board = _cell(state, 0, 3), _cell(state, 1, 6)
    plan = [
        (PlanStep(0, 0, "pickup", _cell(state, 0, 2), (tomato,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", counter, (tomato,)), RELEASE, 1),
        (PlanStep(2, 0, "pickup", counter, (tomato,)), TAKE, 1),
        (PlanStep(3, 0, "putdown", board, (tomato,)), RELEASE, 1),
        (PlanStep(4, 0, "chop", board, (tomato,)), KEEP, 3),
    ]
    (variant,) = unparked(plan, state)
    assert [(s.kind, s.target) for s, _, _ in variant] == [
        ("pickup", _cell(state, 0, 2)), ("putdown", board), ("chop", board)]


def test_a_plate_taken_to_the_sink_is_not_a_plate_that_may_stay_home():
    """hard (MapC): the plate goes from its counter to the sink, is washed there and picked
    up again; that is no move between counters, and washing stays at the sink."""
    state = new_state(make_rules("hard", n_agents=2), 0)
    plate = _item_at(state, 3, 8)
    home, sink = _cell(state, 3, 8), _cell(state, 8, 7)
    plan = [
        (PlanStep(0, 0, "pickup", home, (plate,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", sink, (plate,)), RELEASE, 1),
        (PlanStep(2, 0, "wash", sink, (plate,)), KEEP, 3),
        (PlanStep(3, 0, "pickup", sink, (plate,)), TAKE, 1),
    ]
    assert plate_stays_home(plan, state) == []


def test_switch_aware_schedule_times_walks_over_the_coming_switches():
    """Two rooms joined by a cell that switches between wall and floor every 10 steps
    (``test_paths.SWITCHING``); cook 0 carries the tomato (0,1) to the board (0,5). The
    plain estimate walks over any layout's floor plus a period's detour; ``switches``
    times the walk: closed now, the cook crosses when the switch opens the way (step 10,
    three steps on); open now but closing in one step, it is cut off until it reopens."""
    from tests.execution.test_paths import SWITCHING

    state = new_state(make_rules("easy", map=SWITCHING, n_agents=2, dynamic=True), 0)
    geo = state.geo
    veg, board = _item_at(state, 0, 1), geo.flat(0, 5)
    plan = [(PlanStep(0, 0, "pickup", geo.flat(0, 1), (veg,)), TAKE, 1),
            (PlanStep(1, 0, "putdown", board, (veg,)), RELEASE, 1)]

    def put_at(**kw):
        return next(s.start for s in schedule(plan, state, (0, 1), **kw) if s.kind == "putdown")

    assert put_at() == 1 + 4 + 10
    assert put_at(switches=True) == 1 + 9 + 3
    state.layout_index, state.next_switch = 1, 1  # open, closing after this step
    assert put_at() == 1 + 4
    assert put_at(switches=True) == 1 + 10 + 3  # it reopens at step 11


def test_a_plan_that_cannot_be_scheduled_on_one_board_may_be_on_two():
    """Cook 1 plates the tomato off board (1,6) between cook 0's tomato and its lettuce on
    that board, and the lettuce after it: the plate's trip and the lettuce's segments
    interleave, so the plan cannot be scheduled as it is; with one of the two stays moved
    to the other board (3,6) it can (medium, seed 0: cook 0 stood 13 steps holding the lettuce
    in front of the busy board while the other one stayed free)."""
    state = _state(2)
    plate, lettuce = _item_at(state, 2, 0), _item_at(state, 0, 4)
    board = _cell(state, 1, 6)
    plan = _chop_job(state, 0, (0, 2), (1, 6), 0)
    tomato = plan[0][0].items[0]
    plan += [
        (PlanStep(3, 1, "pickup", _cell(state, 2, 0), (plate,)), TAKE, 1),
        (PlanStep(4, 1, "plate", board, (tomato, plate)), KEEP, 1),
        (PlanStep(5, 0, "pickup", _cell(state, 0, 4), (lettuce,)), TAKE, 1),
        (PlanStep(6, 0, "putdown", board, (lettuce,)), RELEASE, 1),
        (PlanStep(7, 0, "chop", board, (lettuce,)), KEEP, state.rules.chop_steps),
        (PlanStep(8, 1, "plate", board, (lettuce, plate, tomato)), KEEP, 1),
        (PlanStep(9, 1, "deliver", _cell(state, 4, 2), (plate, tomato, lettuce)), RELEASE, 1),
    ]
    kw = {"carry_to_plates": False, "reorder_dishes": False, "fallback": False}
    assert schedule(plan, state, (0, 1), swap_stations=False, **kw) is None
    out = schedule(plan, state, (0, 1), **kw)
    assert out is not None
    put = {s.items[0]: s.target for s in out if s.kind == "putdown"}
    assert {put[tomato], put[lettuce]} == {board, _cell(state, 3, 6)}  # one on each


def test_two_stations_worked_from_one_cell_are_not_worked_at_once():
    """Board (1,6) and counter (0,5) of easy_open are both worked from (1,5) only: the
    schedule does not give one cook a step at the counter while the other chops there."""
    from ocplus_plan.sim.queries import interaction_spots

    state = _state(2)
    walk = state.geo.walkables[0]
    for r, c in ((1, 6), (0, 5)):
        assert interaction_spots(state.geo.neighbors, walk, _cell(state, r, c)) == [_cell(state, 1, 5)]
    plan = _chop_job(state, 0, (0, 4), (1, 6), 0)
    tomato = _item_at(state, 0, 2)
    plan += [
        (PlanStep(3, 1, "pickup", _cell(state, 0, 2), (tomato,)), TAKE, 1),
        (PlanStep(4, 1, "putdown", _cell(state, 0, 5), (tomato,)), RELEASE, 1),
    ]
    out = schedule(plan, state, (0, 1), swap_stations=False, carry_to_plates=False,
                   reorder_dishes=False)
    chop = next(s for s in out if s.kind == "chop")
    counter = next(s for s in out if s.target == _cell(state, 0, 5))
    chopping = range(int(chop.start), int(chop.start) + state.rules.chop_steps)
    assert int(counter.start) not in chopping, (chop, counter)

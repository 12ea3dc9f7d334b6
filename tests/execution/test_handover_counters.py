"""Hand-overs through counters: the schedule may move an item's stay on a counter to another
counter that both cooks reach (execution/plan_variants.py: counter_choices, _best_stations)."""

from __future__ import annotations

import warnings
from dataclasses import replace

from ocplus_plan.execution.plans import PlanStep
from ocplus_plan.execution.schedule import KEEP, RELEASE, TAKE, counter_choices, schedule
from ocplus_plan.sim import make_rules, new_state

warnings.simplefilter("ignore", UserWarning)

# two rooms joined only by the counters of row 2: cook 0 above with the lettuce crate and a
# board, cook 1 below with the tomato crate, a board, the plate and the window
ROOMS = {"name": "rooms", "max_n_agent": 2,
         "game_map": [[1, 4, 6, 1, 1, 1],
                      [1, 0, 0, 0, 0, 1],
                      [1, 1, 1, 1, 1, 1],
                      [1, 0, 0, 0, 0, 7],
                      [1, 3, 6, 5, 1, 1]],
         "agent_spawn_points": [[1, 1], [3, 4]]}


def _state():
    return new_state(make_rules("easy", map=ROOMS, n_agents=2, recipes=["tomato"]), 0)


def test_counter_choices_are_the_nearest_counters_both_rooms_reach():
    state = _state()
    f = state.geo.flat
    choices = counter_choices(state)
    assert choices[f(2, 1)] == [f(2, 2), f(2, 3), f(2, 4)]
    # a counter of the top wall is reached from the top room only: any counter of that
    # room or of row 2 may take its place; a counter reached from nowhere is never chosen
    assert f(0, 3) in choices and f(2, 0) not in choices and f(2, 5) not in choices
    assert all(c != f(2, 0) for cs in choices.values() for c in cs)
    assert not any(c == f(0, 3) for cs in (choices[f(2, c)] for c in range(1, 5)) for c in cs)


def test_two_hand_overs_through_one_counter_go_through_two():
    """The plan hands the tomato up through counter (2,1) and then the lettuce down through
    the same counter: the lettuce waits until the tomato is taken off. Through two counters
    both go at once, and both cooks chop at the same time."""
    state = _state()
    f = state.geo.flat
    tomato, lettuce = state.cell_item[f(4, 1)], state.cell_item[f(0, 1)]
    counter, chops = f(2, 1), state.rules.chop_steps
    plan = [
        (PlanStep(0, 1, "pickup", f(4, 1), (tomato,)), TAKE, 1),
        (PlanStep(1, 1, "putdown", counter, (tomato,)), RELEASE, 1),
        (PlanStep(2, 0, "pickup", counter, (tomato,)), TAKE, 1),
        (PlanStep(3, 0, "putdown", f(0, 2), (tomato,)), RELEASE, 1),
        (PlanStep(4, 0, "chop", f(0, 2), (tomato,)), KEEP, chops),
        (PlanStep(5, 0, "pickup", f(0, 1), (lettuce,)), TAKE, 1),
        (PlanStep(6, 0, "putdown", counter, (lettuce,)), RELEASE, 1),
        (PlanStep(7, 1, "pickup", counter, (lettuce,)), TAKE, 1),
        (PlanStep(8, 1, "putdown", f(4, 2), (lettuce,)), RELEASE, 1),
        (PlanStep(9, 1, "chop", f(4, 2), (lettuce,)), KEEP, chops),
    ]
    fixed = schedule(plan, state, (0, 1), swap_stations=False)
    moved = schedule(plan, state, (0, 1))

    def end(out):
        return max(s.start + (chops if s.kind == "chop" else 1) for s in out)

    assert end(moved) < end(fixed)
    # each item's stay moves whole: it is put on and taken off one counter of row 2,
    # and the two hand-overs go through two counters
    row2 = {f(2, c) for c in range(1, 5)}
    via = [{s.target for s in moved if item in s.items and s.target in row2}
           for item in (tomato, lettuce)]
    assert all(len(v) == 1 for v in via) and via[0] != via[1]
    assert len([s for s in moved if s.target in row2]) == 4
    # one cook hands nothing over: its counters stay as planned
    alone = [(s.kind, s.target) for s in schedule(plan, state, (0,)) if s.kind != "chop"]
    assert alone.count(("putdown", counter)) == 2


def _switching_state():
    """ROOMS on a switching map: only the unreachable corner (0,5) switches."""
    spec = dict(ROOMS, is_dynamic_map=True, map_switch_step=50,
                switch_map=[[-1 if (r, c) == (0, 5) else v for c, v in enumerate(row)]
                            for r, row in enumerate(ROOMS["game_map"])])
    return new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                dynamic=True), 0)


def test_at_equal_makespan_the_counter_where_the_work_starts_earliest():
    """Cook 0 chops the lettuce above while the tomato comes up through counter (2,4). Every
    counter of row 2 ends the schedule at the same step; on a switching map the tomato's
    stay goes to (2,1), above its crate's spot, where it is put down at once (the sum of the
    steps' starts is the schedule cost's last term there); on a static one it is not."""
    state = _switching_state()
    f = state.geo.flat
    tomato, lettuce = state.cell_item[f(4, 1)], state.cell_item[f(0, 1)]
    counter, chops = f(2, 4), state.rules.chop_steps
    plan = [
        (PlanStep(0, 0, "pickup", f(0, 1), (lettuce,)), TAKE, 1),
        (PlanStep(1, 0, "putdown", f(0, 2), (lettuce,)), RELEASE, 1),
        (PlanStep(2, 0, "chop", f(0, 2), (lettuce,)), KEEP, chops),
        (PlanStep(3, 1, "pickup", f(4, 1), (tomato,)), TAKE, 1),
        (PlanStep(4, 1, "putdown", counter, (tomato,)), RELEASE, 1),
        (PlanStep(5, 0, "pickup", f(0, 2), (lettuce,)), TAKE, 1),
        (PlanStep(6, 0, "putdown", f(0, 3), (lettuce,)), RELEASE, 1),
        (PlanStep(7, 0, "pickup", counter, (tomato,)), TAKE, 1),
        (PlanStep(8, 0, "putdown", f(0, 2), (tomato,)), RELEASE, 1),
        (PlanStep(9, 0, "chop", f(0, 2), (tomato,)), KEEP, chops),
    ]

    def end(out):
        return max(s.start + (chops if s.kind == "chop" else 1) for s in out)

    moved = schedule(plan, state, (0, 1), carry_to_plates=False)
    put = next(s for s in moved if s.kind == "putdown" and s.items == (tomato,))
    assert (put.target, put.start) == (f(2, 1), 4)
    for c in (2, 3, 4):  # the plan through any other counter of row 2 ends no sooner
        other = [(s if s.target != counter else replace(s, target=f(2, c)), e, b)
                 for s, e, b in plan]
        assert end(schedule(other, state, (0, 1), carry_to_plates=False,
                            swap_stations=False)) >= end(moved)
    static = schedule(plan, _state(), (0, 1), carry_to_plates=False)
    assert end(static) == end(moved)
    assert next(s for s in static if s.kind == "putdown" and s.items == (tomato,)).start > 4

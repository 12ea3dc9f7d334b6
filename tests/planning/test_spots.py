"""The relaxed kitchen of a switching map and the expected walks its moves cost."""

from __future__ import annotations

import pytest

from ocplus_plan.planning.spots import (
    build_spots,
    expected_walks,
    real_geometry,
    relaxed_state,
)
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.queries import distances, layout_at, walkable_in_any_layout
from tests.execution.test_paths import SWITCHING


def _arrival(geo, period, start, goal, layout, due):
    """Earliest arrival by a plain set BFS over time (the reference)."""
    front, t = {start}, 0
    while goal not in front:
        walk = geo.walkables[layout_at(layout, due, period, t)]
        front |= {n for c in front for n in geo.neighbors[c] if n >= 0 and walk[n]}
        t += 1
    return t


def test_expected_walks_average_the_earliest_arrival_over_every_phase():
    state = new_state(make_rules("easy", map=SWITCHING, n_agents=2, dynamic=True), 0)
    geo = state.geo
    start = geo.flat(1, 1)
    got = expected_walks(geo, 10, start)
    for goal in (geo.flat(1, 2), geo.flat(1, 5), geo.flat(2, 4)):
        arrivals = [_arrival(geo, 10, start, goal, layout, due)
                    for layout in (0, 1) for due in range(1, 11)]
        assert got[goal] == round(sum(arrivals) / len(arrivals))
    assert got[geo.flat(1, 5)] > distances(geo.neighbors, walkable_in_any_layout(geo), [start])[
        geo.flat(1, 5)]  # the way is closed half of the time
    assert geo.flat(0, 0) not in got  # a wall


def test_the_relaxed_kitchen_opens_every_switching_cell_and_knows_its_real_map():
    state = new_state(make_rules("hard", n_agents=2), 0)
    relaxed = relaxed_state(state)
    assert relaxed is not state and relaxed.geo.walkables[0] == walkable_in_any_layout(state.geo)
    assert real_geometry(relaxed.geo) is state.geo and real_geometry(state.geo) is None
    assert relaxed_state(state).geo is relaxed.geo  # one relaxed geometry per map
    assert state.geo.walkables[state.layout_index] != relaxed.geo.walkables[0]  # untouched


def test_relaxed_moves_cost_the_walk_over_the_switches_from_now():
    """MapC: from the top-right room to the bottom-right one the relaxed floor is a short
    walk through both column-3 gaps, never open at once; the move costs the walk that
    starts now (layout 0, next switch in 15 steps), waits for each switch and crosses."""
    state = new_state(make_rules("hard", n_agents=2), 0)
    relaxed = relaxed_state(state)
    graph = build_spots(relaxed)
    geo = state.geo
    top, bottom = geo.flat(3, 7), geo.flat(5, 7)
    cost = {(s, t): c for s, t, c in graph.links}
    assert cost[(top, bottom)] == _arrival(geo, 15, top, bottom, 0, 15)
    assert cost[(top, bottom)] > graph.info.dist[top][bottom]


def test_a_relaxed_move_costs_the_walk_from_the_current_phase():
    """SWITCHING (period 10): (1,3) is a wall in layout 0 and floor in layout 1. The move
    from (1,1) to (1,5) costs what the walk takes if it starts now: a plain walk while the
    way stays open, a wait for the switch while it is closed; with the switch overdue
    (the phase unknown) the mean over the phases."""
    state = new_state(make_rules("easy", map=SWITCHING, n_agents=2, dynamic=True), 0)
    geo = state.geo
    start, goal = geo.flat(1, 1), geo.flat(1, 5)
    state.agent_pos[0] = start

    def cost(layout, due):
        s = state.copy()
        s.layout_index, s.next_switch = layout, s.t + due
        relaxed = relaxed_state(s)
        assert relaxed.layout_index == layout  # the real phase is kept
        return {(a, b): c for a, b, c in build_spots(relaxed).links}[(start, goal)]

    assert cost(1, 10) == 4  # open for 10 more steps: the plain walk
    assert cost(0, 10) == _arrival(geo, 10, start, goal, 0, 10) == 13  # wait, then cross
    assert cost(0, 3) == _arrival(geo, 10, start, goal, 0, 3) == 6
    assert cost(1, 1) == _arrival(geo, 10, start, goal, 1, 1) == 14  # it closes at once
    assert cost(0, 0) == expected_walks(geo, 10, start)[goal]  # overdue: the mean


def test_the_real_layouts_hand_over_counters_are_places_of_the_relaxed_kitchen():
    state = new_state(make_rules("hard", n_agents=2), 0)
    geo = state.geo
    relaxed = build_spots(relaxed_state(state))
    assert {geo.flat(4, c) for c in range(4, 8)} <= set(relaxed.places)  # row 4, MapC
    assert not relaxed.info.handovers  # (the relaxed floor alone has none: one room)


#: two rooms joined by the gap (1,3), a wall in layout 0 and floor in layout 1, and by the
#: counters of column 3 below it: tomato (0,1) on the left, board (0,5), plates (4,5) on the
#: right; the window (1,7) is reached only through (1,6), open with the gap
GAP = [[1, 3, 1, 1, 1, 6, 1, 1],
       [1, 0, 0, -1, 0, 0, -1, 7],
       [1, 0, 0, 1, 0, 0, 1, 1],
       [1, 0, 0, 1, 0, 0, 1, 1],
       [1, 1, 1, 1, 1, 5, 1, 1]]


def _bjolp() -> bool:
    from ocplus_plan.planning.engines import availability

    return availability("fast-downward-bjolp").ok


@pytest.mark.skipif(not _bjolp(), reason="fast-downward-bjolp unavailable")
def test_a_relaxed_plan_hands_over_when_that_is_cheaper_from_now():
    """Layout 0, next switch in 10 steps: the window is closed, so the real problem has no
    plan and the kitchen is planned relaxed. Carrying the tomato across the gap would wait
    for the switch; handing it over a column-3 counter is cheaper from now. With the gap
    open for 10 more steps the cook carries it across itself (an optimal planner)."""
    from ocplus_plan.planning.compile import compile as compile_state
    from ocplus_plan.planning.engines import solve

    spec = {"name": "gap", "game_map": GAP, "switch_map": [[0 if v == -1 else v for v in row]
                                                          for row in GAP],
            "agent_spawn_points": [[1, 1], [3, 4]], "is_dynamic_map": True, "map_switch_step": 10}
    state = new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                 dynamic=True, horizon=100), 0)
    counters = {f"counter_{r}_3" for r in (2, 3)}

    def handed_over(layout):
        s = state.copy()
        s.layout_index, s.next_switch = layout, s.t + 10
        compiled = compile_state(relaxed_state(s), None, max_orders=1)
        result = solve(compiled.problem, "fast-downward-bjolp", timeout=20, validate=False)
        assert result.status == "solved", result.reason
        return any(a.action.name == "put" and str(a.actual_parameters[2]) in counters
                   for a in result.plan.actions)

    assert handed_over(0)
    assert not handed_over(1)

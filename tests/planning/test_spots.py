"""The relaxed kitchen of a switching map and the expected walks its moves cost."""

from __future__ import annotations

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


def test_relaxed_moves_cost_the_expected_walk_over_the_switches():
    """MapC: from the top-right room to the bottom-right one the relaxed floor is a short
    walk through both column-3 gaps, never open at once; the move costs the expected walk."""
    state = new_state(make_rules("hard", n_agents=2), 0)
    relaxed = relaxed_state(state)
    graph = build_spots(relaxed)
    geo = state.geo
    top, bottom = geo.flat(3, 7), geo.flat(5, 7)
    cost = {(s, t): c for s, t, c in graph.links}
    assert cost[(top, bottom)] == expected_walks(geo, 15, top)[bottom]
    assert cost[(top, bottom)] > graph.info.dist[top][bottom]

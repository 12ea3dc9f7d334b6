"""Where agents stand and what they reach: the geometry the compiler turns into objects.

A *place* is a non-walkable cell that holds or processes items (a counter, a spawn
tile, a board, a pan, a sink, the trash, the serving window). A *spot* is a floor
cell from which an agent bumps into a place (it is 4-adjacent to it). With the
``stations`` granularity agents jump between spots and a jump costs the
shortest-path distance in the current layout (other agents ignored); with
``cells`` every reachable floor cell is a spot and a move is one grid step.

Which plain counters become places (there may be dozens, and each one multiplies
the planner's branching):

* every counter that holds an item now (its item must have a location);
* every *hand-over* counter: one that touches floor cells of two or more regions
  that are disconnected from each other (``easy_divided`` needs one to pass a
  tomato through its wall); in the relaxed kitchen (below), which is one room, the
  counters that are hand-overs in some real layout;
* per region, ``extra_counters`` (default 2) free counters, chosen as those whose
  spot is closest in total to the region's stations, so that an agent can set a
  plate or an ingredient down near where the work happens.

Spawn tiles are places too, but the model lets an item be put down only on its
own spawn tile (a foreign item there would make the tile's owner wait to respawn).

Everything that depends only on the layout (regions, all-pairs distances, the
station and counter choice) is computed once per geometry and layout and cached.

The *relaxed kitchen* (:func:`relaxed_state`) of a map whose layout switches has every
cell that is floor in some layout as floor: a plan exists there when no single layout
lets the cooks reach every station (MapC). Its ``stations`` moves cost the steps the
walk takes over the real switches if it starts now (:func:`phase_walks`: from the
current layout and the steps to its next switch, waiting for the switch that opens its
way), not the relaxed floor's distance, so a plan there hands items over a counter
rather than carrying them across a way that is closed now. The relaxed state keeps the
real layout index and next switch (both of its layouts are the same floor); when the
next switch is overdue (a cook holds it up, or a copy of the state ran past it with the
layout frozen, as a chained plan's does) the phase is not known and a move costs
:func:`expected_walks`, the mean over the phases.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

from ..sim.codes import COUNTERS, STATIONS, Cell
from ..sim.queries import distances, interaction_spots, switching_walks, walkable_in_any_layout
from ..sim.state import Geometry, State

#: Cell codes that are places whatever they hold (counters are chosen, see the module doc).
STATION_CODES = frozenset(int(c) for c in STATIONS)
_HOLDERS = frozenset(int(c) for c in COUNTERS)


@dataclass(frozen=True)
class LayoutInfo:
    """Static facts of one layout of one geometry (cached)."""

    #: flat cell -> region id for walkable cells, -1 elsewhere
    region: tuple[int, ...]
    #: distance table: dist[a][b] for walkable cells, by BFS in this layout (None = unreachable)
    dist: dict[int, dict[int, int]]
    #: walkable neighbours of every place-like cell (flat -> tuple of floor cells)
    floor_around: dict[int, tuple[int, ...]]
    stations: tuple[int, ...]
    handovers: tuple[int, ...]
    #: region id -> chosen free counters for that region
    extras: dict[int, tuple[int, ...]]


@lru_cache(maxsize=64)
def layout_info(geo: Geometry, layout_index: int, extra_counters: int = 2) -> LayoutInfo:
    """Regions, distances and chosen places of one layout (cached per geometry)."""
    walk = geo.walkables[layout_index]
    terrain = geo.terrains[layout_index]
    nbrs = geo.neighbors
    n = len(walk)
    region = [-1] * n
    dist: dict[int, dict[int, int]] = {}
    rid = 0
    for f in range(n):
        if walk[f]:
            dist[f] = {g: d for g, d in enumerate(distances(nbrs, walk, [f])) if d >= 0}
            if region[f] < 0:
                for g in dist[f]:
                    region[g] = rid
                rid += 1
    floor_around = {f: tuple(interaction_spots(nbrs, walk, f)) for f in range(n) if not walk[f]}
    stations = tuple(f for f in range(n) if terrain[f] in STATION_CODES and floor_around[f])
    counters = [f for f in range(n) if terrain[f] == Cell.COUNTER and floor_around[f]]
    handovers = tuple(
        f for f in counters if len({region[g] for g in floor_around[f]}) >= 2
    )
    extras: dict[int, tuple[int, ...]] = {}
    for r in range(rid):
        station_spots = [g for s in stations for g in floor_around[s] if region[g] == r]
        scored = []
        for f in counters:
            if f in handovers:
                continue
            spots = [g for g in floor_around[f] if region[g] == r]
            if not spots:
                continue
            score = min(
                sum(dist[g].get(s, n) for s in station_spots) for g in spots
            )
            scored.append((score, f))
        extras[r] = tuple(f for _, f in sorted(scored)[:extra_counters])
    return LayoutInfo(tuple(region), dist, floor_around, stations, handovers, extras)


@dataclass(frozen=True)
class SpotGraph:
    """The places and spots of one state, and how agents move between spots."""

    places: tuple[int, ...]
    spots: tuple[int, ...]
    #: (spot, place) pairs: the agent on spot can bump into place
    adjacent: tuple[tuple[int, int], ...]
    #: (from, to, cost) moves an agent may make
    links: tuple[tuple[int, int, int], ...]
    #: agent -> the spot it stands on now
    agent_spot: tuple[int, ...]
    info: LayoutInfo
    #: (layout, from, to, cost) moves per layout (stations, ``every_layout`` only)
    layout_links: tuple[tuple[int, int, int, int], ...] = ()

    def distance(self, a: int, b: int) -> int | None:
        """Shortest walk from floor cell ``a`` to ``b`` in this layout (None if unreachable)."""
        return self.info.dist.get(a, {}).get(b)


def build_spots(state: State, granularity: str = "stations", extra_counters: int = 2,
                every_layout: bool = False) -> SpotGraph:
    """The spot graph of ``state`` in its current layout.

    ``every_layout`` (for anticipated layout switches): the spots are the floor cells
    reachable from the agents when every layout's floor counts, so a cell that opens
    later is already a spot (cells: the compiler guards it with ``open``; stations:
    ``layout_links`` holds each layout's moves, shorter than the switch period).
    """
    geo = state.geo
    li = state.layout_index
    info = layout_info(geo, li, extra_counters)
    terrain = geo.terrains[li]
    region = info.region
    agent_regions = {region[p] for p in state.agent_pos}
    if every_layout:
        union = walkable_in_any_layout(geo)
        reach: set[int] = set()
        for start in state.agent_pos:
            if start not in reach:
                reach.update(f for f, d in enumerate(distances(geo.neighbors, union, [start]))
                             if d >= 0)
        region = tuple(0 if f in reach else -1 for f in range(len(terrain)))
        agent_regions = {0}
        info = LayoutInfo(region, info.dist, {
            f: tuple(interaction_spots(geo.neighbors, union, f))
            for f in info.floor_around}, info.stations, info.handovers, info.extras)
    chosen = set(info.stations) | set(info.handovers)
    real = real_geometry(geo)
    if real is not None:  # the relaxed kitchen is one room: keep the real layouts' hand-overs
        for layout in range(len(real.walkables)):
            chosen.update(layout_info(real, layout, extra_counters).handovers)
    for r in agent_regions:
        chosen.update(info.extras.get(r, ()))
    for f, item in enumerate(state.cell_item):
        if item >= 0 and terrain[f] in _HOLDERS | STATION_CODES:
            chosen.add(f)
    places = tuple(sorted(chosen))
    adjacent = []
    spot_set: set[int] = set()
    for p in places:
        for g in info.floor_around.get(p, ()):
            if region[g] in agent_regions:
                adjacent.append((g, p))
                spot_set.add(g)
    if granularity == "cells":
        spot_set.update(f for f, r in enumerate(region) if r in agent_regions)
        spot_set.update(state.agent_pos)
        spots = tuple(sorted(spot_set))
        links = tuple(
            (s, t, 1) for s in spots for t in geo.neighbors[s] if t >= 0 and t in spot_set
        )
    else:
        targets = sorted(spot_set)
        spot_set.update(state.agent_pos)
        spots = tuple(sorted(spot_set))
        links_list = []
        due = state.next_switch - state.t
        for s in spots:
            # (a cook the problem leaves out may stand where the problem has a wall)
            if real is None:
                ds = info.dist.get(s, {})
            elif due > 0:
                ds = phase_walks(real, state.rules.map_switch_step, s, li, due)
            else:
                ds = expected_walks(real, state.rules.map_switch_step, s)
            for t in targets:
                if t != s and t in ds:
                    links_list.append((s, t, ds[t]))
        links = tuple(links_list)
    layout_links: list[tuple[int, int, int, int]] = []
    if every_layout and granularity == "stations":
        period = state.rules.map_switch_step
        for layout in range(len(geo.walkables)):
            dist = layout_info(geo, layout, extra_counters).dist
            for s in spots:
                ds = dist.get(s, {})
                layout_links.extend((layout, s, t, ds[t]) for t in targets
                                    if t != s and t in ds and ds[t] < period)
    return SpotGraph(places, spots, tuple(sorted(adjacent)), links,
                     tuple(state.agent_pos), info, tuple(layout_links))


_RELAXED: dict[int, tuple[Geometry, Geometry]] = {}  # id(real) -> (real, relaxed)
_REAL: dict[int, Geometry] = {}  # id(relaxed) -> real


def relaxed_geometry(geo: Geometry) -> Geometry:
    """``geo`` with every cell that is floor in some layout as floor, in both layouts."""
    known = _RELAXED.get(id(geo))
    if known is None or known[0] is not geo:
        floor = walkable_in_any_layout(geo)
        terrain = tuple(int(Cell.FLOOR) if floor[c] else geo.terrains[0][c]
                        for c in range(len(floor)))
        relaxed = replace(geo, terrains=(terrain, terrain), walkables=(floor, floor))
        _RELAXED[id(geo)] = known = (geo, relaxed)
        _REAL[id(relaxed)] = geo
    return known[1]


def real_geometry(geo: Geometry) -> Geometry | None:
    """The switching geometry a relaxed one was made from (None: ``geo`` is not relaxed)."""
    real = _REAL.get(id(geo))
    if real is None or _RELAXED.get(id(real), (None, None))[1] is not geo:
        return None
    return real


def relaxed_state(state: State) -> State:
    """A copy of ``state`` in the relaxed kitchen (see the module doc); ``state`` itself
    when an item lies on a counter that the other layout opens (keep it real). The
    simulator state is never changed."""
    geo = state.geo
    base = relaxed_geometry(geo)
    if any(state.cell_item[c] >= 0 and base.walkables[0][c] and not geo.walkables[state.layout_index][c]
           for c in range(len(state.cell_item))):
        return state
    relaxed = state.copy()
    relaxed.geo = base
    return relaxed


def _arrivals(fronts: list[int]) -> dict[int, int]:
    """Cell -> the first step at which a list of reachability fronts holds it."""
    out: dict[int, int] = {}
    seen = 0
    for t, front in enumerate(fronts):
        new = front & ~seen
        seen |= front
        while new:
            low = new & -new
            out[low.bit_length() - 1] = t
            new ^= low
    return out


@lru_cache(maxsize=4096)
def phase_walks(geo: Geometry, period: int, start: int, layout: int, due: int) -> dict[int, int]:
    """Cell -> steps of the earliest walk from ``start`` to it on the switching map ``geo``
    when ``layout`` is in force and its next switch is ``due`` steps away, then one every
    ``period`` steps (waiting for switches allowed; cells no walk reaches are left out)."""
    walks = switching_walks(geo, period)
    return _arrivals(walks.fronts(start, layout, max(1, min(due, walks.period))))


@lru_cache(maxsize=4096)
def expected_walks(geo: Geometry, period: int, start: int) -> dict[int, int]:
    """Cell -> expected steps from ``start`` to it on the switching map ``geo`` (rounded
    mean over every phase of the switch schedule of the earliest arrival, waiting for
    switches allowed); cells some phase never reaches are left out."""
    walks = switching_walks(geo, period)
    phases = [(layout, due) for layout in range(2) for due in range(1, walks.period + 1)]
    total: dict[int, int] = {}
    reached: dict[int, int] = {}  # in how many phases
    for layout, due in phases:
        for cell, t in _arrivals(walks.fronts(start, layout, due)).items():
            total[cell] = total.get(cell, 0) + t
            reached[cell] = reached.get(cell, 0) + 1
    return {c: round(total[c] / len(phases)) for c in total if reached[c] == len(phases)}


def walk_distance(state: State, start: int, goal: int, blocked: frozenset[int]) -> int | None:
    """Steps of a shortest walk in the current layout that avoids ``blocked`` cells."""
    geo = state.geo
    d = distances(geo.neighbors, geo.walkables[state.layout_index], [start], blocked)[goal]
    return d if d >= 0 else None

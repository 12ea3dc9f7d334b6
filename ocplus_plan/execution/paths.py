"""Grid paths for the executive: memoised distances and multi-agent space-time reservations.

Agents interact by bumping a non-walkable cell from a walkable neighbour (its
*interaction spot*), so every task of the executive is "get to a spot next to
cell X, then bump X". This module answers the "get to" part for several agents
at once, with the simulator's move rules (SPEC section 5) as constraints:

- never two agents in one cell at the same time (vertex reservations);
- no swaps (edge reservations: a->b and b->a in the same step);
- an agent may wait; agents that nobody plans for (a human, another controller)
  are treated as standing still where they are.

:func:`plan_paths` is prioritised planning (one space-time A* per agent in
priority order, each avoiding the reservations of the agents planned before it).
An agent whose goal cannot be reached inside the window is given an *evasion*
path instead: it keeps out of the way of higher-priority agents and ends as close
to its goal as it can. The caller (the executive) detects lack of progress and
rotates priorities, which resolves head-on meetings in one-lane corridors.

Walkability may depend on time (``walk_at``) so that planned paths can route
around a layout switch that is known to come.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from ..errors import ConfigError
from ..sim.codes import STATIONS, Action
from ..sim.queries import (
    direction,
    distances,
    interaction_spots,
    layout_at,
    walkable_in_any_layout,
)
from ..sim.state import Geometry, State

#: walkable flags per cell for the layout in force at a relative time step
WalkAt = Callable[[int], Sequence[bool]]


# ------------------------------------------------------------------ static geometry
class DistanceOracle:
    """Memoised BFS distances per (layout, goal set): the executive asks the same ones a lot."""

    def __init__(self, geo: Geometry) -> None:
        self.geo = geo
        self._cache: dict[tuple[int, frozenset[int]], list[int]] = {}

    def to_goals(self, layout_index: int, goals: Iterable[int]) -> list[int]:
        key = (layout_index, frozenset(goals))
        d = self._cache.get(key)
        if d is None:
            d = distances(self.geo.neighbors, self.geo.walkables[layout_index], key[1])
            self._cache[key] = d
        return d

    def to_station(self, layout_index: int, cell: int) -> list[int]:
        """Distance of every cell to the nearest interaction spot of ``cell`` (-1: none)."""
        spots = interaction_spots(self.geo.neighbors, self.geo.walkables[layout_index], cell)
        return self.to_goals(layout_index, spots) if spots else [-1] * len(self.geo.neighbors)


def layout_connects(geo: Geometry, layout: int, cooks: Sequence[int]) -> bool:
    """Can the cooks at cells ``cooks``, between them, reach every station of the kitchen
    in ``layout`` (each station from some cook)?"""
    walk = geo.walkables[layout]
    reach = distances(geo.neighbors, walk, [p for p in cooks if walk[p]])
    return all(any(reach[spot] >= 0 for spot in interaction_spots(geo.neighbors, walk, cell))
               for cell, code in enumerate(geo.terrains[layout]) if code in STATIONS)


def hub_cells(geo: Geometry) -> frozenset[int]:
    """Floor cells (walkable in every layout) from which the most stations can be reached,
    summed over the layouts: where an agent with nothing to do waits on a map whose
    layout switches, so that it is not cut off from the work after the next switch."""
    stations = [c for c, v in enumerate(geo.terrains[0]) if v in STATIONS]
    n = geo.rows * geo.cols
    score = [0] * n
    for walk in geo.walkables:
        for st in stations:
            spots = interaction_spots(geo.neighbors, walk, st)
            if not spots:
                continue
            for c, d in enumerate(distances(geo.neighbors, walk, spots)):
                if d >= 0:
                    score[c] += 1
    floor = [c for c in range(n) if all(w[c] for w in geo.walkables)]
    best = max((score[c] for c in floor), default=0)
    return frozenset(c for c in floor if score[c] == best)


def one_lane(geo: Geometry, walk: Sequence[bool], cells: Iterable[int]) -> bool:
    """Is the floor the cooks on ``cells`` stand on one path (a lane: no cell with more than
    two floor neighbours, no loop)? There nobody can pass anybody, and a plan in which
    cooks jump past each other (stations granularity) cannot be done."""
    near = distances(geo.neighbors, walk, cells)
    floor = [c for c, d in enumerate(near) if d >= 0]
    degree = [sum(1 for n in geo.neighbors[c] if n >= 0 and walk[n]) for c in floor]
    return len(floor) > 1 and max(degree) <= 2 and sum(degree) == 2 * (len(floor) - 1)


def cooks_in_one_lane(state: State, agents: Sequence[int]) -> bool:
    """Do two or more of ``agents`` stand on one lane (:func:`one_lane`) of a static kitchen?
    The planning step then plans them with cells."""
    geo = state.geo
    return len(agents) > 1 and not state.rules.dynamic and one_lane(
        geo, geo.walkables[state.layout_index], [state.agent_pos[a] for a in agents])


def layout_schedule(state: State, anticipate: bool) -> WalkAt:
    """Walkability over relative time: the current layout, or (``anticipate``) the layout
    after the next due switch from the step it is due on (``state.next_switch``)."""
    geo = state.geo
    now = geo.walkables[state.layout_index]
    if not anticipate or not state.rules.dynamic or len(geo.walkables) < 2:
        return lambda t: now
    due = max(0, state.next_switch - state.t)
    period = state.rules.map_switch_step
    layout = state.layout_index

    def walk_at(t: int) -> Sequence[bool]:
        return geo.walkables[layout_at(layout, due, period, t)]

    return walk_at


# ------------------------------------------------------------------ reservations
@dataclass
class Reservations:
    """Cells (and moves) taken by already planned agents at each relative time step."""

    horizon: int
    vertex: dict[tuple[int, int], int] = field(default_factory=dict)  # (cell, t) -> agent
    edge: set[tuple[int, int, int]] = field(default_factory=set)  # (from, to, t): move t -> t+1
    #: cells held from some time on until the end of the window (parked agents)
    parked: dict[int, int] = field(default_factory=dict)  # cell -> first t held

    def free(self, cell: int, t: int) -> bool:
        if (cell, t) in self.vertex:
            return False
        p = self.parked.get(cell)
        return p is None or t < p

    def free_from(self, cell: int, t: int) -> bool:
        """Free at ``t`` and every later step of the window (a place to park)."""
        if cell in self.parked:
            return False
        return all((cell, u) not in self.vertex for u in range(t, self.horizon + 1))

    def can_move(self, src: int, dst: int, t: int) -> bool:
        """Move src -> dst between t and t+1: dst free at t+1 and nobody moving dst -> src."""
        return self.free(dst, t + 1) and (dst, src, t) not in self.edge

    def add_path(self, agent: int, path: Sequence[int]) -> None:
        """Reserve ``path`` (cell per step from t=0); the last cell stays held afterwards."""
        for t, c in enumerate(path):
            self.vertex[(c, t)] = agent
            if t + 1 < len(path) and path[t + 1] != c:
                self.edge.add((c, path[t + 1], t))
        last = path[-1]
        self.parked[last] = min(self.parked.get(last, len(path) - 1), len(path) - 1)

    def add_static(self, agent: int, cell: int) -> None:
        """An agent nobody plans for: assumed to stay where it is for the whole window."""
        self.vertex[(cell, 0)] = agent
        self.parked[cell] = 0


@dataclass(frozen=True)
class PathRequest:
    """One agent to route: from ``start`` to any of ``goals`` (empty: just keep out of the way)."""

    agent: int
    start: int
    goals: frozenset[int]


@dataclass
class PathResult:
    agent: int
    path: list[int]  # cell at relative t = 0, 1, ...; path[0] == start
    reached: bool  # the path ends on a goal (False: an evasion / waiting path)
    #: the agent can follow the path and then stay, for the whole window, without conflict
    safe: bool = True

    def next_action(self, geo: Geometry) -> int:
        if len(self.path) < 2:
            return int(Action.STAY)
        return direction(geo, self.path[0], self.path[1])


def _heuristic(geo: Geometry, walk: Sequence[bool], goals: frozenset[int]) -> list[int]:
    d = distances(geo.neighbors, walk, goals)
    big = geo.rows * geo.cols
    return [big if v < 0 else v for v in d]


def _window_heuristic(geo: Geometry, walk_at: WalkAt, goals: frozenset[int], start: int,
                      horizon: int) -> list[int]:
    """Distances to ``goals`` in the layout at relative time 0; when that layout cuts
    ``start`` off them and the layout switches inside the window, over every cell walkable
    in some layout instead (a lower bound on any walk that waits for a switch, so the
    search stays admissible)."""
    now = walk_at(0)
    h = _heuristic(geo, now, goals)
    if h[start] < geo.rows * geo.cols or all(walk_at(t) is now for t in range(1, horizon + 1)):
        return h
    return _heuristic(geo, walkable_in_any_layout(geo), goals)


def space_time_astar(
    geo: Geometry, walk_at: WalkAt, request: PathRequest, res: Reservations,
    soft: Mapping[int, int] | None = None,
) -> PathResult:
    """Earliest path from ``request.start`` to a goal where the agent can then stay.

    ``soft`` maps cells to an extra cost (cells where not-yet-planned agents stand,
    so a higher-priority agent prefers to go around them when it can). Falls back
    to :func:`evasion_path` when no goal can be reached inside the window.
    """
    goals = request.goals
    start = request.start
    if not goals:
        return evasion_path(geo, walk_at, request, res)
    horizon = res.horizon
    h = _window_heuristic(geo, walk_at, goals, start, horizon)
    soft = soft or {}
    nbrs = geo.neighbors
    # node: (f, g, tie, cell, t); g counts time steps plus soft penalties
    tie = 0
    openq: list[tuple[int, int, int, int, int]] = [(h[start], 0, tie, start, 0)]
    parent: dict[tuple[int, int], tuple[int, int] | None] = {(start, 0): None}
    best_g: dict[tuple[int, int], int] = {(start, 0): 0}
    while openq:
        _f, g, _tie, cell, t = heapq.heappop(openq)
        if best_g.get((cell, t), 1 << 30) < g:
            continue
        if cell in goals and res.free_from(cell, t):
            return PathResult(request.agent, _unwind(parent, (cell, t)), True)
        if t >= horizon:
            continue
        walk = walk_at(t + 1)
        for nb in (*nbrs[cell], cell):
            if nb < 0 or not walk[nb]:
                continue
            if nb == cell:
                if not res.free(cell, t + 1):
                    continue
            elif not res.can_move(cell, nb, t):
                continue
            ng = g + 1 + soft.get(nb, 0)
            key = (nb, t + 1)
            if ng < best_g.get(key, 1 << 30):
                best_g[key] = ng
                parent[key] = (cell, t)
                tie += 1
                heapq.heappush(openq, (ng + h[nb], ng, tie, nb, t + 1))
    return evasion_path(geo, walk_at, request, res)


def evasion_path(
    geo: Geometry, walk_at: WalkAt, request: PathRequest, res: Reservations
) -> PathResult:
    """A path that avoids every reservation for the whole window and ends as close to the
    goals as possible (or, with no goals, as close to the start: step aside, not away).

    If even that is impossible (cornered), the agent stays (the move rules keep it safe).
    """
    horizon = res.horizon
    start = request.start
    ref = request.goals or frozenset({start})
    h = _window_heuristic(geo, walk_at, ref, start, horizon)
    nbrs = geo.neighbors
    layer = {start: None}
    parents: list[dict[int, int | None]] = [layer]
    for t in range(horizon):
        walk = walk_at(t + 1)
        nxt: dict[int, int | None] = {}
        for cell in layer:
            for nb in (cell, *nbrs[cell]):
                if nb < 0 or nb in nxt or not walk[nb]:
                    continue
                if nb == cell:
                    if res.free(cell, t + 1):
                        nxt[nb] = cell
                elif res.can_move(cell, nb, t):
                    nxt[nb] = cell
        if not nxt:
            break
        parents.append(nxt)
        layer = nxt
    # prefer a survivor of the last layer that can stay; else the latest survivor
    t_end = len(parents) - 1
    candidates = [c for c in parents[t_end] if res.free_from(c, t_end)]
    safe = bool(candidates) and t_end == horizon
    candidates = candidates or list(parents[t_end])
    best = min(candidates, key=lambda c: (h[c], c != start))
    # get there as early as it is safe to stay there (each layer keeps the first parent
    # found, a wait: unwound from the window's end the walk would start at the last moment,
    # and a cook replanned every step would never leave)
    if res.free_from(best, t_end):
        t_end = next(t for t in range(t_end + 1) if best in parents[t] and res.free_from(best, t))
    path = [best]
    for t in range(t_end, 0, -1):
        path.append(parents[t][path[-1]])  # type: ignore[arg-type]
    path.reverse()
    # trim the trailing waits so the reservation parks at the first arrival
    while len(path) > 1 and path[-1] == path[-2]:
        path.pop()
    return PathResult(request.agent, path, best in request.goals, safe)


def _unwind(parent: dict[tuple[int, int], tuple[int, int] | None], node: tuple[int, int]) -> list[int]:
    out = []
    cur: tuple[int, int] | None = node
    while cur is not None:
        out.append(cur[0])
        cur = parent[cur]
    out.reverse()
    return out


def plan_paths(
    geo: Geometry,
    requests: Sequence[PathRequest],
    others: Mapping[int, int | Sequence[int]] | None = None,
    *,
    horizon: int = 40,
    walk_at: WalkAt | None = None,
    layout_index: int = 0,
    soft_penalty: int = 2,
) -> dict[int, PathResult]:
    """Prioritised space-time planning: ``requests`` in priority order (first = highest).

    ``others`` maps agents nobody plans for to their cell (assumed to stay), or to the walk
    they are predicted to take (cells per step from now; the last one held after). Returns
    one :class:`PathResult` per request; no two results occupy one cell at one
    step or swap cells, and none enters a cell held by ``others``.
    """
    if horizon < 1:
        raise ConfigError(f"path horizon must be >= 1, got {horizon}")
    walk_at = walk_at or (lambda t, w=geo.walkables[layout_index]: w)
    starts = [r.start for r in requests]
    if len(set(starts)) != len(starts):
        raise ConfigError(f"two path requests start on the same cell: {starts}")
    order = list(requests)
    best: tuple[int, dict[int, PathResult]] | None = None
    # prioritised planning is incomplete: when an agent is left without a safe path (it is
    # in the way of a higher-priority agent and cannot step aside in time), plan it first,
    # towards the nearest cell off the others' routes (a pocket), and try again
    for _attempt in range(len(requests) + 1):
        out, unsafe, used = _plan_in_order(geo, order, others, horizon, walk_at, soft_penalty)
        if best is None or len(unsafe) < best[0]:
            best = (len(unsafe), out)
        if not unsafe:
            break
        j = unsafe[0]
        req = next(r for r in order if r.agent == j)
        pockets = _pockets(geo, walk_at(0), req.start, used[j])
        rest = [r for r in order if r.agent != j]
        first = PathRequest(j, req.start, pockets) if pockets else req
        order = [first, *rest]
    assert best is not None
    # report against the original goals
    for req in requests:
        r = best[1][req.agent]
        r.reached = r.path[-1] in req.goals
    return best[1]


def _plan_in_order(
    geo: Geometry, order: Sequence[PathRequest], others: Mapping[int, int | Sequence[int]] | None,
    horizon: int, walk_at: WalkAt, soft_penalty: int,
) -> tuple[dict[int, PathResult], list[int], dict[int, set[int]]]:
    res = Reservations(horizon)
    for agent, cell in (others or {}).items():
        if isinstance(cell, int):
            res.add_static(agent, cell)
        else:
            res.add_path(agent, cell)
    out: dict[int, PathResult] = {}
    unsafe: list[int] = []
    used: dict[int, set[int]] = {}  # agent -> cells on the paths planned before it
    taken: set[int] = set()
    for i, req in enumerate(order):
        # lower-priority agents still stand where they are: a soft cost keeps us off their
        # cells when a detour exists (stepping onto a cell its occupant leaves in the same
        # step is allowed by the move rules; if it cannot leave, the move is merely blocked)
        soft = {r.start: soft_penalty for r in order[i + 1:]}
        result = space_time_astar(geo, walk_at, req, res, soft)
        used[req.agent] = set(taken)
        taken.update(result.path)
        if not result.safe:
            unsafe.append(req.agent)
        res.add_path(req.agent, result.path)
        out[req.agent] = result
    return out, unsafe, used


def _pockets(geo: Geometry, walk: Sequence[bool], start: int, avoid: set[int]) -> frozenset[int]:
    """Walkable cells reachable from ``start`` that are off the cells in ``avoid``."""
    dist = distances(geo.neighbors, walk, [start])
    return frozenset(c for c, d in enumerate(dist) if d >= 0 and c not in avoid and c != start)


def check_paths(paths: Mapping[int, Sequence[int]], others: Mapping[int, int] | None = None) -> list[str]:
    """Every conflict between planned paths (empty = none): shared cells, swaps, standing
    agents entered. Paths are extended by waiting at their last cell."""
    problems = []
    length = max((len(p) for p in paths.values()), default=0)

    def at(p: Sequence[int], t: int) -> int:
        return p[min(t, len(p) - 1)]

    agents = sorted(paths)
    for t in range(length):
        seen: dict[int, int] = {}
        for a in agents:
            c = at(paths[a], t)
            if c in seen:
                problems.append(f"t={t}: agents {seen[c]} and {a} both on cell {c}")
            seen[c] = a
            for o, oc in (others or {}).items():
                if c == oc:
                    problems.append(f"t={t}: agent {a} on cell {c} held by agent {o}")
        for i, a in enumerate(agents):
            for b in agents[i + 1:]:
                if t + 1 < length and at(paths[a], t) == at(paths[b], t + 1) and \
                        at(paths[b], t) == at(paths[a], t + 1) and at(paths[a], t) != at(paths[a], t + 1):
                    problems.append(f"t={t}: agents {a} and {b} swap cells")
    return problems


__all__ = [
    "DistanceOracle",
    "PathRequest",
    "PathResult",
    "Reservations",
    "check_paths",
    "cooks_in_one_lane",
    "evasion_path",
    "hub_cells",
    "layout_schedule",
    "one_lane",
    "plan_paths",
    "space_time_astar",
]

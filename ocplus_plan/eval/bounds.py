"""Bounds: an upper bound on the dishes of an episode, lower bounds on a plan's quality.

:func:`dish_bound` (below) bounds the dishes a team can serve in an episode;
:func:`plan_bound` bounds the cost (classical) and the makespan (temporal) of any
plan of the planning model for a state's first orders (its docstring says why).

The dish bound:

The bound relaxes the game until it is easy to solve exactly, so no controller can
beat it on the same rules and horizon (the evaluation's ``bound_ratio`` is only
meaningful if that holds; ``tests/eval/test_bounds.py`` checks it against the
greedy cook and the optimal planner).

One dish of recipe R costs one agent at least

* its **bumps**: per ingredient a pick at its spawn tile, a put on its station,
  ``chop_steps`` chops for a vegetable (cooking is passive, so 0 for a steak) and
  one bump to get it onto the plate; one bump to pick the plate, one to serve;
  with dirty plates one to pick the dirty plate, one to drop it in the sink,
  ``wash_steps`` washes;
* its **walk**: the agent must stand next to every tile the dish needs (each
  ingredient's spawn tile and station, the plate tile, the sink, the serving
  window). The bound takes the shortest closed tour through one tile of each of
  those *visits, in any order* (Held-Karp over the visits, choosing the tile of
  each), between interaction spots, over the cells walkable in *any* layout.
  Any order includes the orders the rules forbid, and the union of layouts
  includes paths no single layout has, so the tour is never longer than a real
  walk.

Waiting for a pan, other agents, order arrival and respawn delays are ignored.
One agent's first dish is an open tour from its spawn cell (clean plates, no
sink) ending at the serving window; after it, each dish costs at least the
cheapest closed cycle. For ``n`` agents the bound is the sum of each agent's
bound (perfect parallelism with no shared-resource conflicts). That sum assumes
no agent shortens another's walk by handing items over a counter (which the tour
does not cover); the built-in controllers never beat it (tested for the greedy
cook).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache

from ..sim.codes import COUNTERS, VEGETABLES, Cell, Item, ItemState, Where
from ..sim.processes import process_tables
from ..sim.queries import distances, interaction_spots, walkable_in_any_layout
from ..sim.rules import Recipe, Rules
from ..sim.state import Geometry, State, geometry_for

_INF = float("inf")


@dataclass(frozen=True)
class DishBound:
    """The bound and its parts, for reports."""

    dishes: int  # no team serves more dishes than this in ``steps`` steps
    steps: int
    cycles: dict[str, int]  # recipe -> steps per dish after an agent's first
    first: tuple[int, ...]  # per agent: fewest steps to its first dish (-1: never)
    orders: str  # "seeded" (the episode's own order stream) or "cheapest" (pool minimum)

    def ratio(self, served: float) -> float:
        return served / self.dishes if self.dishes else 0.0


def _cells(geo: Geometry, code: int) -> list[int]:
    return [c for c, v in enumerate(geo.terrains[0]) if v == code]


def _station_cells(geo: Geometry, kind: int) -> list[int]:
    return list(geo.pans) if kind == Item.STEAK else _cells(geo, Cell.BOARD)


def bumps_per_dish(rules: Rules, recipe: Recipe, dirty: bool) -> int:
    """The fewest bumps one dish of ``recipe`` takes (see the module docstring)."""
    tables = process_tables(rules)  # bump-driven work counts; time-driven (cooking) is passive
    bumps = 2  # pick the plate, serve
    if dirty:
        bumps += 2 + tables.work(Item.PLATE)
    for kind in recipe:
        j = tables.index_of(kind)
        bumps += 3 + (tables.duration[j] if j >= 0 and not tables.timed[j] else 0)
    return bumps


class _Tours:
    """Walking distances between tiles (spot to spot, union of layouts) and tours."""

    def __init__(self, geo: Geometry) -> None:
        self.geo = geo
        self.walk = walkable_in_any_layout(geo)
        self._from: dict[int, list[int]] = {}
        self._between: dict[tuple[int, int], float] = {}

    def spots(self, cell: int) -> list[int]:
        return interaction_spots(self.geo.neighbors, self.walk, cell)

    def dist(self, src: int, tile: int) -> float:
        """Fewest steps from the floor cell ``src`` to a spot next to ``tile``."""
        if src not in self._from:
            self._from[src] = distances(self.geo.neighbors, self.walk, [src])
        d = self._from[src]
        return min((d[s] for s in self.spots(tile) if d[s] >= 0), default=_INF)

    def between(self, a: int, b: int) -> float:
        """Fewest steps from a spot next to tile ``a`` to a spot next to tile ``b``."""
        key = (a, b)
        if key not in self._between:
            self._between[key] = min((self.dist(s, b) for s in self.spots(a)), default=_INF)
        return self._between[key]

    def tour(self, visits: Sequence[Sequence[int]], start: int | None, end: Sequence[int]) -> float:
        """Shortest walk through one tile of every visit, in any order.

        ``start`` None: a closed tour that starts and ends at one tile of ``end``;
        else an open walk from the floor cell ``start`` ending next to a tile of ``end``.
        """
        best = _INF
        for home in (end if start is None else [None]):
            best = min(best, self._held_karp(visits, start, home, end))
        return best

    def _held_karp(self, visits: Sequence[Sequence[int]], start: int | None,
                   home: int | None, end: Sequence[int]) -> float:
        dp = self.walks(visits, lambda t: self.between(home, t) if home is not None
                        else self.dist(start, t))  # type: ignore[arg-type]
        full = (1 << len(visits)) - 1
        finish = [home] if home is not None else list(end)
        return min((dp.get((full, t), _INF) + self.between(t, f)
                    for i, tiles in enumerate(visits) for t in tiles for f in finish),
                   default=_INF)

    def walks(self, visits: Sequence[Sequence[int]],
              first: Callable[[int], float]) -> dict[tuple[int, int], float]:
        """Held-Karp: ``dp[(mask, tile)]`` is the shortest walk that reaches ``tile`` (one
        of the last visit's tiles) after standing next to one tile of every visit in
        ``mask``, in any order; ``first(t)`` is the walk to the first visit's tile ``t``."""
        dp: dict[tuple[int, int], float] = {}
        for i, tiles in enumerate(visits):
            for t in tiles:
                key = (1 << i, t)
                dp[key] = min(dp.get(key, _INF), first(t))
        for mask in range(1, 1 << len(visits)):
            for i, tiles in enumerate(visits):
                if not mask & (1 << i):
                    continue
                for t in tiles:
                    here = dp.get((mask, t), _INF)
                    if here == _INF:
                        continue
                    for j, nxt in enumerate(visits):
                        if mask & (1 << j):
                            continue
                        for u in nxt:
                            key = (mask | (1 << j), u)
                            dp[key] = min(dp.get(key, _INF), here + self.between(t, u))
        return dp


def _visits(geo: Geometry, recipe: Recipe, dirty: bool) -> list[list[int]]:
    visits = [_cells(geo, Cell.PLATE)]
    if dirty:
        visits.append(_cells(geo, Cell.SINK))
    for kind in recipe:
        visits.append(_cells(geo, int(kind)))
        visits.append(_station_cells(geo, int(kind)))
    return visits


def dish_bound(rules: Rules, steps: int | None = None, seed: int | None = None) -> DishBound:
    """Upper bound on the dishes ``rules.n_agents`` agents serve in ``steps`` steps
    (default: the horizon).

    With ``seed`` (and no order time limit) the bound follows the episode's own
    order stream: orders are drawn from a seeded RNG that nothing else consumes, so
    the recipes of the first draws are known; ``K`` dishes need ``K`` of the first
    ``K + n_orders`` draws, at best the cheapest ``K`` of them. Without a seed (or
    when orders expire, which draws extra orders) every dish is priced at the
    cheapest recipe of the pool.
    """
    steps = rules.horizon if steps is None else steps
    cycles, firsts = _costs(rules)
    recipes = rules.recipes
    budget, per_agent = 0.0, 0
    for a in range(rules.n_agents):
        first = min(firsts[r][a] for r in recipes)
        if first > steps:
            continue
        gain = max(0.0, max(cycles[r] - firsts[r][a] for r in recipes if firsts[r][a] < _INF))
        budget += steps + gain
        cheapest = min(cycles.values())
        per_agent += 1 + (int((steps - first) // cheapest) if cheapest < _INF else 0)
    if seed is not None and rules.order_time_limit is None:
        costs, kind = _stream_costs(rules, seed, cycles, per_agent + rules.n_orders), "seeded"
    else:
        costs, kind = [min(cycles.values())] * (per_agent + rules.n_orders), "cheapest"
    dishes = 0
    for k in range(1, per_agent + 1):
        if sum(sorted(costs[: k + rules.n_orders])[:k]) > budget:
            break
        dishes = k
    return DishBound(dishes, steps, {rules.recipe_name(r): _steps(c) for r, c in cycles.items()},
                     tuple(_steps(min(firsts[r][a] for r in recipes))
                           for a in range(rules.n_agents)), kind)


@lru_cache(maxsize=64)
def _costs(rules: Rules) -> tuple[dict[Recipe, float], dict[Recipe, list[float]]]:
    """Per recipe: the steps of one dish after the first, and each agent's first dish."""
    geo = geometry_for(rules)
    tours = _Tours(geo)
    delivery = _cells(geo, Cell.DELIVERY)
    cycles: dict[Recipe, float] = {}
    firsts: dict[Recipe, list[float]] = {}
    for recipe in rules.recipes:
        walk = tours.tour(_visits(geo, recipe, rules.dirty_plates), None, delivery)
        cycles[recipe] = walk + bumps_per_dish(rules, recipe, rules.dirty_plates)
        firsts[recipe] = [tours.tour(_visits(geo, recipe, False), pos, delivery)
                          + bumps_per_dish(rules, recipe, False)
                          for pos in _spawn_cells(rules, geo)]
    return cycles, firsts


def _stream_costs(rules: Rules, seed: int, cycles: dict[Recipe, float], n: int) -> list[float]:
    """The dish cost of each of the episode's first ``n`` orders, in draw order."""
    from ..sim.orders import draw_order
    from ..sim.state import new_state

    state = new_state(rules, seed)
    while len(state.orders) < n:
        draw_order(state)
    return [cycles[o.recipe] for o in state.orders[:n]]


def _steps(x: float) -> int:
    """A step count for reports; -1 when unreachable."""
    return int(x) if x < _INF else -1


def _spawn_cells(rules: Rules, geo: Geometry) -> list[int]:
    return [geo.flat(r, c) for r, c in rules.layout.spawn_points[: rules.n_agents]]


# ------------------------------------------------------------ plan quality bound

#: tiles an item can be handed over across (put on one side, picked from the other)
_HAND_OVER = frozenset(int(c) for c in COUNTERS) | {int(Cell.BOARD), int(Cell.PAN),
                                                     int(Cell.SINK)}


@dataclass(frozen=True)
class PlanBound:
    """Lower bounds on the quality of any plan of the planning model (see :func:`plan_bound`).

    ``cost``: classical (sum of action costs); ``makespan``: temporal. Both are
    ``inf`` when some order cannot be made at all. The parts are for reports.
    """

    cost: float
    makespan: float
    walk: float  # fewest move steps of all cooks together
    work_classical: int  # fewest non-move steps, classical costs (cook = cook_time + 1)
    work_temporal: int  # the same with the temporal cook (two one-step pan bumps)
    critical_path: float  # the longest order's chain of dependent steps
    orders: tuple[int, ...]
    n_agents: int


class _Paths(_Tours):
    """:class:`_Tours` plus how fast an *item* travels: carried over floor (1 per step) or
    handed over a counter, board, pan or sink (1: the put and the pick take 2)."""

    def __init__(self, geo: Geometry) -> None:
        super().__init__(geo)
        # the grid's neighbours plus, from each spot of a hand-over tile, its other spots
        hops: list[list[int]] = [list(nbrs) for nbrs in geo.neighbors]
        for c in range(len(hops)):  # a hand-over tile in any layout (a switch cell may be one)
            if any(t[c] in _HAND_OVER for t in geo.terrains):
                around = self.spots(c)
                for x in around:
                    hops[x].extend(y for y in around if y != x)
        self.item_steps = tuple(tuple(h) for h in hops)
        self._carry: dict[int, list[int]] = {}

    def carry(self, src: int, tile: int) -> float:
        """Fewest steps for an item held at floor cell ``src`` to reach a spot of ``tile``."""
        if src not in self._carry:
            self._carry[src] = distances(self.item_steps, self.walk, [src])
        d = self._carry[src]
        return min((d[s] for s in self.spots(tile) if d[s] >= 0), default=_INF)

    def carry_between(self, a: int, b: int) -> float:
        return min((self.carry(s, b) for s in self.spots(a)), default=_INF)

    def cover(self, start: int, visits: Sequence[Sequence[int]]) -> list[float]:
        """Per subset (bit mask) of ``visits``: the shortest walk from ``start`` that stands
        next to one tile of each, in any order, ending anywhere."""
        best = [0.0] + [_INF] * ((1 << len(visits)) - 1)
        for (mask, _), d in self.walks(visits, lambda t: self.dist(start, t)).items():
            best[mask] = min(best[mask], d)
        return best


@lru_cache(maxsize=64)
def _paths(geo: Geometry) -> _Paths:
    return _Paths(geo)


class _ItemCosts:
    """What it takes to bring one item of ``state`` onto a dish and the dish to the
    window: the work (classical, temporal) and the chain of dependent steps
    (see :func:`plan_bound`, **Work** and **Critical path**)."""

    def __init__(self, state: State, paths: _Paths) -> None:
        self.state, self.rules, self.geo, self.paths = state, state.rules, state.geo, paths
        self.terrain = state.geo.terrains[state.layout_index]
        self.agents = list(range(state.n_agents))
        self.delivery = _cells(state.geo, Cell.DELIVERY)

    def tile_of(self, i: int) -> int | None:  # the tile an item lies on; None: in a hand
        where, loc = self.state.item_where[i], self.state.item_loc[i]
        if where == Where.HAND:
            return None
        if where == Where.PLATE:
            return self.tile_of(loc)
        return loc  # CELL or WAITING (its spawn tile)

    def reach(self, tile: int) -> float:
        pos = self.state.agent_pos
        return min((self.paths.dist(pos[a], tile) for a in self.agents), default=_INF)

    def to_window(self, start_tile: int | None, holder: int) -> float:
        """Carry to the serving window from a tile (or from the cell of ``holder``)."""
        return min(self.carry(start_tile, holder, d) for d in self.delivery)

    def carry(self, tile: int | None, holder: int, dest: int) -> float:
        return (self.paths.carry_between(tile, dest) if tile is not None
                else self.paths.carry(self.state.agent_pos[holder], dest))

    def ingredient(self, i: int) -> tuple[int, int, float]:
        """(classical work, temporal work, chain) of getting item ``i`` onto the dish."""
        state, geo, paths = self.state, self.geo, self.paths
        kind, st, prog = geo.item_kind[i], state.item_state[i], state.item_progress[i]
        where, tile = state.item_where[i], self.tile_of(i)
        holder = state.item_loc[i] if where == Where.HAND else -1
        if where == Where.PLATE:
            return 0, 0, 0.0
        if st == ItemState.BURNT:  # trashed, it starts again fresh from its spawn tile
            tile, holder, where, prog = geo.item_home[i], -1, Where.CELL, 0
            st = ItemState.FRESH
        on = self.terrain[tile] if tile is not None and where == Where.CELL else -1
        if on == Cell.PAN and kind == Item.STEAK:  # heating: take it off in its window
            wait = max(0, self.rules.tables.work(kind) - prog)
            return 2, 2, max(self.reach(tile), wait) + 2 + self.to_window(tile, holder) + 1
        got = 0.0 if tile is None else self.reach(tile)
        if st in (ItemState.CHOPPED, ItemState.COOKED):
            return 1, 1, got + 1 + self.to_window(tile, holder) + 1
        pick = 0 if tile is None or on == Cell.BOARD else 1
        if kind == Item.STEAK:
            left = max(0, self.rules.tables.work(kind) - prog)  # classical cook: left + 1 steps
            chains = [got + pick + self.carry(tile, holder, p) + max(1, left) + 1 + 1
                      + paths.carry_between(p, d) + 1 for p in geo.pans for d in self.delivery]
            return pick + left + 1 + 1, pick + 2 + 1, min(chains, default=_INF)
        full = self.rules.tables.work(kind)
        chop = max(1, full - prog) if prog > 0 else full
        boards = [tile] if on == Cell.BOARD else _cells(geo, Cell.BOARD)
        put = 0 if on == Cell.BOARD else 1
        chains = [got + pick + (0 if b == tile else self.carry(tile, holder, b)) + put + chop + 1
                  + paths.carry_between(b, d) + 1 for b in boards for d in self.delivery]
        work = pick + put + chop + 1
        return work, work, min(chains, default=_INF)

    def plate(self, q: int) -> tuple[int, float]:
        """(work, chain) of bringing plate ``q`` to the window (plating not included)."""
        state, geo, paths = self.state, self.geo, self.paths
        where, tile = state.item_where[q], self.tile_of(q)
        holder = state.item_loc[q] if where == Where.HAND else -1
        got = 0.0 if tile is None else self.reach(tile) + 1
        pick = 0 if tile is None else 1
        if state.item_state[q] != ItemState.DIRTY:
            return pick + 1, got + self.to_window(tile, holder) + 1
        prog = state.item_progress[q]
        full = self.rules.tables.work(Item.PLATE)
        wash = max(1, full - prog) if prog > 0 else full
        in_sink = tile is not None and where == Where.CELL and self.terrain[tile] == Cell.SINK
        if in_sink:
            return wash + 2, self.reach(tile) + wash + 1 + self.to_window(tile, holder) + 1
        chains = [got + self.carry(tile, holder, k) + 1 + wash + 1 + paths.carry_between(k, d) + 1
                  for k in _cells(geo, Cell.SINK) for d in self.delivery]
        return pick + 1 + wash + 1 + 1, min(chains, default=_INF)


def plan_bound(state: State, max_orders: int | None = None) -> PlanBound:
    """Lower bounds on the cost and the makespan of any plan that serves the first
    ``max_orders`` open orders of ``state`` (all by default) with its cooks.

    Why no plan of the planning model (``planning/model.py``, either granularity,
    with or without anticipated switches) does better. Every move costs its walking
    distance in one layout, never less than the distance over the cells walkable in
    *any* layout used here; every other action costs its steps: pick, put, plating,
    deliver, take-off 1, ``chop_steps`` (or what is left) per chop, ``wash_steps`` per
    wash, a classical cook ``cook_time + 1``, a temporal cook two one-step pan bumps
    around ``cook_time`` (or what is left) of waiting.

    * **Work.** Each order's dish needs, per ingredient, the cheapest remaining steps of
      any item of that kind (a fresh vegetable: pick, put on a board, chop, plate it; a
      raw steak: pick, cook, plate it; a ready one: plate it; one on a plate: nothing)
      and a plate (pick it, deliver; a dirty one also goes through the sink). Distinct
      dishes need distinct actions, and taking the cheapest item for every dish can
      only undercount (two dishes may not both use the one chopped tomato).
    * **Walk.** Some cook must stand next to each place the orders need (a tile of each
      needed kind, a board if no needed vegetable is chopped, a pan if no steak is
      cooked, a plate unless one is held, the sink when every plate is dirty, the
      serving window). Each cook's walk is at least the shortest path from where it
      stands through the places it visits, in any order; the bound takes the best
      split of the places between the cooks.
    * **Critical path** of an order: per ingredient, the nearest cook walks to it, then
      the item is picked, carried (handing it over a counter counts 1 step, half of its
      real put + pick) to its station, processed (a cook waits at least ``cook_time``,
      or what is left), plated, carried on to the window and served; the plate's own
      chain likewise. These steps depend on each other, so they cannot overlap in any
      schedule, and each is at least the cost of the actions that make it.
    * **cost** >= walk + classical work (every step of every cook is an action cost),
      and >= every order's critical path (its actions are among the plan's).
    * **makespan** >= ceil((walk + temporal work) / cooks): a cook does one action at a
      time and each cook's busy time is a whole number of steps; and >= every order's
      critical path.

    Respawn waits, other cooks in the way, the order of orders and the contention for
    items, plates and stations are ignored: each only makes real plans longer.
    """
    geo = state.geo
    orders = list(state.orders if max_orders is None else state.orders[:max_orders])
    paths = _paths(geo)
    item_costs = _ItemCosts(state, paths)
    items_of: dict[int, list[int]] = {}
    for i, k in enumerate(geo.item_kind):
        items_of.setdefault(k, []).append(i)
    plates = items_of.get(int(Item.PLATE), [])
    costs = {i: item_costs.ingredient(i)
             for k, its in items_of.items() if k != Item.PLATE for i in its}
    plate_costs = [item_costs.plate(q) for q in plates]
    work_c = work_t = 0
    critical = 0.0
    for order in orders:
        chain = min((c for _, c in plate_costs), default=_INF)
        work_c += min((w for w, _ in plate_costs), default=0)
        work_t += min((w for w, _ in plate_costs), default=0)
        for kind in order.recipe:
            options = [costs[i] for i in items_of.get(int(kind), [])]
            if not options:
                chain = _INF
                continue
            work_c += min(o[0] for o in options)
            work_t += min(o[1] for o in options)
            chain = max(chain, min(o[2] for o in options))
        critical = max(critical, chain)
    walk = _walk_bound(state, paths, orders, items_of) if orders else 0.0
    cost = max(walk + work_c, critical)
    makespan = max(critical, math.ceil((walk + work_t) / max(1, state.n_agents))
                   if walk < _INF else _INF)
    return PlanBound(float(cost), float(makespan), walk, work_c, work_t, float(critical),
                     tuple(o.order_id for o in orders), state.n_agents)


def _walk_bound(state: State, paths: _Paths, orders: list, items_of: dict[int, list[int]]) -> float:
    """Fewest move steps of all cooks together (see :func:`plan_bound`, **Walk**)."""
    geo = state.geo
    where, st = state.item_where, state.item_state

    def tiles(its: list[int]) -> list[int] | None:  # None: one is in a hand or on a plate
        if any(where[i] in (Where.HAND, Where.PLATE) for i in its):
            return None
        return sorted({state.item_loc[i] for i in its})

    visits: list[list[int]] = [_cells(geo, Cell.DELIVERY)]
    kinds = {int(k) for o in orders for k in o.recipe}
    plates = items_of.get(int(Item.PLATE), [])
    if (group := tiles(plates)) is not None:
        visits.append(group)
    if state.rules.dirty_plates and plates and all(st[q] == ItemState.DIRTY for q in plates):
        visits.append(_cells(geo, Cell.SINK))
    chopping = cooking = False
    for kind in sorted(kinds):
        its = items_of.get(kind, [])
        if (group := tiles(its)) is not None:
            visits.append(group)
        ready = any(st[i] in (ItemState.CHOPPED, ItemState.COOKED) or where[i] == Where.PLATE
                    for i in its)
        chopping |= kind in VEGETABLES and not ready
        cooking |= kind == Item.STEAK and not ready
    if chopping:
        visits.append(_cells(geo, Cell.BOARD))
    if cooking:
        visits.append(list(geo.pans))
    full = (1 << len(visits)) - 1
    best = [0.0] + [_INF] * full  # best[mask]: the cooks so far cover exactly ``mask``
    for a in range(state.n_agents):
        mine = paths.cover(state.agent_pos[a], visits)
        nxt = list(best)
        for mask in range(1, full + 1):
            sub = mask
            while sub:
                nxt[mask] = min(nxt[mask], best[mask ^ sub] + mine[sub])
                sub = (sub - 1) & mask
        best = nxt
    return best[full]


__all__ = ["DishBound", "PlanBound", "bumps_per_dish", "dish_bound", "plan_bound"]

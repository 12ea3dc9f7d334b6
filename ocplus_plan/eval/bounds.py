"""An upper bound on the dishes a team can serve in an episode.

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

from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

from ..sim.codes import VEGETABLES, Cell, Item
from ..sim.queries import distances, interaction_spots, walkable_in_any_layout
from ..sim.rules import Recipe, Rules
from ..sim.state import Geometry, geometry_for

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
    bumps = 2  # pick the plate, serve
    if dirty:
        bumps += 2 + rules.wash_steps
    for kind in recipe:
        bumps += 3 + (rules.chop_steps if kind in VEGETABLES else 0)
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
        n = len(visits)
        # dp[(mask, tile)]: shortest walk from the start through the visits in mask,
        # standing at ``tile`` (one of the last visit's tiles)
        dp: dict[tuple[int, int], float] = {}
        for i, tiles in enumerate(visits):
            for t in tiles:
                d = self.between(home, t) if home is not None else self.dist(start, t)  # type: ignore[arg-type]
                key = (1 << i, t)
                if d < dp.get(key, _INF):
                    dp[key] = d
        for mask in range(1, 1 << n):
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
                            d = here + self.between(t, u)
                            if d < dp.get(key, _INF):
                                dp[key] = d
        full = (1 << n) - 1
        finish = [home] if home is not None else list(end)
        return min((dp.get((full, t), _INF) + self.between(t, f)
                    for i, tiles in enumerate(visits) for t in tiles for f in finish),
                   default=_INF)


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


__all__ = ["DishBound", "bumps_per_dish", "dish_bound"]

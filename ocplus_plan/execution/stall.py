"""Stalls: stretches of steps with no progress toward any open order, whatever the cause.

A livelock (:mod:`.livelock`) is one kind of stall, seen through the executive's own
triggers. This measure reads only the state, so it counts a stall however it comes about
(deadlock replans, a cook standing still beside a partner, a plan that keeps finishing
without effect) and for any controller.

Progress between two states (:class:`ProgressMeter`) is any of:

- a dish served;
- a station advanced: an item chopped, cooked or washed a tick further, or changing state
  to a useful one (not burnt, not dirty);
- an ingredient put on a plate;
- an item moved closer to where it goes next than it has been since the last progress:
  a raw vegetable to a board, a raw steak to a pan, a chopped or cooked ingredient an open
  order asks for to a clean plate, a clean plate holding food to the window, a dirty plate
  to a sink. Distances are walks over the floor of every layout and, with two cooks or
  more, across a plain counter between two floor cells (one step onto the counter, one off:
  an item handed over from one cook to another, as on a kitchen split in halves). Carrying
  an item to and fro is no progress: only a new low counts.

:class:`StallWatch` turns that into stretches: ``stretch`` steps or more with open orders
and no progress are a stall (recorded as ``(first, last)`` step).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Sequence

from ..sim.codes import Cell, Item, ItemState, Where
from ..sim.queries import interaction_spots, walkable_in_any_layout
from ..sim.state import State

#: steps with no progress toward any open order that make a stall
STALL_STRETCH = 30
#: steps with no progress after which the executive changes strategy (again every as many)
STALL_PATIENCE = 18

_PLATE = int(Item.PLATE)
_FRESH, _CLEAN, _DIRTY = int(ItemState.FRESH), int(ItemState.CLEAN), int(ItemState.DIRTY)
_COOKED, _BURNT = int(ItemState.COOKED), int(ItemState.BURNT)


def item_distances(neighbors: Sequence[Sequence[int]], walk: Sequence[bool],
                   bridge: Sequence[bool], sources: Iterable[int]) -> list[int]:
    """Steps an item takes from each cell to the nearest of ``sources`` (-1: never): walks
    over the ``walk`` floor, and across a ``bridge`` counter only from floor to floor (put
    down on one side, taken on from the other; never from counter to counter)."""
    dist = [-1] * len(walk)
    todo: deque[int] = deque()
    for c in sources:
        if dist[c] < 0:
            dist[c] = 0
            todo.append(c)
    while todo:
        u = todo.popleft()
        for v in neighbors[u]:
            if v >= 0 and dist[v] < 0 and (walk[v] or (bridge[v] and walk[u])):
                dist[v] = dist[u] + 1
                todo.append(v)
    return dist


class ProgressMeter:
    """Says whether a state made progress toward the open orders since the last one."""

    def __init__(self, state: State) -> None:
        geo = state.geo
        self.nbrs = geo.neighbors
        self.walk = walkable_in_any_layout(geo)
        counter = int(Cell.COUNTER)  # a counter in every layout, with a cook to hand over to
        self.bridge = tuple(state.n_agents >= 2 and all(t[c] == counter for t in geo.terrains)
                            for c in range(len(self.walk)))
        terrain = geo.terrains[0]
        self._to: dict[int, list[int]] = {}
        self.tables = state.rules.tables
        # the delivery, the sink and every process station (the oven too, where it runs)
        for code in sorted({int(Cell.DELIVERY), int(Cell.SINK), *self.tables.by_code}):
            cells = [c for c, v in enumerate(terrain) if v == int(code)]
            self._to[int(code)] = self._walk_to(cells)
        self.lows: dict[int, int] = {}
        self.last = self._facts(state)

    def _walk_to(self, cells: list[int]) -> list[int]:
        spots = {s for c in cells for s in interaction_spots(self.nbrs, self.walk, c)}
        spots |= {c for c in cells if self.walk[c]}
        return item_distances(self.nbrs, self.walk, self.bridge, spots) if spots else \
            [-1] * len(self.nbrs)

    def _facts(self, state: State) -> tuple:
        """What only progress changes: dishes, item states and ticks, plate sizes."""
        ticks = tuple(p if s != _COOKED else -1  # a cooked steak's ticks count to burning
                      for p, s in zip(state.item_progress, state.item_state))
        on_plates = sum(1 for w in state.item_where if w == Where.PLATE)
        return state.stats["dishes_served"], tuple(state.item_state), ticks, on_plates

    def _place(self, state: State, item: int) -> tuple[int, int] | None:
        """(floor cell, extra steps) from which ``item`` is taken on: the holder's cell, or
        the cell of the counter it lies on (one step more, from a floor neighbour)."""
        where, loc = state.item_where[item], state.item_loc[item]
        if where == Where.HAND:
            return state.agent_pos[loc], 0
        if where == Where.CELL:
            return loc, 0 if self.walk[loc] else 1
        return None

    def _distance(self, d: list[int], cell: int, extra: int) -> int:
        if extra == 0:
            return d[cell]
        near = [d[n] for n in self.nbrs[cell] if n >= 0 and d[n] >= 0 and self.walk[n]]
        return min(near) + 1 if near else -1

    def _goal_map(self, state: State, item: int, needed: set[int],
                  plates: list[int] | None) -> list[int] | None:
        kind, st = state.geo.item_kind[item], state.item_state[item]
        if kind == _PLATE:
            if st == _DIRTY:
                return self._to[int(Cell.SINK)]
            if st == _CLEAN and state.plate_contents(item):
                return self._to[int(Cell.DELIVERY)]
            return None
        if kind not in needed:
            return None
        if st == _FRESH:  # to the station whose process takes it
            return self._to.get(self.tables.station_of(kind))
        if st == self.tables.ready_of(kind) and plates:
            return plates
        return None

    def _plate_map(self, state: State) -> list[int] | None:
        cells = []
        for i in range(state.n_items):
            if state.geo.item_kind[i] == _PLATE and state.item_state[i] == _CLEAN:
                place = self._place(state, i)
                if place is not None:
                    cells.append(place[0])
        if not cells:
            return None
        spots = {s for c in cells for s in ([c] if self.walk[c] else
                                            interaction_spots(self.nbrs, self.walk, c))}
        return item_distances(self.nbrs, self.walk, self.bridge, spots)

    def update(self, state: State) -> bool:
        """Did ``state`` progress since the state of the last call (or the first one)?"""
        facts = self._facts(state)
        progressed = self._advanced(self.last, facts)
        self.last = facts
        needed = {int(k) for o in state.orders for k in o.recipe}
        plates = self._plate_map(state)
        now: dict[int, int] = {}
        for i in range(state.n_items):
            goal = self._goal_map(state, i, needed, plates)
            place = self._place(state, i) if goal is not None else None
            if goal is None or place is None:
                continue
            d = self._distance(goal, *place)
            if d >= 0:
                now[i] = d
                if d < self.lows.get(i, d + 1) and i in self.lows:
                    progressed = True
        if progressed:
            self.lows = now
        else:
            for i, d in now.items():
                self.lows[i] = min(d, self.lows.get(i, d))
        return progressed

    @staticmethod
    def _advanced(before: tuple, after: tuple) -> bool:
        if after[0] > before[0] or after[3] > before[3]:
            return True
        for s0, s1, p0, p1 in zip(before[1], after[1], before[2], after[2]):
            if s1 != s0 and s1 not in (_BURNT, _DIRTY):
                return True
            if s1 == s0 and p1 > p0 >= 0:
                return True
        return False


class StallWatch:
    """Stretches of ``stretch`` steps or more with open orders and no progress."""

    def __init__(self, state: State, stretch: int = STALL_STRETCH) -> None:
        self.meter = ProgressMeter(state)
        self.stretch = stretch
        self.since = state.t  # the step of the last progress (or of the start)
        self.now = state.t
        self.stretches: list[tuple[int, int]] = []

    def update(self, state: State) -> int:
        """Read one state (once per step); the steps since the last progress."""
        self.now = state.t
        if self.meter.update(state) or not state.orders:
            self.close(state.t)
            self.since = state.t
        return state.t - self.since

    @property
    def length(self) -> int:
        """Steps since the last progress."""
        return self.now - self.since

    def close(self, t: int) -> None:
        """Record the stretch that ends at ``t`` if it is long enough."""
        if t - self.since >= self.stretch:
            self.stretches.append((self.since, t))
        self.since = t

    def info(self) -> dict[str, object]:
        """``stall_stretches`` (closed at the last step read) and ``longest_stall``."""
        out = list(self.stretches)
        if self.now - self.since >= self.stretch:
            out.append((self.since, self.now))
        longest = max([b - a for a, b in out] + [self.now - self.since], default=0)
        return {"stall_stretches": out, "longest_stall": longest}


__all__ = ["STALL_PATIENCE", "STALL_STRETCH", "ProgressMeter", "StallWatch", "item_distances"]

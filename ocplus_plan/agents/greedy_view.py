"""What the greedy controller knows about a kitchen at one step (derived, never mutated).

:class:`KitchenView` holds walking distances for every cook (now, around the other cooks,
and, for a lone cook on a dynamic map, over both layouts), the free counters, which clean
plate serves which open order, what each plate still misses, and how many of each
ingredient the open orders need beyond those already on their way.
"""

from __future__ import annotations

from collections import Counter

from ..sim.codes import COUNTERS, VEGETABLES, Cell, Item, ItemState
from ..sim.queries import (distances, interaction_spots, order_needs, plate_fits,
                           walkable_in_any_layout)
from ..sim.state import State

_COUNTER_CODES = frozenset(int(c) for c in COUNTERS)
_PLAIN_COUNTER = int(Cell.COUNTER)
_VEG = frozenset(int(v) for v in VEGETABLES)


class KitchenView:
    """Per-step facts derived from the state (terrain, reachability, plates, needs)."""

    def __init__(self, state: State, driven: int | None = None) -> None:
        self.s = state
        geo = state.geo
        self.terrain = geo.terrains[state.layout_index]
        #: the station that heats steak: the pan (an oven where the kitchen's records say)
        self.heat = state.rules.tables.station_of(int(Item.STEAK))
        self.walk = geo.walkables[state.layout_index]
        self.nbrs = geo.neighbors
        self.kind = geo.item_kind
        self.dist = [self.bfs(p) for p in state.agent_pos]
        # on a dynamic map a place out of reach now may be reachable after a switch: a lone
        # cook plans over the union of the layouts' floors, at a price for the wait (with
        # teammates, hand-overs through counters are faster than waiting for switches). Lone
        # means ``driven`` (the cooks it works with: those this controller drives and the
        # partners it counts on; default: every cook) is 1: a cook beside others it does
        # not count on walks over the switches itself (it passes them only what it can take
        # nowhere, in any layout, or what they finish sooner).
        lone = (state.n_agents if driven is None else driven) == 1
        self.dynamic = state.rules.dynamic and len(geo.walkables) > 1 and lone
        self.walk_any = walkable_in_any_layout(geo) if self.dynamic else self.walk
        self.dist_any = ([self.bfs(p, walk=self.walk_any) for p in state.agent_pos]
                         if self.dynamic else self.dist)
        self.wait_cost = state.rules.map_switch_step / 2
        # the same with the other cooks as walls: who can get there without anybody moving
        self.dist_now = [self.bfs(p, frozenset(q for q in state.agent_pos if q != p))
                         for p in state.agent_pos]
        self.cells_of: dict[int, list[int]] = {}
        for f, code in enumerate(self.terrain):
            self.cells_of.setdefault(code, []).append(f)
        self.switch_cells = set(geo.switch_cells)
        self._plates()
        # a lone cook on a dynamic map must not get cut off from a steak on the pan
        self.pan_region: set[int] | None = None
        if self.dynamic:
            cooking = [p for p in geo.pans if state.cell_item[p] >= 0
                       and state.item_state[state.cell_item[p]] != ItemState.BURNT]
            if cooking:
                self.pan_region = set()
                for p in cooking:
                    for n in interaction_spots(self.nbrs, self.walk, p):
                        self.pan_region.update(c for c, d in enumerate(self.bfs(n)) if d >= 0)

    def near_pan(self, cell: int) -> bool:
        """Can ``cell`` be worked from where a cooking steak stays reachable (always True
        unless a lone cook on a dynamic map has a steak on the pan)?"""
        if self.pan_region is None:
            return True
        return any(n >= 0 and n in self.pan_region for n in self.nbrs[cell])

    # ---------------------------------------------------------------- geometry
    def bfs(self, start: int, blocked: frozenset[int] = frozenset(),
             walk: tuple[bool, ...] | None = None) -> list[int]:
        """Steps from ``start`` to every cell (-1: unreachable), around ``blocked`` cells."""
        return distances(self.nbrs, self.walk if walk is None else walk, [start], blocked)

    def reach(self, agent: int, cell: int) -> float:
        """Steps for ``agent`` to stand next to ``cell`` (inf when it cannot)."""
        best = self.reach_in(self.dist[agent], cell)
        if best == float("inf") and self.dynamic:
            best = self.reach_in(self.dist_any[agent], cell) + self.wait_cost
        return best

    def reach_now(self, agent: int, cell: int) -> float:
        """Like :meth:`reach` but around the other cooks where they stand now."""
        return self.reach_in(self.dist_now[agent], cell)

    def reach_in(self, d: list[int], cell: int) -> float:
        best = float("inf")
        for n in self.nbrs[cell]:
            if n >= 0 and 0 <= d[n] < best:
                best = d[n]
        return best

    def stations(self, code: Cell) -> list[int]:
        return self.cells_of.get(int(code), [])

    def free_counters(self) -> list[int]:
        """Empty counters; plain ones first (items on spawn tiles delay respawns), and never
        a counter that a layout switch removes (it would hold the switch back)."""
        s = self.s
        plain, spawn = [], []
        for code in _COUNTER_CODES:
            for f in self.cells_of.get(code, []):
                if s.cell_item[f] < 0 and f not in self.switch_cells:
                    (plain if code == _PLAIN_COUNTER else spawn).append(f)
        return plain + spawn

    def raw_on_board(self, agent: int, board: int) -> bool:
        """Does ``board`` hold a vegetable still to chop while ``agent`` stands on the only
        floor cell it is worked from?"""
        s = self.s
        it = s.cell_item[board]
        spots = interaction_spots(self.nbrs, self.walk, board)
        return (it >= 0 and self.kind[it] in _VEG and s.item_state[it] == int(ItemState.FRESH)
                and spots == [s.agent_pos[agent]])

    # ---------------------------------------------------------------- plates and needs
    def contents(self, plate: int) -> Counter:
        return Counter(self.kind[i] for i in self.s.plate_contents(plate))

    def _plates(self) -> None:
        """Match clean plates to open orders and count what each still needs
        (:func:`~ocplus_plan.sim.queries.order_needs`)."""
        needs = order_needs(self.s)
        recipes = self.recipes = needs.recipes
        self.plate_contents, self.plate_order = needs.plate_contents, needs.plate_order
        self.plate_missing, self.need, self.supply = needs.plate_missing, needs.need, needs.supply
        #: kind -> index of the oldest open order that still needs it (older orders go first)
        self.first_need: dict[int, int] = {}
        for oi, rec in enumerate(recipes):
            plate = next((p for p, o in self.plate_order.items() if o == oi), None)
            missing = rec if plate is None else self.plate_missing[plate]
            for k in missing:
                self.first_need.setdefault(k, oi)
        self.bad_plates = [p for p, c in self.plate_contents.items() if p not in self.plate_order
                           and c and not any(plate_fits(c, r) for r in recipes)]

    def exact_match(self, plate: int) -> bool:
        c = self.plate_contents.get(plate)
        return bool(c) and any(c == r for r in self.recipes)

    def plate_wants(self, plate: int, kind: int) -> bool:
        """Would adding ``kind`` keep this clean plate on the way to some open order?"""
        c = self.plate_contents.get(plate)
        if c is None:
            return False
        c = c + Counter({kind: 1})
        return any(plate_fits(c, r) for r in self.recipes)



__all__ = ["KitchenView"]

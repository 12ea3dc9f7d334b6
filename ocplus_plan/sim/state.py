"""The world state: static geometry, the mutable per-episode state, and its hash.

Design note (profiled, see README "Speed"): the transition touches a handful of
scalars per step, and single-element access to numpy arrays costs several times
a Python list's. So the per-step state is flat lists of ints (cells indexed
``row * cols + col``), and numpy arrays are views made on demand for encoders
(:meth:`State.item_grid`, :attr:`State.grid`). Static data that never changes in
an episode lives in :class:`Geometry`, shared by every copy of a state.
"""

from __future__ import annotations

import hashlib
import struct
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from .codes import ITEM_NAMES, SPAWN_TILES, WALKABLE, Cell, Item, ItemState, Where
from .grid import grid_neighbors
from .records import Event, Order
from .rules import Rules, recipe_name
from .stations import KIND_OF


@dataclass(frozen=True, eq=False)
class Geometry:
    """Static, precomputed facts about one :class:`Rules` (shared, never mutated)."""

    rows: int
    cols: int
    #: per layout: flat list of cell codes
    terrains: tuple[tuple[int, ...], ...]
    #: per layout: flat list of walkable flags
    walkables: tuple[tuple[bool, ...], ...]
    #: per cell: flat index of the neighbour in direction RIGHT, DOWN, LEFT, UP (or -1)
    neighbors: tuple[tuple[int, int, int, int], ...]
    #: the cells of the station that heats steak (the pan; an oven where a kitchen's
    #: records give it the steak), in cell order
    pans: tuple[int, ...]
    switch_cells: tuple[int, ...]
    item_kind: tuple[int, ...]
    item_home: tuple[int, ...]
    item_names: tuple[str, ...]
    #: the cells of time-driven process stations (the pans), in cell order
    timed: tuple[int, ...]

    @classmethod
    def build(cls, rules: Rules) -> Geometry:
        layout = rules.layout
        rows, cols = layout.shape
        terrains = tuple(tuple(int(v) for v in g.ravel()) for g in layout.grids())
        walk = tuple(tuple(v in WALKABLE for v in t) for t in terrains)
        kinds, homes, names = [], [], []
        counts: dict[int, int] = {}
        for flat, code in enumerate(terrains[0]):
            if code in SPAWN_TILES:
                kinds.append(code)
                homes.append(flat)
                k = counts.get(code, 0)
                counts[code] = k + 1
                names.append(f"{Item(code).name.lower()}{k}")
        switch = ()
        if len(terrains) > 1:
            switch = tuple(i for i, (a, b) in enumerate(zip(*terrains)) if a != b)
        timed_codes = {p.station for p in rules.processes if p.timed}
        timed = tuple(i for i, v in enumerate(terrains[0]) if v in timed_codes)
        heat = rules.tables.station_of(int(Item.STEAK))
        pans = tuple(i for i, v in enumerate(terrains[0]) if v == heat)
        return cls(rows, cols, terrains, walk, grid_neighbors(rows, cols), pans, switch,
                   tuple(kinds), tuple(homes), tuple(names), timed)

    def rc(self, flat: int) -> tuple[int, int]:
        return divmod(flat, self.cols)

    def flat(self, row: int, col: int) -> int:
        return row * self.cols + col


@lru_cache(maxsize=64)
def geometry_for(rules: Rules) -> Geometry:
    """The (cached) geometry of a rule set: resets do not rebuild it."""
    return Geometry.build(rules)


class State:
    """Mutable world state of one episode. ``transition`` updates it in place."""

    __slots__ = (
        "_rng",
        "_rng_state",
        "agent_hand",
        "agent_pos",
        "cell_item",
        "geo",
        "item_agent",
        "item_loc",
        "item_progress",
        "item_state",
        "item_where",
        "layout_index",
        "next_order_id",
        "next_switch",
        "orders",
        "rules",
        "seed",
        "stats",
        "t",
    )

    rules: Rules
    geo: Geometry
    t: int
    layout_index: int
    next_switch: int
    agent_pos: list[int]
    agent_hand: list[int]
    cell_item: list[int]
    item_state: list[int]
    item_progress: list[int]
    item_where: list[int]
    item_loc: list[int]
    item_agent: list[int]
    orders: list[Order]
    next_order_id: int
    _rng: np.random.Generator | None
    _rng_state: dict[str, Any] | None
    stats: dict[str, int]
    seed: int | None

    # ----- the episode's order RNG (copied lazily: building a PCG64 costs more than a step)
    @property
    def rng(self) -> np.random.Generator:
        if self._rng is None:
            bit = np.random.PCG64(0)
            bit.state = self._rng_state
            self._rng, self._rng_state = np.random.Generator(bit), None
        return self._rng

    @rng.setter
    def rng(self, generator: np.random.Generator) -> None:
        self._rng, self._rng_state = generator, None

    def rng_state(self) -> dict[str, Any]:
        """The RNG's bit-generator state, without materialising a lazy copy."""
        return self._rng.bit_generator.state if self._rng is not None else self._rng_state

    # ----- views -----
    @property
    def n_agents(self) -> int:
        return len(self.agent_pos)

    @property
    def n_items(self) -> int:
        return len(self.item_state)

    @property
    def grid(self) -> np.ndarray:
        """The current layout's cell codes, ``(rows, cols)`` int8 (read-only)."""
        return self.rules.layout.grids()[self.layout_index]

    def agent_rc(self, agent: int) -> tuple[int, int]:
        return self.geo.rc(self.agent_pos[agent])

    def item_kind(self, item: int) -> Item:
        return Item(self.geo.item_kind[item])

    def item_name(self, item: int) -> str:
        return self.geo.item_names[item]

    def plate_contents(self, plate: int) -> list[int]:
        where, loc = self.item_where, self.item_loc
        return [i for i in range(len(where)) if where[i] == Where.PLATE and loc[i] == plate]

    def item_grid(self) -> np.ndarray:
        """``(rows, cols)`` array of the item id on each cell, -1 where none."""
        return np.array(self.cell_item, dtype=np.int16).reshape(self.geo.rows, self.geo.cols)

    def item_cell(self, item: int) -> tuple[int, int] | None:
        """The cell the item is at (following hands and plates), None while waiting."""
        where, loc = self.item_where[item], self.item_loc[item]
        if where == Where.PLATE:
            return self.item_cell(loc)
        if where == Where.HAND:
            return self.agent_rc(loc)
        if where == Where.CELL:
            return self.geo.rc(loc)
        return None

    @property
    def done(self) -> bool:
        r = self.rules
        if r.stop_after_orders is not None and self.stats["orders_completed"] >= r.stop_after_orders:
            return True
        return self.t >= r.horizon

    # ----- copy / hash / serialise -----
    def copy(self) -> State:
        s = State.__new__(State)
        s.rules, s.geo, s.t = self.rules, self.geo, self.t
        s.layout_index, s.next_switch = self.layout_index, self.next_switch
        for name in ("agent_pos", "agent_hand", "cell_item", "item_state", "item_progress",
                     "item_where", "item_loc", "item_agent", "orders"):
            setattr(s, name, list(getattr(self, name)))
        s.next_order_id, s.seed = self.next_order_id, self.seed
        s.stats = dict(self.stats)
        s._rng, s._rng_state = None, self.rng_state()
        return s

    def state_hash(self) -> str:
        """SHA-256 of everything that determines the future (incl. the RNG state)."""
        h = hashlib.sha256()
        ints = [self.t, self.layout_index, self.next_switch, self.next_order_id]
        for name in ("agent_pos", "agent_hand", "cell_item", "item_state", "item_progress",
                     "item_where", "item_loc", "item_agent"):
            seq = getattr(self, name)
            ints.append(len(seq))
            ints.extend(seq)
        for o in self.orders:
            ints.extend((o.order_id, o.created, o.deadline, len(o.recipe), *o.recipe))
        h.update(struct.pack(f"<{len(ints)}q", *ints))
        h.update(repr(sorted(self.stats.items())).encode())
        h.update(repr(self.rng_state()).encode())
        return h.hexdigest()

    def to_dict(self) -> dict[str, Any]:
        """A JSON-able snapshot (with :func:`state_from_dict` it round-trips exactly)."""
        d: dict[str, Any] = {
            name: list(getattr(self, name))
            for name in ("agent_pos", "agent_hand", "cell_item", "item_state", "item_progress",
                         "item_where", "item_loc", "item_agent")
        }
        d.update(
            t=self.t,
            layout_index=self.layout_index,
            next_switch=self.next_switch,
            next_order_id=self.next_order_id,
            seed=self.seed,
            orders=[[o.order_id, recipe_name(o.recipe), o.created, o.deadline] for o in self.orders],
            stats=dict(self.stats),
            rng=self.rng_state(),
        )
        return d

    def describe(self) -> str:
        """A small text picture of the kitchen, for debugging and the CLI."""
        lines = map_rows(self)
        orders = ", ".join(recipe_name(o.recipe) for o in self.orders)
        lines.append(f"t={self.t} orders=[{orders}] hands={self.agent_hand}")
        return "\n".join(lines)


def new_state(rules: Rules, seed: int | None = 0, *, geometry: Geometry | None = None) -> State:
    """The initial state of an episode: items on their spawn tiles, agents on spawn points,
    ``n_orders`` orders drawn from the recipe pool with ``numpy.random.default_rng(seed)``."""
    geo = geometry or geometry_for(rules)
    s = State.__new__(State)
    s.rules, s.geo, s.t, s.seed = rules, geo, 0, seed
    s.layout_index = 0
    s.next_switch = rules.map_switch_step
    s.agent_pos = [geo.flat(r, c) for r, c in rules.layout.spawn_points[: rules.n_agents]]
    s.agent_hand = [-1] * rules.n_agents
    s.cell_item = [-1] * (geo.rows * geo.cols)
    n = len(geo.item_kind)
    s.item_state = [
        int(ItemState.CLEAN if k == Item.PLATE else ItemState.FRESH) for k in geo.item_kind
    ]
    s.item_progress = [0] * n
    s.item_where = [int(Where.CELL)] * n
    s.item_loc = list(geo.item_home)
    s.item_agent = [-1] * n
    for i, home in enumerate(geo.item_home):
        s.cell_item[home] = i
    s.orders = []
    s.next_order_id = 0
    s.rng = np.random.default_rng(seed)
    s.stats = {
        "dishes_served": 0, "orders_completed": 0, "orders_expired": 0, "burns": 0,
        "wrong_deliveries": 0,
    }
    for p in rules.processes:  # one counter per process (chops, cooks, washes)
        s.stats.setdefault(p.stat, 0)
        if p.overrun_state is not None:
            s.stats.setdefault(p.overrun_stat, 0)
    s.stats["layout_switches"] = 0
    for _ in range(rules.n_orders):
        draw_order(s)
    return s


def draw_order(state: State, replaces: Order | None = None) -> None:
    """Append one order drawn uniformly from the recipe pool with the episode's RNG.

    With fixed orders (``rules.fixed_orders``) nothing is drawn: the order that
    ``replaces`` a served or expired one has its recipe, and otherwise the fixed
    recipes come in turn."""
    fixed = state.rules.fixed_orders
    if fixed is not None:
        recipe = replaces.recipe if replaces is not None else \
            fixed[state.next_order_id % len(fixed)]
    else:
        recipes = state.rules.recipes
        recipe = recipes[int(state.rng.integers(len(recipes)))]
    limit = state.rules.order_time_limit
    deadline = state.t + limit if limit is not None else -1
    state.orders.append(Order(state.next_order_id, recipe, state.t, deadline))
    state.next_order_id += 1


def map_rows(state: State, mark_items: bool = True) -> list[str]:
    """The current layout, one string per row, one letter per cell (its
    :class:`~.stations.CellKind`'s);
    a cook is drawn as its index and, with ``mark_items``, an item on a cell upper-cases the
    cell's letter (``*`` on a plain counter; a tomato on its counter then reads like the
    trash can, so texts that list the items leave them off)."""
    geo, terrain = state.geo, state.geo.terrains[state.layout_index]
    lines = []
    for r in range(geo.rows):
        row = []
        for f in range(r * geo.cols, (r + 1) * geo.cols):
            ch = KIND_OF[terrain[f]].letter
            if f in state.agent_pos:
                ch = str(state.agent_pos.index(f))
            elif mark_items and state.cell_item[f] >= 0:
                ch = ch.upper() if ch.isalpha() else "*"
            row.append(ch)
        lines.append("".join(row))
    return lines


def state_from_dict(rules: Rules, d: dict[str, Any]) -> State:
    """Rebuild a state saved by :meth:`State.to_dict` (for the same rules)."""
    from .rules import parse_recipe

    s = new_state(rules, d.get("seed"))
    for name in ("agent_pos", "agent_hand", "cell_item", "item_state", "item_progress",
                 "item_where", "item_loc", "item_agent"):
        setattr(s, name, [int(v) for v in d[name]])
    s.t, s.layout_index = int(d["t"]), int(d["layout_index"])
    s.next_switch, s.next_order_id = int(d["next_switch"]), int(d["next_order_id"])
    s.orders = [Order(int(i), parse_recipe(r), int(c), int(dl)) for i, r, c, dl in d["orders"]]
    s.stats = {k: int(v) for k, v in d["stats"].items()}
    s.rng.bit_generator.state = d["rng"]
    return s


def conservation_problems(state: State) -> list[str]:
    """Every way in which the state loses or duplicates an item (empty list = consistent).

    Checks that each item is in exactly one place and that the per-cell and per-hand
    indexes agree with each item's own record, and that item counts match the map.
    """
    problems = []
    geo = state.geo
    seen_cells: dict[int, int] = {}
    for f, it in enumerate(state.cell_item):
        if it >= 0:
            if it in seen_cells:
                problems.append(f"item {it} on two cells {seen_cells[it]} and {f}")
            seen_cells[it] = f
    seen_hands: dict[int, int] = {}
    for a, it in enumerate(state.agent_hand):
        if it >= 0:
            if it in seen_hands or it in seen_cells:
                problems.append(f"item {it} held by agent {a} and elsewhere")
            seen_hands[it] = a
    for i in range(state.n_items):
        w, loc = state.item_where[i], state.item_loc[i]
        if w == Where.CELL and seen_cells.get(i) != loc:
            problems.append(f"item {i} says cell {loc}, cell index says {seen_cells.get(i)}")
        elif w == Where.HAND and seen_hands.get(i) != loc:
            problems.append(f"item {i} says hand {loc}, hands say {seen_hands.get(i)}")
        elif w == Where.PLATE:
            if geo.item_kind[loc] != Item.PLATE or state.item_where[loc] == Where.PLATE:
                problems.append(f"item {i} lies on {loc}, which is not a plate in play")
            if i in seen_cells or i in seen_hands:
                problems.append(f"item {i} on a plate and also on a cell or in a hand")
        elif w == Where.WAITING and (loc != geo.item_home[i] or i in seen_cells or i in seen_hands):
            problems.append(f"item {i} waiting at {loc} but is elsewhere too or not its home")
    kinds = {}
    for k in geo.item_kind:
        kinds[k] = kinds.get(k, 0) + 1
    expect = {int(Item(c)): n for c, n in state.rules.layout.spawn_tile_counts().items() if n}
    if kinds != expect:
        problems.append(f"item counts {kinds} differ from the map's spawn tiles {expect}")
    return problems


__all__ = [
    "ITEM_NAMES",
    "Event",
    "Geometry",
    "Order",
    "State",
    "conservation_problems",
    "new_state",
    "state_from_dict",
]

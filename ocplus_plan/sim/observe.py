"""Observation encoders (SPEC section 8): the ``vector`` encoding and ``symbolic`` snapshots.

numpy only (no gymnasium): the env, the batched simulator and learned-policy agents all
encode through :class:`VectorEncoder`. The ``rgb`` encoding lives in :mod:`ocplus_plan.render`.

Vector layout (per agent, one flat ``float32`` row of :attr:`VectorEncoder.size` values)::

    [ grid (C, h, w) channels-first, flattened | features (F,) ]

``h = w = 2r + 1`` centred on the agent for ``obs_radius`` r > 0, the whole map (``rows x
cols``, not centred) for r = 0. Grid channels, in order (see :data:`GRID_CHANNELS`):

* 13 terrain one-hots of the *current* layout (spawn floor reads as floor),
* ``unknown``: 1 for window cells outside the map (nothing is remembered between steps),
* 5 item-kind counts (tomato, lettuce, onion, steak, plate) of the items on the cell;
  a held item is drawn on its holder's cell, plate contents on the plate's cell,
* 6 item-state counts (fresh/raw, chopped, cooked, burnt, clean, dirty) of the same items,
* ``progress``: chop or wash count / steps needed, or pan ticks / (burn_time + 1), in [0, 1],
* ``agent:self`` and ``agent:other``.

Features (see :meth:`VectorEncoder.feature_names`): own hand (kind and state one-hots,
plate contents counts), own (row, col) / (rows-1, cols-1), ``t / horizon``, layout index,
steps to the next due layout switch / ``map_switch_step``, the ``n_orders`` active orders
oldest first (ingredient counts, present flag, time left / ``order_time_limit``), and with
communication one slot per other agent (``(a + k) % n`` for k = 1..n-1) holding a one-hot of
``comm_vocab`` tokens plus a final "nothing received" bit.

Design note: the encoder is built for throughput. Static terrain one-hots (and the empty
feature block) are precomputed per layout and copied, or gathered per agent window, in
one numpy call; per step only the dynamic values (about 50 for two agents) are written,
through a ``memoryview``, in one Python pass over the items; several states (the batched
simulator) are encoded into one array.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import ConfigError
from .codes import Cell, Item, ItemState, Where
from .processes import process_tables
from .rules import Rules
from .state import Geometry, State
from .stations import CELL_KINDS, KIND_OF

#: terrain codes with a one-hot channel, in channel order (``Cell.SPAWN`` reads as floor):
#: the shipped kinds up to the trash can; a kind added later reads as its record's
#: ``observe_as`` (``sim/stations.py``), so the layout of the channels never changes
TERRAIN_CODES: tuple[Cell, ...] = tuple(c for c in Cell if c != Cell.SPAWN
                                        and KIND_OF[int(c)].observe_as is None)
ITEM_KINDS: tuple[Item, ...] = (Item.TOMATO, Item.LETTUCE, Item.ONION, Item.STEAK, Item.PLATE)
INGREDIENT_KINDS: tuple[Item, ...] = ITEM_KINDS[:4]
ITEM_STATES: tuple[ItemState, ...] = (
    ItemState.FRESH, ItemState.CHOPPED, ItemState.COOKED, ItemState.BURNT, ItemState.CLEAN,
    ItemState.DIRTY,
)
GRID_CHANNELS: tuple[str, ...] = (
    *(f"terrain:{c.name.lower()}" for c in TERRAIN_CODES),
    "unknown",
    *(f"item:{k.name.lower()}" for k in ITEM_KINDS),
    *(f"state:{s.name.lower()}" for s in ITEM_STATES),
    "progress",
    "agent:self",
    "agent:other",
)
_CH = {name: i for i, name in enumerate(GRID_CHANNELS)}
CH_UNKNOWN, CH_PROGRESS = _CH["unknown"], _CH["progress"]
CH_SELF, CH_OTHER = _CH["agent:self"], _CH["agent:other"]
_CH_KIND0, _CH_STATE0 = _CH["item:tomato"], _CH["state:fresh"]
_KIND_INDEX = {int(k): i for i, k in enumerate(ITEM_KINDS)}
_TERRAIN_INDEX = {int(c): i for i, c in enumerate(TERRAIN_CODES)} | {int(Cell.SPAWN): 1}
_TERRAIN_INDEX |= {int(k.code): _TERRAIN_INDEX[int(k.observe_as)] for k in CELL_KINDS
                   if k.observe_as is not None}
_CELL, _HAND, _PLATE = int(Where.CELL), int(Where.HAND), int(Where.PLATE)
_PLATE_KIND = int(Item.PLATE)


class SharedTables:
    """Tables that encoders of one key share (one object per key while a holder lives).

    Their arrays are read-only and their lists are never changed: encoders only read
    them (a radius-2 window's gather indices alone are 0.5 MB on a 9x9 map). Derived
    tables (:mod:`ocplus_plan.sim.fast.observe_incremental`, :mod:`ocplus_plan.sim.fast.batch`)
    are added under their own names with :meth:`derived`.
    """

    def __init__(self) -> None:
        self.filled = False

    def fill(self, **tables: Any) -> None:
        """Set the tables (arrays made read-only) and mark the object filled."""
        for name, value in tables.items():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
            setattr(self, name, value)
        self.filled = True

    def derived(self, name: str, build: Callable[[], Any]) -> Any:
        """The table ``name``, built by ``build()`` on its first use (an array is made
        read-only)."""
        value = self.__dict__.get(name)
        if value is None:
            self.fill(**{name: build()})
            value = self.__dict__[name]
        return value


#: key -> tables, alive as long as an encoder (or another holder) keeps them
_SHARED: weakref.WeakValueDictionary[tuple, SharedTables] = weakref.WeakValueDictionary()


def shared_tables(key: tuple) -> SharedTables:
    """The tables object of ``key``: the live one, or a new unfilled one."""
    tables = _SHARED.get(key)
    if tables is None:
        tables = _SHARED[key] = SharedTables()
    return tables


def _window_tables(rows: int, cols: int, r: int, n_features: int) -> dict[str, Any]:
    """The tables of a ``rows x cols`` map that do not depend on its terrain: every map
    cell's (row, col) and position features, and (r > 0) the gather indices of every
    agent cell's window into the padded planes (features gather their trailing zero)."""
    rc = [divmod(f, cols) for f in range(rows * cols)]
    pos_feat = [(r_ / max(1, rows - 1), c_ / max(1, cols - 1)) for r_, c_ in rc]
    gather = None
    if r:
        wh = ww = 2 * r + 1
        hp, wp = rows + 2 * r, cols + 2 * r
        offs = (np.arange(wh)[:, None] * wp + np.arange(ww)[None, :]).reshape(-1)
        tops = np.array([(f // cols) * wp + f % cols for f in range(rows * cols)])
        win = tops[:, None] + offs[None, :]
        chan = (np.arange(len(GRID_CHANNELS)) * hp * wp)[None, :, None]
        grid = (chan + win[:, None, :]).reshape(rows * cols, -1)
        feat = np.full((rows * cols, n_features), len(GRID_CHANNELS) * hp * wp)
        gather = np.concatenate([grid, feat], axis=1)
    return dict(rc=rc, pos_feat=pos_feat, gather=gather)


def _plane_tables(rules: Rules, r: int, n: int, n_features: int) -> dict[str, Any]:
    """The static planes of every layout, padded by r: terrain one-hots, unknown outside
    the map. ``blank`` (r = 0): per layout, a ready ``(n, size)`` block of rows with zero
    features; ``padded_ext`` (r > 0): per layout, the padded planes plus one trailing
    zero, which windows gather from."""
    rows, cols = rules.layout.shape
    hp, wp = rows + 2 * r, cols + 2 * r
    static = []
    for grid in rules.layout.grids():
        planes = np.zeros((len(GRID_CHANNELS), hp, wp), np.float32)
        planes[CH_UNKNOWN] = 1.0
        planes[CH_UNKNOWN, r : r + rows, r : r + cols] = 0.0
        for (row, col), code in np.ndenumerate(grid):
            planes[_TERRAIN_INDEX[int(code)], row + r, col + r] = 1.0
        static.append(planes.reshape(-1))
    blank = np.stack([np.tile(p, (n, 1)) for p in static])
    blank = np.concatenate(
        [blank, np.zeros((*blank.shape[:2], n_features), np.float32)], axis=2)
    padded_ext = np.stack([np.concatenate([p, np.zeros(1, np.float32)]) for p in static])
    return dict(blank=blank, padded_ext=padded_ext)


class VectorEncoder:
    """Encodes states of one :class:`Rules` into per-agent ``float32`` vectors.

    ``obs_radius`` r >= 0 (0 = whole map); ``comm_vocab`` > 0 adds the received-message
    slots. :attr:`low` / :attr:`high` are the exact element bounds (for a ``Box``).
    """

    def __init__(self, rules: Rules, obs_radius: int = 0, comm_vocab: int = 0) -> None:
        if isinstance(obs_radius, bool) or not isinstance(obs_radius, int) or obs_radius < 0:
            raise ConfigError(f"obs_radius must be an integer >= 0 (0 = whole map), got {obs_radius!r}")
        if isinstance(comm_vocab, bool) or not isinstance(comm_vocab, int) or comm_vocab < 0:
            raise ConfigError(f"comm_vocab must be an integer >= 0, got {comm_vocab!r}")
        self.rules = rules
        self.radius = r = obs_radius
        self.comm_vocab = comm_vocab
        self.n_agents = rules.n_agents
        rows, cols = rules.layout.shape
        self.rows, self.cols = rows, cols
        self.window = (2 * r + 1, 2 * r + 1) if r else (rows, cols)
        wh, ww = self.window
        self._cells = wh * ww
        self.grid_shape = (len(GRID_CHANNELS), wh, ww)
        self.grid_size = len(GRID_CHANNELS) * self._cells
        self._has_switch = rules.dynamic and rules.layout.switch_grid is not None
        self._init_features(rules, comm_vocab)
        self._init_static(rules)
        geo_kinds = [int(k) for k in Geometry.build(rules).item_kind]
        self._init_items(rules, geo_kinds)
        self._init_bounds(rules, geo_kinds)

    def _init_static(self, rules: Rules) -> None:
        """The static planes per layout (terrain one-hots, unknown outside the map, zero
        features) and, for a window, the gather indices of every agent cell's window:
        shared with every encoder of the same layouts and sizes (:func:`shared_tables`)."""
        r, n, nf = self.radius, self.n_agents, self.n_features
        #: tables that depend on the map's shape, the radius and the row layout only
        self._window = window = shared_tables(("window", self.rows, self.cols, r, n, nf))
        if not window.filled:
            window.fill(**_window_tables(self.rows, self.cols, r, nf))
        grids = tuple(tuple(int(v) for v in np.asarray(g).ravel()) for g in rules.layout.grids())
        #: tables that depend on the layouts' terrain too
        self._planes = planes = shared_tables(("planes", self.rows, self.cols, grids, r, n, nf))
        if not planes.filled:
            planes.fill(**_plane_tables(rules, r, n, nf))
        self._rc, self._pos_feat, self._gather = window.rc, window.pos_feat, window.gather
        self._blank, self._padded_ext = planes.blank, planes.padded_ext

    def _init_items(self, rules: Rules, geo_kinds: list[int]) -> None:
        """The channel offsets of every item's kind, state and progress entries."""
        rows, cols = self.rows, self.cols
        # item entries are built as channel * map_cells + cell (for r = 0 the window is the
        # map, so these are already output offsets; windows re-index them)
        m = self._map_cells = rows * cols
        self._kind_ch = [(_CH_KIND0 + _KIND_INDEX[k]) * m for k in geo_kinds]
        self._state_ch = [(_CH_STATE0 + s) * m for s in range(len(ITEM_STATES))]
        self._prog_chm = CH_PROGRESS * m
        cells = self._cells
        self._kind_chw = [(_CH_KIND0 + _KIND_INDEX[k]) * cells for k in geo_kinds]
        self._state_chw = [(_CH_STATE0 + s) * cells for s in range(len(ITEM_STATES))]
        self._prog_chw = CH_PROGRESS * cells
        #: r > 0: per agent cell (built when first needed), per map cell: its index in
        #: that agent's window, or -1 outside it
        self._local: dict[int, list[int]] = {}
        tables = process_tables(rules)
        self._prog_den = [float(tables.progress_scale(k)) for k in geo_kinds]
        self._item_kind = geo_kinds

    def _init_features(self, rules: Rules, comm_vocab: int) -> None:
        """The feature names and offsets."""
        n = self.n_agents
        names = [f"hand:{k.name.lower()}" for k in ITEM_KINDS]
        names += [f"hand_state:{s.name.lower()}" for s in ITEM_STATES]
        names += [f"hand_plate:{k.name.lower()}" for k in INGREDIENT_KINDS]
        names += ["row", "col", "time", "layout", "switch_in"]
        self._order0 = len(names)
        for o in range(rules.n_orders):
            names += [f"order{o}:{k.name.lower()}" for k in INGREDIENT_KINDS]
            names += [f"order{o}:present", f"order{o}:time_left"]
        self._msg0 = len(names)
        if comm_vocab:
            for k in range(1, n):
                names += [f"msg{k}:token{v}" for v in range(comm_vocab)] + [f"msg{k}:none"]
        self.feature_names: tuple[str, ...] = tuple(names)
        self.n_features = len(names)
        self.size = self.grid_size + self.n_features

    def _init_bounds(self, rules: Rules, geo_kinds: list[int]) -> None:
        """The exact element bounds :attr:`low` / :attr:`high` and the per-step offsets."""
        counts = {k: geo_kinds.count(int(k)) for k in ITEM_KINDS}
        grid_high = np.ones(self.grid_shape, np.float32)
        for i, k in enumerate(ITEM_KINDS):
            grid_high[_CH_KIND0 + i] = max(1, counts[k])
        grid_high[_CH_STATE0 : _CH_STATE0 + len(ITEM_STATES)] = max(1, len(geo_kinds))
        feat_high = np.ones(self.n_features, np.float32)
        for j, k in enumerate(INGREDIENT_KINDS):
            feat_high[len(ITEM_KINDS) + len(ITEM_STATES) + j] = max(1, counts[k])
            most = max((rec.count(k) for rec in rules.recipes), default=0)
            for o in range(rules.n_orders):
                feat_high[self._order0 + 6 * o + j] = max(1, most)
        self.high = np.concatenate([grid_high.reshape(-1), feat_high])
        self.low = np.zeros(self.size, np.float32)
        self._feat_base = self.grid_size
        self._state_feat0 = len(ITEM_KINDS)
        self._plate_feat0 = len(ITEM_KINDS) + len(ITEM_STATES)
        self._ingredient_index = {int(k): j for j, k in enumerate(INGREDIENT_KINDS)}
        self._self_ch, self._other_ch = CH_SELF * self._cells, CH_OTHER * self._cells
        self._prog_ch = CH_PROGRESS * self._cells
        self._orders_cache: dict[tuple, tuple[list[int], list[float]]] = {}

    # ------------------------------------------------------------------ public
    def encode(self, state: State, received: np.ndarray | None = None) -> np.ndarray:
        """``(n_agents, size)`` float32 observations of every agent.

        ``received``: ``(n_agents, n_agents - 1)`` int tokens per sender slot, -1 = none
        (only with ``comm_vocab`` > 0; None reads as nothing received).
        """
        if self.radius == 0:
            out = self._blank[state.layout_index].copy()
        else:
            out = self._padded_ext[state.layout_index][self._gather[state.agent_pos]]
        self._entries(state, 0, out, memoryview(out.reshape(-1)), received)
        return out

    def encode_many(
        self, states: Sequence[State], received: np.ndarray | None = None
    ) -> np.ndarray:
        """``(len(states), n_agents, size)`` observations of several kitchens at once
        (``received``: ``(len(states), n_agents, n_agents - 1)`` or None)."""
        n_env, n, size = len(states), self.n_agents, self.size
        layouts = [s.layout_index for s in states]
        if self.radius == 0:
            out = self._blank[layouts].reshape(n_env * n, size)
        else:
            rows = np.repeat(layouts, n)[:, None]
            out = self._padded_ext[rows, self._gather[[f for s in states for f in s.agent_pos]]]
        mv = memoryview(out.reshape(-1))
        for e, s in enumerate(states):
            self._entries(s, e * n, out, mv, None if received is None else received[e])
        return out.reshape(n_env, n, size)

    def split(self, obs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``obs[..., size]`` -> (grid ``[..., C, h, w]``, features ``[..., F]``) views."""
        lead = obs.shape[:-1]
        return (obs[..., : self.grid_size].reshape(*lead, *self.grid_shape),
                obs[..., self.grid_size :])

    # ------------------------------------------------------------------ internals
    def _entries(self, s: State, first_row: int, out: np.ndarray, mv: memoryview,
                 received: np.ndarray | None) -> None:
        """Write one kitchen's dynamic values into its rows ``first_row ..`` of ``out``
        (``(rows, size)``; ``mv`` is a flat float32 view of it). Every target is 0 in the
        static part; values are assigned, or added where an index can repeat (several
        items on one plate). Whole map (r = 0): the part every agent shares is written
        once and the row copied, then each agent's own values.

        Design note (profiled): item assignment through a ``memoryview`` beats collecting
        index lists for one numpy scatter, whose list conversions cost more than the
        writes themselves at these sizes (about 50 values per step for two agents)."""
        n, size, r = self.n_agents, self.size, self.radius
        kind_ch, state_ch = self._kind_ch, self._state_ch
        pos = s.agent_pos
        base = first_row * size
        where, loc, st, prog = s.item_where, s.item_loc, s.item_state, s.item_progress
        f_idx, f_val = self._features(s)
        fb0, other_ch, self_ch = self._feat_base, self._other_ch, self._self_ch
        pos_feat, hands = self._pos_feat, s.agent_hand
        if r == 0:
            # whole map: write the part every agent shares into the first row directly,
            # then copy that row. Only items on a plate can share a channel and a cell
            # (two chopped vegetables, ...), so they add; everything else is assigned.
            for i, w in enumerate(where):
                if w == _CELL:
                    cell = base + loc[i]
                elif w == _HAND:
                    cell = base + pos[loc[i]]
                elif w == _PLATE:
                    p = loc[i]
                    cell = base + (loc[p] if where[p] == _CELL else pos[loc[p]])
                    mv[kind_ch[i] + cell] += 1.0
                    mv[state_ch[st[i]] + cell] += 1.0
                    continue
                else:
                    continue
                mv[kind_ch[i] + cell] = 1.0
                mv[state_ch[st[i]] + cell] = 1.0
                if prog[i]:
                    mv[self._prog_chm + cell] = min(1.0, prog[i] / self._prog_den[i])
            for f in pos:
                mv[base + other_ch + f] = 1.0
            for x, v in zip(f_idx, f_val):
                mv[base + x] = v
            if n > 1:
                out[first_row + 1 : first_row + n] = out[first_row]
        else:
            # window: collect (window channel offset, map cell, value), re-index per agent
            repeats = False
            kind_w, state_w, prog_w = self._kind_chw, self._state_chw, self._prog_chw
            ent: list[int] = []
            ent_cell: list[int] = []
            ent_v: list[float] = []
            for i, w in enumerate(where):
                if w == _CELL:
                    cell = loc[i]
                elif w == _HAND:
                    cell = pos[loc[i]]
                elif w == _PLATE:
                    p = loc[i]
                    cell = loc[p] if where[p] == _CELL else pos[loc[p]]
                    repeats = True
                else:
                    continue
                if prog[i] and w != _PLATE:
                    ent += (kind_w[i], state_w[st[i]], prog_w)
                    ent_cell += (cell, cell, cell)
                    ent_v += (1.0, 1.0, min(1.0, prog[i] / self._prog_den[i]))
                else:
                    ent += (kind_w[i], state_w[st[i]])
                    ent_cell += (cell, cell)
                    ent_v += (1.0, 1.0)
        for a in range(n):
            row0 = base + a * size
            f = pos[a]
            if r == 0:  # this agent is 'self', not 'other'
                mv[row0 + self_ch + f] = 1.0
                mv[row0 + other_ch + f] = 0.0
            else:
                self._window_entries(row0, pos, a, ent, ent_cell, ent_v, mv, repeats)
                for x, v in zip(f_idx, f_val):
                    mv[row0 + x] = v
            fb = row0 + fb0
            mv[fb + 15], mv[fb + 16] = pos_feat[f]
            held = hands[a]
            if held >= 0:
                kinds = self._item_kind
                mv[fb + _KIND_INDEX[kinds[held]]] = 1.0
                mv[fb + self._state_feat0 + st[held]] = 1.0
                if kinds[held] == _PLATE_KIND:
                    for i in s.plate_contents(held):
                        mv[fb + self._plate_feat0 + self._ingredient_index[kinds[i]]] += 1.0
            if self.comm_vocab and n > 1:
                v1, mb = self.comm_vocab + 1, fb + self._msg0
                for k in range(n - 1):
                    tok = -1 if received is None else int(received[a, k])
                    mv[mb + k * v1 + (tok if tok >= 0 else self.comm_vocab)] = 1.0

    def _window_entries(self, row0: int, pos: list[int], a: int, ent: list[int],
                        ent_cell: list[int], ent_v: list[float], mv: memoryview,
                        repeats: bool) -> None:
        """Grid entries of agent ``a``'s window (r > 0): keep the cells inside, re-index
        through the precomputed map-cell -> window-cell table of the agent's cell."""
        local = self._local.get(pos[a])
        if local is None:
            r, ww = self.radius, self.window[1]
            ar, ac = self._rc[pos[a]]
            local = self._local[pos[a]] = [
                (rr - ar + r) * ww + (cc - ac + r) if abs(rr - ar) <= r and abs(cc - ac) <= r
                else -1
                for rr, cc in self._rc
            ]
        if repeats:
            for ch, cell, v in zip(ent, ent_cell, ent_v):
                at = local[cell]
                if at >= 0:
                    mv[row0 + ch + at] += v
        else:
            for ch, cell, v in zip(ent, ent_cell, ent_v):
                at = local[cell]
                if at >= 0:
                    mv[row0 + ch + at] = v
        for b, f in enumerate(pos):
            at = local[f]
            if at >= 0:
                mv[row0 + (self._self_ch if b == a else self._other_ch) + at] = 1.0

    def _features(self, s: State) -> tuple[list[int], list[float]]:
        """Features shared by every agent of ``s``: (offsets from the row start, values)."""
        rules = self.rules
        key = tuple(s.orders)
        cached = self._orders_cache.get(key)
        if cached is None:
            if len(self._orders_cache) > 4096:
                self._orders_cache.clear()
            cached = self._orders_cache[key] = self._order_features(s)
        fb0 = self._feat_base
        f_idx = cached[0] + [fb0 + 17, fb0 + 18]
        f_val = cached[1] + [s.t / rules.horizon, float(s.layout_index)]
        if self._has_switch:
            f_idx.append(fb0 + 19)
            f_val.append(min(1.0, max(0, s.next_switch - s.t) / rules.map_switch_step))
        limit = rules.order_time_limit
        if limit is not None:
            for o, order in enumerate(s.orders[: rules.n_orders]):
                if order.deadline >= 0:
                    f_idx.append(fb0 + self._order0 + 6 * o + 5)
                    f_val.append(min(1.0, max(0, order.deadline - s.t) / limit))
        return f_idx, f_val

    def _order_features(self, s: State) -> tuple[list[int], list[float]]:
        """The orders' ingredient counts and present flags (cached per order tuple)."""
        f_idx: list[int] = []
        f_val: list[float] = []
        ing = self._ingredient_index
        for o, order in enumerate(s.orders[: self.rules.n_orders]):
            base = self._feat_base + self._order0 + 6 * o
            counts: dict[int, int] = {}
            for k in order.recipe:
                counts[ing[k]] = counts.get(ing[k], 0) + 1
            for j, c in counts.items():
                f_idx.append(base + j)
                f_val.append(float(c))
            f_idx.append(base + 4)
            f_val.append(1.0)
        return f_idx, f_val


class StateSnapshot(State):
    """A frozen-in-time copy of a :class:`State` that compares equal by :meth:`state_hash`.

    The ``symbolic`` observation: planners read it like any state; equality makes two
    snapshots of identical worlds equal (what Gymnasium's determinism checks expect).
    """

    __slots__ = ()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, State):
            return NotImplemented
        return self.state_hash() == other.state_hash()

    def __hash__(self) -> int:
        return hash(self.state_hash())


def snapshot(state: State) -> StateSnapshot:
    """The ``symbolic`` observation: an independent copy of ``state`` (later steps never
    change it)."""
    copy = state.copy()
    copy.__class__ = StateSnapshot  # same slots, adds only value equality
    return copy  # type: ignore[return-value]


__all__ = [
    "GRID_CHANNELS",
    "INGREDIENT_KINDS",
    "ITEM_KINDS",
    "ITEM_STATES",
    "TERRAIN_CODES",
    "SharedTables",
    "StateSnapshot",
    "VectorEncoder",
    "shared_tables",
    "snapshot",
]

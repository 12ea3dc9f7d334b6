"""Incremental vector observations for one stream of states (the env's hot path).

:class:`IncrementalEncoder` returns exactly what :meth:`VectorEncoder.encode` returns (that
from-scratch path stays the reference; a property test compares the two every step), but
it keeps the previous observation and rewrites only what changed since the previous
call. It remembers the values it encoded (agent cells, the four per-item lists, time,
next switch, layout, orders, received tokens) and compares them with the new state's:
list ``==`` runs in C, so a step in which only agents moved costs a few comparisons and
the moving agents' entries.

Grid entries come in two kinds:

* *lying* items (on a cell, or on a plate that is on a cell) are added with ``+=`` and
  taken out with ``-=`` when their values change (counts are small integers, exact in
  float32; the progress channel has one writer per cell, so it is assigned);
* each *agent* with what it *carries* (the held item, its progress, the plate's
  contents) lives on the agent's floor cell and is assigned: a move clears it at the old
  cell and writes it at the new one (all clears before all writes, so an agent may
  follow another); what it carries is rebuilt (cached by the held item's values) when
  its hand or what lies on its plate changed.

This relies on the simulator's invariants (items lie only on non-walkable cells, one
agent per cell, a plate with contents is on a cell or in a hand), which is why it is
checked against the from-scratch encoder along random episodes and not assumed.

Design note: it diffs values instead of trusting a list of what ``transition`` touched,
so it stays exact for any sequence of valid states of its rules (resets, copies,
snapshots, several steps between two calls, layout switches) and the transition pays
nothing for it.

Buffers: whole map (r = 0): the last ``(n_agents, size)`` observation itself, returned as
a copy. Window (r > 0): the padded full-map planes once (items and every agent in
``agent:other``), a constant 0 and 1, and the agents' feature rows; each call gathers the
whole observation through a precomputed index per agent and cell (it reads the window
centre of ``agent:self`` as 1 and of ``agent:other`` as 0).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..codes import Where
from ..observe import (
    _CH_KIND0,
    _CH_STATE0,
    _KIND_INDEX,
    _PLATE_KIND,
    _TERRAIN_INDEX,
    CH_OTHER,
    CH_PROGRESS,
    CH_SELF,
    GRID_CHANNELS,
    ITEM_STATES,
    SharedTables,
    VectorEncoder,
)
from ..state import State

_CELL, _HAND, _PLATE = int(Where.CELL), int(Where.HAND), int(Where.PLATE)
_UNSET = object()


class IncrementalEncoder:
    """Vector observations of successive states of ``encoder.rules``, updated in place.

    ``encode(state, received)`` has the contract of :meth:`VectorEncoder.encode` (a fresh
    ``(n_agents, size)`` float32 array, the same values bit for bit). :meth:`forget`
    drops the remembered observation (the next call starts from the static planes).
    """

    def __init__(self, encoder: VectorEncoder) -> None:
        e = self.encoder = encoder
        self.rules = rules = e.rules
        n, r, m = e.n_agents, e.radius, e.rows * e.cols
        self.n_agents, self.radius = n, r
        self._agents = range(n)
        self._n_items = len(e._item_kind)
        self._item_kind = e._item_kind
        self._prog_den = e._prog_den
        g, f = e.grid_size, e.n_features
        self._grid_size = g
        # feature offsets from the start of an agent's feature block
        f_row, f_col, f_time, f_switch, f_layout = (
            e.feature_names.index(name) for name in ("row", "col", "time", "switch_in", "layout"))
        if r == 0:
            # the observation itself: agent a's grid at a * size, its features after it
            plane = m
            self._cell_off = list(range(m))
            self._grid_rows = [a * e.size for a in range(n)]
            self._feat_rows = [a * e.size + g for a in range(n)]
        else:
            rows, cols = e.rows, e.cols
            wp = cols + 2 * r
            plane = (rows + 2 * r) * wp
            zero_slot = len(GRID_CHANNELS) * plane
            self._src_size = zero_slot + 2 + n * f
            self._cell_off = [(c // cols + r) * wp + c % cols + r for c in range(m)]
            self._grid_rows = [0]
            self._feat_rows = [zero_slot + 2 + a * f for a in range(n)]
            self._agent_ids = np.arange(n)
        self._kind_off = [(_CH_KIND0 + _KIND_INDEX[k]) * plane for k in self._item_kind]
        self._state_off = [(_CH_STATE0 + s) * plane for s in range(len(ITEM_STATES))]
        self._prog_off = CH_PROGRESS * plane
        # the per-cell tables depend on the encoder's sizes only: built once and shared by
        # every incremental encoder of an encoder with the same window tables
        shared = e._window.derived("incremental", lambda: self._shared(plane, f_row, f_col))
        self._agent_clear, self._agent_put = shared.agent_clear, shared.agent_put
        if r:
            self._rows = shared.rows
        self._tick_offs = [(fr + f_time, fr + f_switch) for fr in self._feat_rows]
        self._layout_offs = [fr + f_layout for fr in self._feat_rows]
        self._has_switch = e._has_switch
        self._horizon, self._switch_step = rules.horizon, rules.map_switch_step
        self._limit = rules.order_time_limit is not None
        self._comm = bool(e.comm_vocab) and n > 1
        self._extras = self._limit or self._comm
        # terrain one-hots a layout switch changes, per (from, to): to clear, then to set
        grids = [tuple(int(v) for v in grid.ravel()) for grid in rules.layout.grids()]
        self._terrain_diff: dict[tuple[int, int], tuple[list[int], list[int]]] = {}
        for i, gi in enumerate(grids):
            for j, gj in enumerate(grids):
                if i != j:
                    diff = [c for c in range(m) if gi[c] != gj[c]]
                    self._terrain_diff[i, j] = (
                        [_TERRAIN_INDEX[gi[c]] * plane + self._cell_off[c] for c in diff],
                        [_TERRAIN_INDEX[gj[c]] * plane + self._cell_off[c] for c in diff],
                    )
        self._holding_cache: dict[tuple, tuple[list, list]] = {}
        self._layout = -1  # nothing remembered yet

    def _shared(self, plane: int, f_row: int, f_col: int) -> SharedTables:
        shared = SharedTables()
        shared.fill(**self._cell_tables(plane, f_row, f_col))
        return shared

    def _cell_tables(self, plane: int, f_row: int, f_col: int) -> dict[str, Any]:
        """Per agent and map cell: ``agent_clear``, the absolute offsets of the agent
        standing there; ``agent_put``, (offset, value) writes of that plus its (row, col)
        features; and (r > 0) ``rows``, the gather index of the agent's observation row
        (its window, then its features: one lookup per step, no misses)."""
        e, n, r = self.encoder, self.n_agents, self.radius
        m, g, f = e.rows * e.cols, e.grid_size, e.n_features
        tables: dict[str, Any] = {}
        if r:
            # the encoder's window indices per agent cell, agent:self read as the
            # constant 1 at the centre and 0 elsewhere, agent:other as 0 at the centre
            zero_slot = len(GRID_CHANNELS) * plane
            cells, centre = e._cells, r * e.window[1] + r
            table = e._gather[:, :g].copy()
            table[:, CH_SELF * cells : (CH_SELF + 1) * cells] = zero_slot
            table[:, CH_SELF * cells + centre] = zero_slot + 1
            table[:, CH_OTHER * cells + centre] = zero_slot
            feats = np.array([np.arange(fr, fr + f) for fr in self._feat_rows],
                             dtype=np.intp).reshape(n, f)
            tables["rows"] = np.concatenate(
                (np.broadcast_to(table, (n, m, g)), np.broadcast_to(feats[:, None, :], (n, m, f))),
                axis=2).astype(np.intp)
        # an agent's own plane, per grid row: r = 0 agent:self in its row, agent:other in
        # the others; r > 0 the shared agent:other plane
        if r == 0:
            planes = [[ro + (CH_SELF if b == a else CH_OTHER) * plane
                       for b, ro in enumerate(self._grid_rows)] for a in range(n)]
        else:
            planes = [[CH_OTHER * plane] for _ in range(n)]
        clear = tuple(tuple(tuple(x + self._cell_off[c] for x in planes[a]) for c in range(m))
                      for a in range(n))
        tables["agent_clear"] = clear
        tables["agent_put"] = tuple(
            tuple(tuple((x, 1.0) for x in clear[a][c])
                  + tuple(zip((self._feat_rows[a] + f_row, self._feat_rows[a] + f_col),
                              e._pos_feat[c]))
                  for c in range(m))
            for a in range(n))
        return tables

    def forget(self) -> None:
        """Drop the remembered observation; the next :meth:`encode` starts from scratch."""
        self._layout = -1

    # ------------------------------------------------------------------ public
    def encode(self, state: State, received: np.ndarray | None = None) -> np.ndarray:
        """``(n_agents, size)`` float32 observations, equal to ``encoder.encode(state,
        received)``."""
        s = state
        if s.layout_index != self._layout:  # a switch, or nothing remembered (-1)
            self._new_layout(s)
        where, loc, st, prog = s.item_where, s.item_loc, s.item_state, s.item_progress
        if where != self._where or loc != self._loc or st != self._st or prog != self._prog:
            self._items_changed(s)
        elif s.agent_pos != self._pos:
            # only agents moved (the common step): each one and what it carries, all old
            # cells cleared before the new ones are written (an agent may follow another)
            pos, old, mv = s.agent_pos, self._pos, self._mv
            for a in self._agents:
                f = old[a]
                if pos[a] != f:
                    for x in self._agent_clear[a][f]:
                        mv[x] = 0.0
                    if self._carry[a]:
                        c = self._cell_off[f]
                        for x, _ in self._carry[a]:
                            mv[x + c] = 0.0
            for a in self._agents:
                f = pos[a]
                if f != old[a]:
                    for x, v in self._agent_put[a][f]:
                        mv[x] = v
                    if self._carry[a]:
                        c = self._cell_off[f]
                        for x, v in self._carry[a]:
                            mv[x + c] = v
            self._pos = pos[:]

        t = s.t
        if t != self._t or s.next_switch != self._next_switch:
            mv = self._mv
            v = t / self._horizon
            if self._has_switch:
                d, step = s.next_switch - t, self._switch_step  # min(1, max(0, d) / step)
                w = 0.0 if d <= 0 else 1.0 if d >= step else d / step
                for x, y in self._tick_offs:
                    mv[x] = v
                    mv[y] = w
            else:
                for x, _ in self._tick_offs:
                    mv[x] = v
            self._t, self._next_switch = t, s.next_switch
        if s.orders != self._orders:
            self._write_orders(s)
        if self._extras:
            if self._limit:
                self._time_left(s)
            if self._comm:
                self._messages(received)

        if self.radius == 0:
            return self._cur.copy()
        return self._src.take(self._rows[self._agent_ids, s.agent_pos])

    # ------------------------------------------------------------------ internals
    def _rebuild(self, state: State) -> None:
        """Static planes of the state's layout and nothing dynamic remembered, so the
        next update writes every item, agent and feature."""
        e, n, m = self.encoder, self.n_agents, self._n_items
        layout = state.layout_index
        if self.radius == 0:
            self._cur = e._blank[layout].copy()
            mv = memoryview(self._cur.reshape(-1))
        else:
            self._src = np.zeros(self._src_size, np.float32)
            planes = e._padded_ext[layout][:-1]
            self._src[: len(planes)] = planes
            self._src[len(planes) + 1] = 1.0
            mv = memoryview(self._src)
        self._mv = mv
        self._layout = layout
        for x in self._layout_offs:
            mv[x] = float(layout)
        self._pos = state.agent_pos[:]
        for a, f in enumerate(self._pos):
            for x, v in self._agent_put[a][f]:
                mv[x] = v
        #: per agent: (offset without the cell, value) of the channels of what it holds
        self._carry: list[list[tuple[int, float]]] = [[] for _ in range(n)]
        self._held = [-1] * n
        self._where, self._loc = [-1] * m, [-1] * m
        self._st, self._prog = [-1] * m, [-1] * m
        #: per lying item: (cell offset, state channel offset, progress value), else None
        self._entry: list[tuple[int, int, float] | None] = [None] * m
        #: plate id -> items on it
        self._contents: dict[int, list[int]] = {}
        self._hand_feats: list[list[tuple[int, float]]] = [[] for _ in range(n)]
        self._t = self._next_switch = -1
        self._orders: list | None = None
        self._order_offs: list[int] = []
        self._limit_offs: list[int] = []
        self._received: object = _UNSET
        self._msg_offs: list[int] = []

    def _new_layout(self, s: State) -> None:
        """Rebuild when nothing is remembered; else the terrain one-hots of the cells a
        layout switch changes, and the layout feature."""
        if self._layout < 0:
            self._rebuild(s)
            return
        layout, mv = s.layout_index, self._mv
        clear, put = self._terrain_diff[self._layout, layout]
        for ro in self._grid_rows:
            for x in clear:
                mv[ro + x] = 0.0
            for x in put:
                mv[ro + x] = 1.0
        for x in self._layout_offs:
            mv[x] = float(layout)
        self._layout = layout

    def _items_changed(self, s: State) -> None:
        """Some item's values changed: re-enter the changed lying items (and the contents
        of a changed plate); rebuild what is carried and the own-hand features of every
        agent whose hand is concerned; redraw the agents that moved or carry something new."""
        where, loc, st, prog = s.item_where, s.item_loc, s.item_state, s.item_progress
        w0, l0, s0, p0 = self._where, self._loc, self._st, self._prog
        dirty = [i for i in range(self._n_items)
                 if where[i] != w0[i] or loc[i] != l0[i] or st[i] != s0[i] or prog[i] != p0[i]]
        self._where, self._loc, self._st, self._prog = where[:], loc[:], st[:], prog[:]
        plates = [] if _PLATE in where or _PLATE in w0 else None
        if plates is not None:  # keep the plate index; a changed plate's contents are dirty
            contents, kinds = self._contents, self._item_kind
            for i in dirty:
                if w0[i] == _PLATE:
                    contents[l0[i]].remove(i)
                    plates.append(l0[i])
                if where[i] == _PLATE:
                    contents.setdefault(loc[i], []).append(i)
                    plates.append(loc[i])
            for p in list(dirty):
                if kinds[p] == _PLATE_KIND:
                    dirty += [i for i in contents.get(p, ()) if i not in dirty]
        self._lying(s, dirty)

        mv, cell_off, carries = self._mv, self._cell_off, self._carry
        pos, old_pos, hand, old_hand = s.agent_pos, self._pos, s.agent_hand, self._held
        redraw = []
        for a in self._agents:
            h = hand[a]
            if h != old_hand[a] or (h >= 0 and (h in dirty or (plates and h in plates))):
                carry, feats = self._holding(s, a, h)
                redraw.append((a, carry))
                for x, _ in self._hand_feats[a]:
                    mv[x] = 0.0
                for x, v in feats:
                    mv[x] = v
                self._hand_feats[a] = feats
            elif pos[a] != old_pos[a]:
                redraw.append((a, carries[a]))
        for a, _ in redraw:  # agents out at the old cells, then in at the new ones
            f = old_pos[a]
            for x in self._agent_clear[a][f]:
                mv[x] = 0.0
            c = cell_off[f]
            for x, _ in carries[a]:
                mv[x + c] = 0.0
        for a, carry in redraw:
            carries[a] = carry
            f = pos[a]
            for x, v in self._agent_put[a][f]:
                mv[x] = v
            c = cell_off[f]
            for x, v in carry:
                mv[x + c] = v
        self._pos, self._held = pos[:], hand[:]

    def _lying(self, s: State, dirty: list[int]) -> None:
        """Take the ``dirty`` items' old lying entries out, then put their new ones in."""
        mv, rows, entry = self._mv, self._grid_rows, self._entry
        kind_off, state_off, prog_off = self._kind_off, self._state_off, self._prog_off
        for i in dirty:
            old = entry[i]
            if old is not None:
                c, so, pv = old
                ko, so = kind_off[i] + c, so + c
                for ro in rows:
                    mv[ro + ko] -= 1.0
                    mv[ro + so] -= 1.0
                    if pv:
                        mv[ro + prog_off + c] = 0.0
        where, loc, st, prog = s.item_where, s.item_loc, s.item_state, s.item_progress
        cell_off, den = self._cell_off, self._prog_den
        for i in dirty:
            w = where[i]
            if w == _CELL:
                cell = loc[i]
            elif w == _PLATE and where[loc[i]] == _CELL:
                cell = loc[loc[i]]
            else:
                entry[i] = None
                continue
            c = cell_off[cell]
            pv = min(1.0, prog[i] / den[i]) if prog[i] and w != _PLATE else 0.0
            so = state_off[st[i]]
            entry[i] = (c, so, pv)
            ko, so = kind_off[i] + c, so + c
            for ro in rows:
                mv[ro + ko] += 1.0
                mv[ro + so] += 1.0
                if pv:
                    mv[ro + prog_off + c] = pv

    def _holding(self, s: State, a: int, held: int) -> tuple[list, list]:
        """The grid channels of what agent ``a`` holds (offsets without the cell) and its
        own-hand features, as (offset, value) lists; cached by what it holds."""
        if held < 0:
            key: tuple = (a,)
        else:
            on = self._contents.get(held)
            key = (a, held, s.item_state[held], s.item_progress[held], tuple(on) if on else ())
        hit = self._holding_cache.get(key)
        if hit is not None:
            return hit
        carry: list[tuple[int, float]] = []
        feats: list[tuple[int, float]] = []
        if held >= 0:
            kinds, kind_off, state_off, st = self._item_kind, self._kind_off, self._state_off, s.item_state
            e, fr = self.encoder, self._feat_rows[a]
            chans = {kind_off[held]: 1.0, state_off[st[held]]: 1.0}
            if s.item_progress[held]:
                chans[self._prog_off] = min(1.0, s.item_progress[held] / self._prog_den[held])
            hand = {fr + _KIND_INDEX[kinds[held]]: 1.0, fr + e._state_feat0 + st[held]: 1.0}
            for i in self._contents.get(held, ()):
                for x in (kind_off[i], state_off[st[i]]):
                    chans[x] = chans.get(x, 0.0) + 1.0
                x = fr + e._plate_feat0 + e._ingredient_index[kinds[i]]
                hand[x] = hand.get(x, 0.0) + 1.0
            carry = [(ro + x, v) for ro in self._grid_rows for x, v in chans.items()]
            feats = list(hand.items())
        if len(self._holding_cache) > 4096:
            self._holding_cache.clear()
        hit = self._holding_cache[key] = (carry, feats)
        return hit

    def _write_orders(self, s: State) -> None:
        """Ingredient counts and present flags of the orders (only when they change)."""
        mv, e = self._mv, self.encoder
        for x in self._order_offs:
            mv[x] = 0.0
        cached = e._orders_cache.get(tuple(s.orders))
        if cached is None:
            cached = e._order_features(s)
        offs = []
        for fr in self._feat_rows:
            base = fr - self._grid_size
            for x, v in zip(*cached):
                mv[base + x] = v
                offs.append(base + x)
        self._order_offs = offs
        self._orders = s.orders[:]

    def _time_left(self, s: State) -> None:
        """Time left of each order with a deadline (changes every step)."""
        mv, rules = self._mv, self.rules
        for x in self._limit_offs:
            mv[x] = 0.0
        offs = []
        limit, t, order0 = rules.order_time_limit, s.t, self.encoder._order0
        for o, order in enumerate(s.orders[: rules.n_orders]):
            if order.deadline >= 0:
                v = min(1.0, max(0, order.deadline - t) / limit)
                for fr in self._feat_rows:
                    x = fr + order0 + 6 * o + 5
                    mv[x] = v
                    offs.append(x)
        self._limit_offs = offs

    def _messages(self, received: np.ndarray | None) -> None:
        """Received-token one-hots (only when the tokens differ from the last ones)."""
        tokens = None if received is None else received.tolist()
        if tokens == self._received:
            return
        mv, e = self._mv, self.encoder
        for x in self._msg_offs:
            mv[x] = 0.0
        vocab = e.comm_vocab
        offs = []
        for a, fr in enumerate(self._feat_rows):
            mb = fr + e._msg0
            for k in range(self.n_agents - 1):
                tok = -1 if tokens is None else tokens[a][k]
                x = mb + k * (vocab + 1) + (tok if tok >= 0 else vocab)
                mv[x] = 1.0
                offs.append(x)
        self._msg_offs = offs
        self._received = tokens


__all__ = ["IncrementalEncoder"]

"""The batched engine's observation kernels: every agent's vector observation kept up to
date (SPEC section 8, exactly :class:`ocplus_plan.sim.observe.VectorEncoder`'s), written in
the subset of Python that numba compiles, as :mod:`.kernels` (which calls them after each
step and reset).

Observations are kept, not rebuilt: ``obs`` holds every agent's vector observation and
each step lists the observation's dynamic entries (index, value) in a fixed order and
touches only those that differ from the previous step's list (all stale ones are taken
away before new ones are added). Entries add (several items on a plate share a count
cell); only counts, small integers, ever share an index, so this is exact in float32.
"""

from __future__ import annotations

from .arrays import (
    A_HAND, A_POS, C_LAYOUT, C_SWITCH, C_T, ITEM_PLATE, I_LOC, I_PROG, I_STATE, I_WHERE,
    O_DEADLINE, O_RECIPE, P_COLS, P_HAS_SWITCH, P_HORIZON, P_LIMIT, P_RADIUS, P_ROWS,
    P_SWITCH_STEP, V_CELLS, V_FEAT, V_KIND0, V_ORDER0, V_OTHER, V_PROG, V_SELF, V_STATE0,
    V_STATIC, V_WW, WHERE_CELL, WHERE_HAND, WHERE_PLATE,
)


def on_plate(e, i, plate, items):
    return items[e, I_WHERE, i] == WHERE_PLATE and items[e, I_LOC, i] == plate


def observe_env(e, clock, agents, items, orders, obs, static_at, ent_idx, ent_val, ent_n, p,
                view, kind, kidx, prog_den, recipes, static_obs, gather, n_cells):
    """Bring every agent's observation of env ``e`` up to date (see the module note)."""
    lay = clock[e, C_LAYOUT]
    scratch = ent_idx.shape[1] - 1
    for a in range(agents.shape[2]):
        me = agents[e, A_POS, a]
        at = lay * n_cells + (me if p[P_RADIUS] else 0)
        if static_at[e, a] != at:  # a new layout, or (window) a new agent cell
            row = me if p[P_RADIUS] else 0
            for j in range(view[V_STATIC]):
                obs[e, a, j] = static_obs[lay, gather[row, j]]
            static_at[e, a] = at
        m = entries(e, a, me, clock, agents, items, orders, ent_idx, ent_val, scratch, p,
                    view, kind, kidx, prog_den, recipes)
        old_n = ent_n[e, a]
        for j in range(old_n):  # take the stale entries away first, then add the new ones
            if j >= m or ent_idx[e, a, j] != ent_idx[e, scratch, j] \
                    or ent_val[e, a, j] != ent_val[e, scratch, j]:
                obs[e, a, ent_idx[e, a, j]] -= ent_val[e, a, j]
        for j in range(m):
            x, v = ent_idx[e, scratch, j], ent_val[e, scratch, j]
            if j >= old_n or ent_idx[e, a, j] != x or ent_val[e, a, j] != v:
                obs[e, a, x] += v
                ent_idx[e, a, j] = x
                ent_val[e, a, j] = v
        ent_n[e, a] = m


def window_index(me, cell, r, cols, ww):
    """``cell``'s index in the window of an agent on ``me`` (-1 outside it); r = 0: itself."""
    if r == 0:
        return cell
    dr = cell // cols - me // cols
    dc = cell % cols - me % cols
    if dr < -r or dr > r or dc < -r or dc > r:
        return -1
    return (dr + r) * ww + dc + r


def entries(e, a, me, clock, agents, items, orders, idx, val, row, p, view, kind, kidx,
            prog_den, recipes):
    """Agent ``a``'s dynamic observation entries, in a fixed order, into ``idx[e, row]`` /
    ``val[e, row]``; returns their number (VectorEncoder._entries, value for value)."""
    cells = view[V_CELLS]
    r, cols, ww = p[P_RADIUS], p[P_COLS], view[V_WW]
    m = 0
    for i in range(items.shape[2]):
        w = items[e, I_WHERE, i]
        loc = items[e, I_LOC, i]
        if w == WHERE_CELL:
            cell = loc
        elif w == WHERE_HAND:
            cell = agents[e, A_POS, loc]
        elif w == WHERE_PLATE:
            if items[e, I_WHERE, loc] == WHERE_CELL:
                cell = items[e, I_LOC, loc]
            else:
                cell = agents[e, A_POS, items[e, I_LOC, loc]]
        else:
            continue
        at = window_index(me, cell, r, cols, ww)
        if at < 0:
            continue
        idx[e, row, m] = (view[V_KIND0] + kidx[kind[i]]) * cells + at
        val[e, row, m] = 1.0
        idx[e, row, m + 1] = (view[V_STATE0] + items[e, I_STATE, i]) * cells + at
        val[e, row, m + 1] = 1.0
        m += 2
        prog = items[e, I_PROG, i]
        if prog != 0 and w != WHERE_PLATE:
            idx[e, row, m] = view[V_PROG] * cells + at
            val[e, row, m] = min(1.0, prog / prog_den[i])
            m += 1
    for b in range(agents.shape[2]):
        at = window_index(me, agents[e, A_POS, b], r, cols, ww)
        if at >= 0:
            idx[e, row, m] = (view[V_SELF] if b == a else view[V_OTHER]) * cells + at
            val[e, row, m] = 1.0
            m += 1
    fb = view[V_FEAT]
    held = agents[e, A_HAND, a]
    if held >= 0:
        idx[e, row, m] = fb + kidx[kind[held]]
        idx[e, row, m + 1] = fb + 5 + items[e, I_STATE, held]
        val[e, row, m] = 1.0
        val[e, row, m + 1] = 1.0
        m += 2
        if kind[held] == ITEM_PLATE:
            for i in range(items.shape[2]):
                if on_plate(e, i, held, items):
                    idx[e, row, m] = fb + 11 + kidx[kind[i]]
                    val[e, row, m] = 1.0
                    m += 1
    t = clock[e, C_T]
    idx[e, row, m] = fb + 15
    val[e, row, m] = (me // cols) / max(1, p[P_ROWS] - 1)
    idx[e, row, m + 1] = fb + 16
    val[e, row, m + 1] = (me % cols) / max(1, cols - 1)
    idx[e, row, m + 2] = fb + 17
    val[e, row, m + 2] = t / p[P_HORIZON]
    idx[e, row, m + 3] = fb + 18
    val[e, row, m + 3] = clock[e, C_LAYOUT]
    m += 4
    if p[P_HAS_SWITCH]:
        idx[e, row, m] = fb + 19
        val[e, row, m] = min(1.0, max(0, clock[e, C_SWITCH] - t) / p[P_SWITCH_STEP])
        m += 1
    for o in range(orders.shape[2]):
        ob = view[V_ORDER0] + 6 * o
        rec = orders[e, O_RECIPE, o]
        for j in range(4):
            if recipes[rec, j]:
                idx[e, row, m] = ob + j
                val[e, row, m] = recipes[rec, j]
                m += 1
        idx[e, row, m] = ob + 4
        val[e, row, m] = 1.0
        m += 1
        dl = orders[e, O_DEADLINE, o]
        if p[P_LIMIT] >= 0 and dl >= 0:
            idx[e, row, m] = ob + 5
            val[e, row, m] = min(1.0, max(0, dl - t) / p[P_LIMIT])
            m += 1
    return m


KERNELS = ("on_plate", "observe_env", "window_index", "entries")

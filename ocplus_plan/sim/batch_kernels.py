"""The kitchen's rules as array kernels: the step of :mod:`ocplus_plan.sim.step`, one env row
at a time, written in the subset of Python that numba compiles.

Plain Python as it stands (the fallback, and what ``numba`` compiles: see
:func:`ocplus_plan.sim.batch.kernels`). Every function reads and writes arrays whose first
axis is the env: ``k`` holds the per-env state (:class:`KitchenArrays`), ``g`` the static
tables of one rule set (:class:`StaticArrays`). The functions follow ``step.py`` rule for
rule and in the same order (bumps in agent order, waiting respawns, simultaneous moves,
pans, layout switch, expiry, horizon); a differential property test
(``tests/sim/test_batch.py``) holds the two to the same kitchen, bit for bit.

Orders draw no random numbers here: each env carries a queue of recipe indices drawn in
advance from its episode generator (``k.queue``, read from ``k.queue_pos``), which the
Python side refills; a draw is one queue read.

Observations are kept, not rebuilt: ``k.obs`` holds every agent's vector observation
(SPEC section 8, exactly :class:`ocplus_plan.sim.observe.VectorEncoder`'s) and each step
lists the observation's dynamic entries (index, value) in a fixed order and touches only
those that differ from the previous step's list (kept in ``k.ent_idx`` / ``k.ent_val``).
Entries add (several items on a plate share a count cell); only counts, small integers,
ever share an index, so adding and taking away is exact in float32.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

prange = range  # numba.prange when compiled

# codes (sim/codes.py), repeated as plain ints so the compiled kernels see constants
_FLOOR, _COUNTER, _SPAWN = 0, 1, 2
_BOARD, _DELIVERY, _PAN, _SINK, _TRASH = 6, 7, 9, 11, 12
_TOMATO, _LETTUCE, _PLATE_KIND, _ONION, _STEAK = 3, 4, 5, 8, 10
_FRESH, _CHOPPED, _COOKED, _BURNT, _CLEAN, _DIRTY = 0, 1, 2, 3, 4, 5
_CELL, _HAND, _PLATE, _WAITING = 0, 1, 2, 3
_STAY = 4
# stats columns, in the order of State.stats
DISHES, COMPLETED, EXPIRED, BURNS, WRONG, CHOPS, COOKS, WASHES, SWITCHES = range(9)
STAT_NAMES = ("dishes_served", "orders_completed", "orders_expired", "burns",
              "wrong_deliveries", "chops", "cooks", "washes", "layout_switches")
# params columns (ints)
(P_CHOP, P_COOK, P_BURN, P_WASH, P_HORIZON, P_LIMIT, P_STOP, P_DIRTY, P_DYNAMIC,
 P_SWITCH_STEP, P_SHARED, P_FIXED, P_RADIUS, P_ROWS, P_COLS, P_HAS_SWITCH) = range(16)
# reward columns (floats)
R_SUBTASK, R_CORRECT, R_WRONG, R_STEP, R_BURNED, R_EXPIRED = range(6)
# obs layout columns (ints): channel starts and feature offsets
(O_CELLS, O_WW, O_KIND0, O_STATE0, O_PROG, O_SELF, O_OTHER, O_FEAT, O_ORDER0,
 O_STATIC) = range(10)


class StaticArrays(NamedTuple):
    """What one rule set fixes (see :meth:`ocplus_plan.sim.batch.BatchSim` for the build)."""

    params: np.ndarray  # int64 (16,)
    rewards: np.ndarray  # float64 (6,)
    terrain: np.ndarray  # int64 (layouts, cells)
    walk: np.ndarray  # bool (layouts, cells)
    nbrs: np.ndarray  # int64 (cells, 4)
    pans: np.ndarray  # int64 (n_pans,)
    switch_cells: np.ndarray  # int64 (n,)
    item_kind: np.ndarray  # int64 (items,)
    item_home: np.ndarray  # int64 (items,)
    kind_index: np.ndarray  # int64 (16,): item kind -> 0..4 (tomato lettuce onion steak plate)
    prog_den: np.ndarray  # float64 (items,)
    recipe_counts: np.ndarray  # int64 (recipes, 4)
    fixed: np.ndarray  # int64 (n_fixed,) recipe indices of the fixed orders
    spawn: np.ndarray  # int64 (agents,)
    obs_layout: np.ndarray  # int64 (10,)
    static_obs: np.ndarray  # float32 (layouts, padded cells * static channels + 1)
    static_gather: np.ndarray  # int64 (cells, static size of one agent's window)


class KitchenArrays(NamedTuple):
    """The state of ``E`` kitchens (first axis), plus their observations."""

    t: np.ndarray  # (E,)
    layout: np.ndarray
    next_switch: np.ndarray
    next_order_id: np.ndarray
    pos: np.ndarray  # (E, agents)
    hand: np.ndarray
    cell_item: np.ndarray  # (E, cells)
    item_state: np.ndarray  # (E, items)
    item_progress: np.ndarray
    item_where: np.ndarray
    item_loc: np.ndarray
    item_agent: np.ndarray
    order_id: np.ndarray  # (E, n_orders), oldest first
    order_recipe: np.ndarray
    order_created: np.ndarray
    order_deadline: np.ndarray
    stats: np.ndarray  # (E, 9)
    queue: np.ndarray  # (E, Q) recipe indices drawn ahead
    queue_pos: np.ndarray  # (E,)
    rewards: np.ndarray  # float64 (E, agents), the last step's
    obs: np.ndarray  # float32 (E, agents, size)
    obs_static_at: np.ndarray  # (E, agents): layout * cells + cell whose static part is in obs
    ent_idx: np.ndarray  # (E, agents, K)
    ent_val: np.ndarray  # float32 (E, agents, K)
    ent_n: np.ndarray  # (E, agents)


# ---------------------------------------------------------------- entry points
def step_all(k, g, actions, active):
    """One step of every env ``e`` with ``active[e]``; then their observations."""
    for e in prange(len(active)):
        if active[e]:
            step_env(k, g, e, actions[e])
            observe_env(k, g, e)


def reset_some(k, g, envs):
    """Start a new episode in each listed env (its queue already holds the new draws)."""
    for j in prange(len(envs)):
        reset_env(k, g, envs[j])
        observe_env(k, g, envs[j])


def reset_env(k, g, e):
    p = g.params
    k.t[e] = 0
    k.layout[e] = 0
    k.next_switch[e] = p[P_SWITCH_STEP]
    k.next_order_id[e] = 0
    for a in range(len(g.spawn)):
        k.pos[e, a] = g.spawn[a]
        k.hand[e, a] = -1
        k.rewards[e, a] = 0.0
    k.cell_item[e, :] = -1
    for i in range(len(g.item_kind)):
        k.item_state[e, i] = _CLEAN if g.item_kind[i] == _PLATE_KIND else _FRESH
        k.item_progress[e, i] = 0
        k.item_where[e, i] = _CELL
        k.item_loc[e, i] = g.item_home[i]
        k.item_agent[e, i] = -1
        k.cell_item[e, g.item_home[i]] = i
    k.stats[e, :] = 0
    for o in range(k.order_id.shape[1]):
        recipe = g.fixed[k.next_order_id[e] % len(g.fixed)] if p[P_FIXED] else draw(k, e)
        put_order(k, g, e, o, recipe)


def draw(k, e):
    r = k.queue[e, k.queue_pos[e]]
    k.queue_pos[e] += 1
    return r


def put_order(k, g, e, slot, recipe):
    k.order_id[e, slot] = k.next_order_id[e]
    k.order_recipe[e, slot] = recipe
    k.order_created[e, slot] = k.t[e]
    limit = g.params[P_LIMIT]
    k.order_deadline[e, slot] = k.t[e] + limit if limit >= 0 else -1
    k.next_order_id[e] += 1


def replace_order(k, g, e, slot):
    """Drop order ``slot`` (later ones move up) and append its replacement."""
    recipe = k.order_recipe[e, slot]
    last = k.order_id.shape[1] - 1
    for o in range(slot, last):
        k.order_id[e, o] = k.order_id[e, o + 1]
        k.order_recipe[e, o] = k.order_recipe[e, o + 1]
        k.order_created[e, o] = k.order_created[e, o + 1]
        k.order_deadline[e, o] = k.order_deadline[e, o + 1]
    put_order(k, g, e, last, recipe if g.params[P_FIXED] else draw(k, e))


# ---------------------------------------------------------------- the step
def step_env(k, g, e, acts):
    p = g.params
    n = k.pos.shape[1]
    for a in range(n):
        k.rewards[e, a] = g.rewards[R_STEP]
    lay = k.layout[e]
    targets = np.full(n, -1, np.int64)
    moving = False
    for a in range(n):
        act = acts[a]
        if act == _STAY:
            continue
        tgt = g.nbrs[k.pos[e, a], act]
        if tgt < 0:
            continue
        if g.walk[lay, tgt]:
            targets[a] = tgt
            moving = True
        else:
            interact(k, g, e, a, tgt)
    waiting = False
    for i in range(k.item_where.shape[1]):
        if k.item_where[e, i] == _WAITING:
            waiting = True
    if waiting:
        for i in range(k.item_where.shape[1]):
            if k.item_where[e, i] == _WAITING and k.cell_item[e, k.item_loc[e, i]] < 0:
                k.cell_item[e, k.item_loc[e, i]] = i
                k.item_where[e, i] = _CELL
    if moving:
        resolve_moves(k, e, targets)
    for j in range(len(g.pans)):
        it = k.cell_item[e, g.pans[j]]
        if it >= 0:
            tick_pan(k, g, e, it)
    k.t[e] += 1
    if p[P_DYNAMIC]:
        maybe_switch(k, g, e)
    if p[P_LIMIT] >= 0:
        expire_orders(k, g, e)
    if p[P_SHARED]:
        total = 0.0
        for a in range(n):
            total += k.rewards[e, a]
        for a in range(n):
            k.rewards[e, a] = total


def resolve_moves(k, e, targets):
    """Simultaneous moves (step._resolve_moves): contested cells, swaps and cycles block."""
    n = len(targets)
    status = np.full(n, 2, np.int64)  # 0 undecided, 1 moves, 2 stays
    for a in range(n):
        if targets[a] >= 0:
            same = 0
            for b in range(n):
                if targets[b] == targets[a]:
                    same += 1
            if same == 1:
                status[a] = 0
    chain = np.empty(n, np.int64)
    for a in range(n):
        if status[a] != 0:
            continue
        chain[0] = a
        length = 1
        b = occupant(k, e, targets[a])
        while b >= 0 and status[b] == 0 and not in_chain(chain, length, b):
            chain[length] = b
            length += 1
            b = occupant(k, e, targets[b])
        ok = b < 0 or status[b] == 1
        for c in range(length):
            status[chain[c]] = 1 if ok else 2
    for a in range(n):
        if status[a] == 1:
            k.pos[e, a] = targets[a]


def occupant(k, e, cell):
    for a in range(k.pos.shape[1]):
        if k.pos[e, a] == cell:
            return a
    return -1


def in_chain(chain, length, b):
    for c in range(length):
        if chain[c] == b:
            return True
    return False


def tick_pan(k, g, e, it):
    p = g.params
    ticks = k.item_progress[e, it] + 1
    k.item_progress[e, it] = ticks
    st = k.item_state[e, it]
    owner = k.item_agent[e, it]
    if st == _FRESH and p[P_COOK] - ticks <= 0:
        k.item_state[e, it] = _COOKED
        k.stats[e, COOKS] += 1
        if owner >= 0:
            k.rewards[e, owner] += g.rewards[R_SUBTASK]
        st = _COOKED
    if st != _BURNT and p[P_BURN] + 1 - ticks <= 0:
        k.item_state[e, it] = _BURNT
        k.stats[e, BURNS] += 1
        if owner >= 0:
            k.rewards[e, owner] += g.rewards[R_BURNED]


def maybe_switch(k, g, e):
    if k.t[e] < k.next_switch[e] or g.terrain.shape[0] < 2:
        return
    old = k.layout[e]
    new = 1 - old
    for j in range(len(g.switch_cells)):
        f = g.switch_cells[j]
        if not g.walk[new, f] and occupant(k, e, f) >= 0:
            return
        if (g.terrain[old, f] == _COUNTER and g.terrain[new, f] != _COUNTER
                and k.cell_item[e, f] >= 0):
            return
    k.layout[e] = new
    k.next_switch[e] = k.t[e] + g.params[P_SWITCH_STEP]
    k.stats[e, SWITCHES] += 1


def expire_orders(k, g, e):
    n = k.pos.shape[1]
    share = g.rewards[R_EXPIRED] / n
    slot = 0
    for _ in range(k.order_id.shape[1]):  # the orders open before this check, in order
        dl = k.order_deadline[e, slot]
        if 0 <= dl <= k.t[e]:
            k.stats[e, EXPIRED] += 1
            for a in range(n):
                k.rewards[e, a] += share
            replace_order(k, g, e, slot)
        else:
            slot += 1


# ---------------------------------------------------------------- bumps (queries.bump_effect)
def is_veg(kind):
    return kind == _TOMATO or kind == _LETTUCE or kind == _ONION


def plateable(k, g, e, it):
    kind = g.item_kind[it]
    st = k.item_state[e, it]
    return (is_veg(kind) and st == _CHOPPED) or (kind == _STEAK and st == _COOKED)


def fresh_veg(k, g, e, it):
    return is_veg(g.item_kind[it]) and k.item_state[e, it] == _FRESH


def has_contents(k, e, plate):
    for i in range(k.item_where.shape[1]):
        if k.item_where[e, i] == _PLATE and k.item_loc[e, i] == plate:
            return True
    return False


def interact(k, g, e, a, cell):
    """Agent ``a`` bumps the non-walkable ``cell`` (queries.bump_effect, then step._interact)."""
    code = g.terrain[k.layout[e], cell]
    held = k.hand[e, a]
    here = k.cell_item[e, cell]
    if code == _COUNTER or code == _TOMATO or code == _LETTUCE or code == _PLATE_KIND \
            or code == _ONION or code == _STEAK:
        if held < 0:
            if here >= 0:
                pick(k, e, a, cell, here)
        elif here < 0:
            put(k, e, a, cell, held)
        else:
            plate_exchange(k, g, e, a, cell, held, here)
    elif code == _BOARD:
        if held < 0:
            if here >= 0:
                if fresh_veg(k, g, e, here):
                    advance(k, g, e, a, here, g.params[P_CHOP], _CHOPPED, CHOPS)
                else:
                    pick(k, e, a, cell, here)
        elif here < 0:
            if fresh_veg(k, g, e, held):
                put(k, e, a, cell, held)
        else:
            plate_exchange(k, g, e, a, cell, held, here)
    elif code == _PAN:
        if held < 0:
            if here >= 0:
                pick(k, e, a, cell, here)
        elif here < 0:
            st = k.item_state[e, held]
            if g.item_kind[held] == _STEAK and (st == _FRESH or st == _COOKED):
                put(k, e, a, cell, held)
        else:
            plate_exchange(k, g, e, a, cell, held, here)
    elif code == _SINK:
        if held < 0:
            if here >= 0:
                if k.item_state[e, here] == _DIRTY:
                    advance(k, g, e, a, here, g.params[P_WASH], _CLEAN, WASHES)
                else:
                    pick(k, e, a, cell, here)
        elif here < 0 and k.item_state[e, held] == _DIRTY:
            put(k, e, a, cell, held)
    elif code == _DELIVERY:
        if held >= 0:
            deliver(k, g, e, a, held)
    elif code == _TRASH:
        if held >= 0:
            if g.item_kind[held] == _PLATE_KIND:
                if has_contents(k, e, held):  # an empty plate: nothing to throw away
                    for i in range(k.item_where.shape[1]):
                        if k.item_where[e, i] == _PLATE and k.item_loc[e, i] == held:
                            send_home(k, g, e, i, _FRESH)
            else:
                k.hand[e, a] = -1
                send_home(k, g, e, held, _FRESH)


def plate_exchange(k, g, e, a, cell, held, here):
    if g.item_kind[here] == _PLATE_KIND and k.item_state[e, here] == _CLEAN \
            and plateable(k, g, e, held):
        k.hand[e, a] = -1
        k.item_where[e, held] = _PLATE
        k.item_loc[e, held] = here
    elif g.item_kind[held] == _PLATE_KIND and k.item_state[e, held] == _CLEAN \
            and plateable(k, g, e, here):
        k.cell_item[e, cell] = -1
        k.item_where[e, here] = _PLATE
        k.item_loc[e, here] = held
        k.item_agent[e, here] = a


def pick(k, e, a, cell, it):
    k.cell_item[e, cell] = -1
    k.hand[e, a] = it
    k.item_where[e, it] = _HAND
    k.item_loc[e, it] = a
    k.item_agent[e, it] = a


def put(k, e, a, cell, it):
    k.hand[e, a] = -1
    k.cell_item[e, cell] = it
    k.item_where[e, it] = _CELL
    k.item_loc[e, it] = cell


def advance(k, g, e, a, it, needed, done_state, stat):
    k.item_progress[e, it] += 1
    k.item_agent[e, it] = a
    if k.item_progress[e, it] >= needed:
        k.item_state[e, it] = done_state
        k.item_progress[e, it] = 0
        k.stats[e, stat] += 1
        k.rewards[e, a] += g.rewards[R_SUBTASK]


def send_home(k, g, e, it, state):
    home = g.item_home[it]
    k.item_state[e, it] = state
    k.item_progress[e, it] = 0
    k.item_agent[e, it] = -1
    k.item_loc[e, it] = home
    if k.cell_item[e, home] < 0:
        k.cell_item[e, home] = it
        k.item_where[e, it] = _CELL
    else:
        k.item_where[e, it] = _WAITING


def deliver(k, g, e, a, held):
    slot = -1
    if g.item_kind[held] == _PLATE_KIND:
        slot = matching_order(k, g, e, held)
    if slot < 0:
        k.stats[e, WRONG] += 1
        k.rewards[e, a] += g.rewards[R_WRONG]
        return
    k.stats[e, DISHES] += 1
    k.stats[e, COMPLETED] += 1
    k.rewards[e, a] += g.rewards[R_CORRECT]
    for i in range(k.item_where.shape[1]):
        if k.item_where[e, i] == _PLATE and k.item_loc[e, i] == held:
            send_home(k, g, e, i, _FRESH)
    k.hand[e, a] = -1
    send_home(k, g, e, held, _DIRTY if g.params[P_DIRTY] else _CLEAN)
    replace_order(k, g, e, slot)


def matching_order(k, g, e, plate):
    """The slot of the oldest order the plate serves (orders.plate_recipe / matching_order)."""
    if k.item_state[e, plate] != _CLEAN:
        return -1
    counts = np.zeros(4, np.int64)
    empty = True
    for i in range(k.item_where.shape[1]):
        if k.item_where[e, i] == _PLATE and k.item_loc[e, i] == plate:
            if not plateable(k, g, e, i):
                return -1
            counts[g.kind_index[g.item_kind[i]]] += 1
            empty = False
    if empty:
        return -1
    for o in range(k.order_id.shape[1]):
        r = k.order_recipe[e, o]
        same = True
        for j in range(4):
            if g.recipe_counts[r, j] != counts[j]:
                same = False
        if same:
            return o
    return -1


# ---------------------------------------------------------------- observations
def observe_env(k, g, e):
    """Bring every agent's observation of env ``e`` up to date (see the module note)."""
    ol = g.obs_layout
    n = k.pos.shape[1]
    cells_m = g.terrain.shape[1]
    size_k = k.ent_idx.shape[2]
    idx = np.empty(size_k, np.int64)
    val = np.empty(size_k, np.float32)
    for a in range(n):
        at = k.layout[e] * cells_m + k.pos[e, a]
        if g.params[P_RADIUS] == 0:
            at = k.layout[e] * cells_m
        if k.obs_static_at[e, a] != at:  # a new layout, or (window) a new agent cell
            src = g.static_gather[k.pos[e, a] if g.params[P_RADIUS] else 0]
            for j in range(ol[O_STATIC]):
                k.obs[e, a, j] = g.static_obs[k.layout[e], src[j]]
            k.obs_static_at[e, a] = at
        m = entries(k, g, e, a, idx, val)
        apply_entries(k, e, a, idx, val, m)


def apply_entries(k, e, a, idx, val, m):
    old_n = k.ent_n[e, a]
    same = min(m, old_n)
    for j in range(same):
        if k.ent_idx[e, a, j] != idx[j] or k.ent_val[e, a, j] != val[j]:
            k.obs[e, a, k.ent_idx[e, a, j]] -= k.ent_val[e, a, j]
    for j in range(same, old_n):
        k.obs[e, a, k.ent_idx[e, a, j]] -= k.ent_val[e, a, j]
    for j in range(m):
        if j >= old_n or k.ent_idx[e, a, j] != idx[j] or k.ent_val[e, a, j] != val[j]:
            k.obs[e, a, idx[j]] += val[j]
            k.ent_idx[e, a, j] = idx[j]
            k.ent_val[e, a, j] = val[j]
    k.ent_n[e, a] = m


def local_index(g, agent_cell, cell):
    """``cell``'s index in the window of an agent on ``agent_cell`` (-1 outside it)."""
    p = g.params
    r = p[P_RADIUS]
    if r == 0:
        return cell
    cols = p[P_COLS]
    dr = cell // cols - agent_cell // cols
    dc = cell % cols - agent_cell % cols
    if dr < -r or dr > r or dc < -r or dc > r:
        return -1
    return (dr + r) * g.obs_layout[O_WW] + dc + r


def item_cell(k, e, i):
    """The map cell an item is drawn on (holder's cell, plate's cell), -1 while waiting."""
    w = k.item_where[e, i]
    loc = k.item_loc[e, i]
    if w == _CELL:
        return loc
    if w == _HAND:
        return k.pos[e, loc]
    if w == _PLATE:
        if k.item_where[e, loc] == _CELL:
            return k.item_loc[e, loc]
        return k.pos[e, k.item_loc[e, loc]]
    return -1


def entries(k, g, e, a, idx, val):
    """Agent ``a``'s dynamic observation entries, in a fixed order; returns their number."""
    ol = g.obs_layout
    p = g.params
    cells = ol[O_CELLS]
    me = k.pos[e, a]
    m = 0
    for i in range(k.item_where.shape[1]):
        cell = item_cell(k, e, i)
        if cell < 0:
            continue
        at = local_index(g, me, cell)
        if at < 0:
            continue
        idx[m] = (ol[O_KIND0] + g.kind_index[g.item_kind[i]]) * cells + at
        val[m] = 1.0
        idx[m + 1] = (ol[O_STATE0] + k.item_state[e, i]) * cells + at
        val[m + 1] = 1.0
        m += 2
        prog = k.item_progress[e, i]
        if prog != 0 and k.item_where[e, i] != _PLATE:
            idx[m] = ol[O_PROG] * cells + at
            val[m] = min(1.0, prog / g.prog_den[i])
            m += 1
    for b in range(k.pos.shape[1]):
        at = local_index(g, me, k.pos[e, b])
        if at >= 0:
            idx[m] = (ol[O_SELF] if b == a else ol[O_OTHER]) * cells + at
            val[m] = 1.0
            m += 1
    fb = ol[O_FEAT]
    held = k.hand[e, a]
    if held >= 0:
        kind = g.item_kind[held]
        idx[m] = fb + g.kind_index[kind]
        idx[m + 1] = fb + 5 + k.item_state[e, held]
        val[m] = 1.0
        val[m + 1] = 1.0
        m += 2
        if kind == _PLATE_KIND:
            for i in range(k.item_where.shape[1]):
                if k.item_where[e, i] == _PLATE and k.item_loc[e, i] == held:
                    idx[m] = fb + 11 + g.kind_index[g.item_kind[i]]
                    val[m] = 1.0
                    m += 1
    rows, cols = p[P_ROWS], p[P_COLS]
    idx[m] = fb + 15
    val[m] = (me // cols) / max(1, rows - 1)
    idx[m + 1] = fb + 16
    val[m + 1] = (me % cols) / max(1, cols - 1)
    idx[m + 2] = fb + 17
    val[m + 2] = k.t[e] / p[P_HORIZON]
    idx[m + 3] = fb + 18
    val[m + 3] = k.layout[e]
    m += 4
    if p[P_HAS_SWITCH]:
        idx[m] = fb + 19
        val[m] = min(1.0, max(0, k.next_switch[e] - k.t[e]) / p[P_SWITCH_STEP])
        m += 1
    for o in range(k.order_id.shape[1]):
        ob = ol[O_ORDER0] + 6 * o
        r = k.order_recipe[e, o]
        for j in range(4):
            if g.recipe_counts[r, j]:
                idx[m] = ob + j
                val[m] = g.recipe_counts[r, j]
                m += 1
        idx[m] = ob + 4
        val[m] = 1.0
        m += 1
        dl = k.order_deadline[e, o]
        if p[P_LIMIT] >= 0 and dl >= 0:
            idx[m] = ob + 5
            val[m] = min(1.0, max(0, dl - k.t[e]) / p[P_LIMIT])
            m += 1
    return m


KERNELS = (
    "step_all", "reset_some", "reset_env", "draw", "put_order", "replace_order", "step_env",
    "resolve_moves", "occupant", "in_chain", "tick_pan", "maybe_switch", "expire_orders",
    "is_veg", "plateable", "fresh_veg", "has_contents", "interact", "plate_exchange", "pick",
    "put", "advance", "send_home", "deliver", "matching_order", "observe_env",
    "apply_entries", "local_index", "item_cell", "entries",
)

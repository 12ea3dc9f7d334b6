"""The kitchen's rules as array kernels: the step of :mod:`ocplus_plan.sim.step`, one env row
at a time, written in the subset of Python that numba compiles.

Plain Python as it stands (the fallback, and what ``numba`` compiles: see
:func:`ocplus_plan.sim.fast.batch.kernels`). The state of ``E`` kitchens lives in a few integer
arrays whose first axis is the env (:class:`KitchenArrays`); the tables of one rule set in
:class:`StaticArrays`. The functions follow ``step.py`` rule for rule and in the same order
(bumps in agent order, waiting respawns, simultaneous moves, pans, layout switch, expiry);
a differential property test (``tests/sim/fast/test_batch.py``) holds the two to the same
kitchen, bit for bit.

Design notes (profiled with numba 0.68):

* helpers take the arrays one by one plus the env index ``e``, never the named tuples:
  passing a tuple of twenty arrays to a compiled function, or taking an attribute of it,
  costs more than the rule it serves, and reference counting on shared arrays makes the
  two threads fight; the entry points unpack the tuples once per call;
* orders draw no random numbers here: each env carries a queue of recipe indices drawn
  in advance from its episode generator (``queue``, read at ``clock[e, C_QPOS]``), which
  the Python side refills; a draw is one queue read;
* observations are kept, not rebuilt: ``obs`` holds every agent's vector observation
  (SPEC section 8, exactly :class:`ocplus_plan.sim.observe.VectorEncoder`'s) and each
  step lists the observation's dynamic entries (index, value) in a fixed order and touches
  only those that differ from the previous step's list (all stale ones are taken away
  before new ones are added). Entries add (several items on a plate share a count cell);
  only counts, small integers, ever share an index, so this is exact in float32.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


# codes (sim/codes.py), repeated as plain ints so the compiled kernels see constants
_COUNTER = 1
_TOMATO, _LETTUCE, _PLATE_KIND, _ONION, _STEAK = 3, 4, 5, 8, 10
_BOARD, _DELIVERY, _PAN, _SINK, _TRASH = 6, 7, 9, 11, 12
_FRESH, _CHOPPED, _COOKED, _BURNT, _CLEAN, _DIRTY = 0, 1, 2, 3, 4, 5
_CELL, _HAND, _PLATE, _WAITING = 0, 1, 2, 3
_STAY = 4
# columns and rows of the state arrays
C_T, C_LAYOUT, C_SWITCH, C_ORDER_ID, C_QPOS = range(5)  # clock (E, 5)
A_POS, A_HAND = range(2)  # agents (E, 2, n_agents)
# items (E, 6, n_items); I_LIFE counts the item's respawns (batch bookkeeping, not State)
I_STATE, I_PROG, I_WHERE, I_LOC, I_OWNER, I_LIFE = range(6)
O_ID, O_RECIPE, O_CREATED, O_DEADLINE = range(4)  # orders (E, 4, n_orders), oldest first
DISHES, COMPLETED, EXPIRED, BURNS, WRONG, CHOPS, COOKS, WASHES, SWITCHES = range(9)
STAT_NAMES = ("dishes_served", "orders_completed", "orders_expired", "burns",
              "wrong_deliveries", "chops", "cooks", "washes", "layout_switches")
# params (ints) and reward values (floats)
(P_CHOP, P_COOK, P_BURN, P_WASH, P_HORIZON, P_LIMIT, P_STOP, P_DIRTY, P_DYNAMIC,
 P_SWITCH_STEP, P_SHARED, P_FIXED, P_RADIUS, P_ROWS, P_COLS, P_HAS_SWITCH, P_OBSERVE) = range(17)
R_SUBTASK, R_CORRECT, R_WRONG, R_STEP, R_BURNED, R_EXPIRED = range(6)
# what each agent's bump did in the last step (bumps (E, 3, agents): kind, item, plate)
B_NONE, B_PUTDOWN, B_PLATE_ADD = range(3)
# observation layout: window cells and width, channel starts, feature offsets, static size
(V_CELLS, V_WW, V_KIND0, V_STATE0, V_PROG, V_SELF, V_OTHER, V_FEAT, V_ORDER0,
 V_STATIC) = range(10)


class StaticArrays(NamedTuple):
    """What one rule set fixes (built by :func:`ocplus_plan.sim.fast.batch.static_arrays`)."""

    params: np.ndarray  # int64 (17,)
    rewards: np.ndarray  # float64 (6,)
    terrain: np.ndarray  # int64 (layouts, cells)
    walk: np.ndarray  # bool (layouts, cells)
    nbrs: np.ndarray  # int64 (cells, 4)
    pans: np.ndarray  # int64 (n_pans,)
    switch_cells: np.ndarray  # int64 (n,)
    kind: np.ndarray  # int64 (items,) item kind
    home: np.ndarray  # int64 (items,) spawn tile
    kind_index: np.ndarray  # int64 (16,): item kind -> 0..4 (tomato lettuce onion steak plate)
    prog_den: np.ndarray  # float64 (items,) what the progress channel divides by
    recipes: np.ndarray  # int64 (recipes, 4) ingredient counts
    fixed: np.ndarray  # int64 (n_fixed,) recipe indices of the fixed orders
    spawn: np.ndarray  # int64 (agents,)
    obs_layout: np.ndarray  # int64 (10,) observation layout (V_*)
    static_obs: np.ndarray  # float32 (layouts, padded static planes + 1)
    static_gather: np.ndarray  # int64 (cells or 1, static size of one agent's observation)


class KitchenArrays(NamedTuple):
    """The state of ``E`` kitchens (first axis), their observations and scratch space."""

    clock: np.ndarray  # (E, 5) C_*
    agents: np.ndarray  # (E, 2, agents) A_*
    cells: np.ndarray  # (E, cells) item id lying there, -1
    items: np.ndarray  # (E, 6, items) I_*
    orders: np.ndarray  # (E, 4, n_orders) O_*
    stats: np.ndarray  # (E, 9)
    queue: np.ndarray  # (E, Q) recipe indices drawn ahead
    rewards: np.ndarray  # float64 (E, agents), the last step's
    subtasks: np.ndarray  # (E, agents): chops, washes and cooks each finished in the last step
    bumps: np.ndarray  # (E, 3, agents): each agent's last putdown (item, cell) / plate_add
    #   (item, plate), or B_NONE
    obs: np.ndarray  # float32 (E, agents, size)
    static_at: np.ndarray  # (E, agents): layout * cells + cell whose static part is in obs
    ent_idx: np.ndarray  # (E, agents + 1, K): last entries per agent; the last row is scratch
    ent_val: np.ndarray  # float32 (E, agents + 1, K)
    ent_n: np.ndarray  # (E, agents)
    scratch: np.ndarray  # int64 (E, 3, agents): move targets, status, chain


# ---------------------------------------------------------------- entry points
def step_range(k, g, actions, active, start, stop):
    """One step of every env ``e`` in ``start .. stop - 1`` with ``active[e]``, then their
    observations (compiled without the GIL: threads step disjoint ranges)."""
    clock, agents, cells, items, orders = k.clock, k.agents, k.cells, k.items, k.orders
    stats, queue, rewards, scratch, subtasks = k.stats, k.queue, k.rewards, k.scratch, k.subtasks
    bumps = k.bumps
    p, rw, terrain, walk, nbrs = g.params, g.rewards, g.terrain, g.walk, g.nbrs
    kind, home, kidx, recipes = g.kind, g.home, g.kind_index, g.recipes
    pans, switch_cells = g.pans, g.switch_cells
    obs, static_at, ent_idx, ent_val, ent_n = k.obs, k.static_at, k.ent_idx, k.ent_val, k.ent_n
    view, prog_den, static_obs, gather = g.obs_layout, g.prog_den, g.static_obs, g.static_gather
    for e in range(start, stop):
        if active[e]:
            step_env(e, actions, clock, agents, cells, items, orders, stats, queue, rewards,
                     subtasks, bumps, scratch, p, rw, terrain, walk, nbrs, kind, home, kidx,
                     recipes, pans, switch_cells)
            if p[P_OBSERVE]:
                observe_env(e, clock, agents, items, orders, obs, static_at, ent_idx, ent_val,
                            ent_n, p, view, kind, kidx, prog_den, recipes, static_obs, gather,
                            terrain.shape[1])


def reset_some(k, g, envs):
    """Start a new episode in each listed env (its queue already holds the new draws; a
    few envs a step: one thread)."""
    clock, agents, cells, items, orders = k.clock, k.agents, k.cells, k.items, k.orders
    p, kind, home, spawn, fixed = g.params, g.kind, g.home, g.spawn, g.fixed
    obs, static_at, ent_idx, ent_val, ent_n = k.obs, k.static_at, k.ent_idx, k.ent_val, k.ent_n
    stats, queue, kidx, recipes = k.stats, k.queue, g.kind_index, g.recipes
    view, prog_den, static_obs, gather = g.obs_layout, g.prog_den, g.static_obs, g.static_gather
    n_cells = g.terrain.shape[1]
    for j in range(len(envs)):
        e = envs[j]
        clock[e, C_T] = 0
        clock[e, C_LAYOUT] = 0
        clock[e, C_SWITCH] = p[P_SWITCH_STEP]
        clock[e, C_ORDER_ID] = 0
        for a in range(agents.shape[2]):
            agents[e, A_POS, a] = spawn[a]
            agents[e, A_HAND, a] = -1
        for c in range(cells.shape[1]):
            cells[e, c] = -1
        for i in range(items.shape[2]):
            items[e, I_STATE, i] = _CLEAN if kind[i] == _PLATE_KIND else _FRESH
            items[e, I_PROG, i] = 0
            items[e, I_WHERE, i] = _CELL
            items[e, I_LOC, i] = home[i]
            items[e, I_OWNER, i] = -1
            items[e, I_LIFE, i] = 0
            cells[e, home[i]] = i
        for s in range(stats.shape[1]):
            stats[e, s] = 0
        for o in range(orders.shape[2]):
            if p[P_FIXED]:
                recipe = fixed[clock[e, C_ORDER_ID] % len(fixed)]
            else:
                recipe = draw(e, clock, queue)
            put_order(e, o, recipe, clock, orders, p)
        if p[P_OBSERVE]:
            observe_env(e, clock, agents, items, orders, obs, static_at, ent_idx, ent_val,
                        ent_n, p, view, kind, kidx, prog_den, recipes, static_obs, gather,
                        n_cells)


def observe_some(k, g, envs):
    """Bring the observations of the listed envs up to date (after a state was loaded)."""
    if not g.params[P_OBSERVE]:
        return
    for j in range(len(envs)):
        observe_env(envs[j], k.clock, k.agents, k.items, k.orders, k.obs, k.static_at,
                    k.ent_idx, k.ent_val, k.ent_n, g.params, g.obs_layout, g.kind,
                    g.kind_index, g.prog_den, g.recipes, g.static_obs, g.static_gather,
                    g.terrain.shape[1])


# ---------------------------------------------------------------- orders
def draw(e, clock, queue):
    r = queue[e, clock[e, C_QPOS]]
    clock[e, C_QPOS] += 1
    return r


def put_order(e, slot, recipe, clock, orders, p):
    t = clock[e, C_T]
    orders[e, O_ID, slot] = clock[e, C_ORDER_ID]
    orders[e, O_RECIPE, slot] = recipe
    orders[e, O_CREATED, slot] = t
    orders[e, O_DEADLINE, slot] = t + p[P_LIMIT] if p[P_LIMIT] >= 0 else -1
    clock[e, C_ORDER_ID] += 1


def replace_order(e, slot, clock, orders, queue, p):
    """Drop order ``slot`` (later ones move up) and append its replacement."""
    recipe = orders[e, O_RECIPE, slot]
    last = orders.shape[2] - 1
    for o in range(slot, last):
        for f in range(4):
            orders[e, f, o] = orders[e, f, o + 1]
    put_order(e, last, recipe if p[P_FIXED] else draw(e, clock, queue), clock, orders, p)


def expire_orders(e, clock, orders, stats, queue, rewards, p, rw):
    n = rewards.shape[1]
    share = rw[R_EXPIRED] / n
    slot = 0
    for _ in range(orders.shape[2]):  # the orders open before this check, in order
        dl = orders[e, O_DEADLINE, slot]
        if 0 <= dl <= clock[e, C_T]:
            stats[e, EXPIRED] += 1
            for a in range(n):
                rewards[e, a] += share
            replace_order(e, slot, clock, orders, queue, p)
        else:
            slot += 1


# ---------------------------------------------------------------- the step
def step_env(e, actions, clock, agents, cells, items, orders, stats, queue, rewards, subtasks,
             bumps, scratch, p, rw, terrain, walk, nbrs, kind, home, kidx, recipes, pans,
             switch_cells):
    n = agents.shape[2]
    for a in range(n):
        rewards[e, a] = rw[R_STEP]
        subtasks[e, a] = 0
        bumps[e, 0, a] = B_NONE
    lay = clock[e, C_LAYOUT]
    moving = False
    for a in range(n):
        scratch[e, 0, a] = -1
        act = actions[e, a]
        if act == _STAY:
            continue
        tgt = nbrs[agents[e, A_POS, a], act]
        if tgt < 0:
            continue
        if walk[lay, tgt]:
            scratch[e, 0, a] = tgt
            moving = True
        else:
            held = agents[e, A_HAND, a]
            here = cells[e, tgt]
            interact(e, a, tgt, clock, agents, cells, items, orders, stats, queue, rewards,
                     subtasks, p, rw, terrain[lay, tgt], kind, home, kidx, recipes)
            record_bump(e, a, tgt, held, here, agents, cells, items, bumps)
    waiting = False
    for i in range(items.shape[2]):
        if items[e, I_WHERE, i] == _WAITING:
            waiting = True
    if waiting:
        for i in range(items.shape[2]):
            at = items[e, I_LOC, i]
            if items[e, I_WHERE, i] == _WAITING and cells[e, at] < 0:
                cells[e, at] = i
                items[e, I_WHERE, i] = _CELL
    if moving:
        resolve_moves(e, agents, scratch)
    for j in range(len(pans)):
        it = cells[e, pans[j]]
        if it >= 0:
            tick_pan(e, it, items, stats, rewards, subtasks, p, rw)
    clock[e, C_T] += 1
    if p[P_DYNAMIC] and clock[e, C_T] >= clock[e, C_SWITCH] and terrain.shape[0] > 1:
        maybe_switch(e, clock, agents, cells, stats, p, terrain, walk, switch_cells)
    if p[P_LIMIT] >= 0:
        expire_orders(e, clock, orders, stats, queue, rewards, p, rw)
    if p[P_SHARED]:
        total = 0.0
        for a in range(n):
            total += rewards[e, a]
        for a in range(n):
            rewards[e, a] = total


def record_bump(e, a, cell, held, here, agents, cells, items, bumps):
    """Note a putdown or a plate_add (step.py's events of those kinds) by agent ``a``, who
    held ``held`` and bumped ``cell`` holding ``here`` (reward shaping reads them)."""
    if held < 0:
        return
    if agents[e, A_HAND, a] < 0:
        if cells[e, cell] == held:
            bumps[e, 0, a] = B_PUTDOWN
            bumps[e, 1, a] = held
            bumps[e, 2, a] = cell
        elif items[e, I_WHERE, held] == _PLATE:
            bumps[e, 0, a] = B_PLATE_ADD
            bumps[e, 1, a] = held
            bumps[e, 2, a] = items[e, I_LOC, held]
    elif here >= 0 and items[e, I_WHERE, here] == _PLATE and items[e, I_LOC, here] == held:
        bumps[e, 0, a] = B_PLATE_ADD
        bumps[e, 1, a] = here
        bumps[e, 2, a] = held


def resolve_moves(e, agents, scratch):
    """Simultaneous moves (step._resolve_moves): contested cells, swaps and cycles block.
    ``scratch[e]`` rows: targets (filled by the caller), status, chain."""
    n = agents.shape[2]
    for a in range(n):  # status: 0 undecided, 1 moves, 2 stays (or not a mover)
        scratch[e, 1, a] = 2
        if scratch[e, 0, a] >= 0:
            same = 0
            for b in range(n):
                if scratch[e, 0, b] == scratch[e, 0, a]:
                    same += 1
            if same == 1:
                scratch[e, 1, a] = 0
    for a in range(n):
        if scratch[e, 1, a] != 0:
            continue
        scratch[e, 2, 0] = a
        length = 1
        b = occupant(e, scratch[e, 0, a], agents)
        while b >= 0 and scratch[e, 1, b] == 0 and not in_chain(e, length, b, scratch):
            scratch[e, 2, length] = b
            length += 1
            b = occupant(e, scratch[e, 0, b], agents)
        ok = b < 0 or scratch[e, 1, b] == 1
        for c in range(length):
            scratch[e, 1, scratch[e, 2, c]] = 1 if ok else 2
    for a in range(n):
        if scratch[e, 1, a] == 1:
            agents[e, A_POS, a] = scratch[e, 0, a]


def occupant(e, cell, agents):
    for a in range(agents.shape[2]):
        if agents[e, A_POS, a] == cell:
            return a
    return -1


def in_chain(e, length, b, scratch):
    for c in range(length):
        if scratch[e, 2, c] == b:
            return True
    return False


def tick_pan(e, it, items, stats, rewards, subtasks, p, rw):
    ticks = items[e, I_PROG, it] + 1
    items[e, I_PROG, it] = ticks
    st = items[e, I_STATE, it]
    owner = items[e, I_OWNER, it]
    if st == _FRESH and p[P_COOK] - ticks <= 0:
        items[e, I_STATE, it] = _COOKED
        stats[e, COOKS] += 1
        if owner >= 0:
            rewards[e, owner] += rw[R_SUBTASK]
            subtasks[e, owner] += 1
        st = _COOKED
    if st != _BURNT and p[P_BURN] + 1 - ticks <= 0:
        items[e, I_STATE, it] = _BURNT
        stats[e, BURNS] += 1
        if owner >= 0:
            rewards[e, owner] += rw[R_BURNED]


def maybe_switch(e, clock, agents, cells, stats, p, terrain, walk, switch_cells):
    old = clock[e, C_LAYOUT]
    new = 1 - old
    for j in range(len(switch_cells)):
        f = switch_cells[j]
        if not walk[new, f] and occupant(e, f, agents) >= 0:
            return
        if terrain[old, f] == _COUNTER and terrain[new, f] != _COUNTER and cells[e, f] >= 0:
            return
    clock[e, C_LAYOUT] = new
    clock[e, C_SWITCH] = clock[e, C_T] + p[P_SWITCH_STEP]
    stats[e, SWITCHES] += 1


# ---------------------------------------------------------------- bumps (queries.bump_effect)
def is_veg(kind):
    return kind == _TOMATO or kind == _LETTUCE or kind == _ONION


def plateable(e, it, items, kind):
    st = items[e, I_STATE, it]
    return (is_veg(kind[it]) and st == _CHOPPED) or (kind[it] == _STEAK and st == _COOKED)


def fresh_veg(e, it, items, kind):
    return is_veg(kind[it]) and items[e, I_STATE, it] == _FRESH


def on_plate(e, i, plate, items):
    return items[e, I_WHERE, i] == _PLATE and items[e, I_LOC, i] == plate


def interact(e, a, cell, clock, agents, cells, items, orders, stats, queue, rewards, subtasks,
             p, rw, code, kind, home, kidx, recipes):
    """Agent ``a`` bumps the non-walkable ``cell`` of terrain ``code``."""
    held = agents[e, A_HAND, a]
    here = cells[e, cell]
    if code == _COUNTER or code == _TOMATO or code == _LETTUCE or code == _PLATE_KIND \
            or code == _ONION or code == _STEAK or code == _PAN:
        if held < 0:
            if here >= 0:
                pick(e, a, cell, here, agents, cells, items)
        elif here >= 0:
            plate_exchange(e, a, cell, held, here, agents, cells, items, kind)
        elif code != _PAN:
            put(e, a, cell, held, agents, cells, items)
        elif kind[held] == _STEAK and (items[e, I_STATE, held] == _FRESH
                                       or items[e, I_STATE, held] == _COOKED):
            put(e, a, cell, held, agents, cells, items)
    elif code == _BOARD:
        if held < 0:
            if here >= 0:
                if fresh_veg(e, here, items, kind):
                    advance(e, a, here, p[P_CHOP], _CHOPPED, CHOPS, items, stats, rewards,
                            subtasks, rw)
                else:
                    pick(e, a, cell, here, agents, cells, items)
        elif here >= 0:
            plate_exchange(e, a, cell, held, here, agents, cells, items, kind)
        elif fresh_veg(e, held, items, kind):
            put(e, a, cell, held, agents, cells, items)
    elif code == _SINK:
        if held < 0:
            if here >= 0:
                if items[e, I_STATE, here] == _DIRTY:
                    advance(e, a, here, p[P_WASH], _CLEAN, WASHES, items, stats, rewards,
                            subtasks, rw)
                else:
                    pick(e, a, cell, here, agents, cells, items)
        elif here < 0 and items[e, I_STATE, held] == _DIRTY:
            put(e, a, cell, held, agents, cells, items)
    elif code == _DELIVERY:
        if held >= 0:
            deliver(e, a, held, clock, agents, cells, items, orders, stats, queue, rewards, p,
                    rw, kind, home, kidx, recipes)
    elif code == _TRASH and held >= 0:
        if kind[held] != _PLATE_KIND:
            agents[e, A_HAND, a] = -1
            send_home(e, held, _FRESH, cells, items, home)
        else:  # the plate is emptied (an empty one: nothing to throw away)
            for i in range(items.shape[2]):
                if on_plate(e, i, held, items):
                    send_home(e, i, _FRESH, cells, items, home)


def plate_exchange(e, a, cell, held, here, agents, cells, items, kind):
    if kind[here] == _PLATE_KIND and items[e, I_STATE, here] == _CLEAN \
            and plateable(e, held, items, kind):
        agents[e, A_HAND, a] = -1
        items[e, I_WHERE, held] = _PLATE
        items[e, I_LOC, held] = here
    elif kind[held] == _PLATE_KIND and items[e, I_STATE, held] == _CLEAN \
            and plateable(e, here, items, kind):
        cells[e, cell] = -1
        items[e, I_WHERE, here] = _PLATE
        items[e, I_LOC, here] = held
        items[e, I_OWNER, here] = a


def pick(e, a, cell, it, agents, cells, items):
    cells[e, cell] = -1
    agents[e, A_HAND, a] = it
    items[e, I_WHERE, it] = _HAND
    items[e, I_LOC, it] = a
    items[e, I_OWNER, it] = a


def put(e, a, cell, it, agents, cells, items):
    agents[e, A_HAND, a] = -1
    cells[e, cell] = it
    items[e, I_WHERE, it] = _CELL
    items[e, I_LOC, it] = cell


def advance(e, a, it, needed, done_state, stat, items, stats, rewards, subtasks, rw):
    items[e, I_PROG, it] += 1
    items[e, I_OWNER, it] = a
    if items[e, I_PROG, it] >= needed:
        items[e, I_STATE, it] = done_state
        items[e, I_PROG, it] = 0
        stats[e, stat] += 1
        rewards[e, a] += rw[R_SUBTASK]
        subtasks[e, a] += 1


def send_home(e, it, state, cells, items, home):
    h = home[it]
    items[e, I_STATE, it] = state
    items[e, I_PROG, it] = 0
    items[e, I_OWNER, it] = -1
    items[e, I_LOC, it] = h
    items[e, I_LIFE, it] += 1
    if cells[e, h] < 0:
        cells[e, h] = it
        items[e, I_WHERE, it] = _CELL
    else:
        items[e, I_WHERE, it] = _WAITING


def deliver(e, a, held, clock, agents, cells, items, orders, stats, queue, rewards, p, rw,
            kind, home, kidx, recipes):
    slot = -1
    if kind[held] == _PLATE_KIND:
        slot = matching_order(e, held, items, orders, kind, kidx, recipes)
    if slot < 0:
        stats[e, WRONG] += 1
        rewards[e, a] += rw[R_WRONG]
        return
    stats[e, DISHES] += 1
    stats[e, COMPLETED] += 1
    rewards[e, a] += rw[R_CORRECT]
    for i in range(items.shape[2]):
        if on_plate(e, i, held, items):
            send_home(e, i, _FRESH, cells, items, home)
    agents[e, A_HAND, a] = -1
    send_home(e, held, _DIRTY if p[P_DIRTY] else _CLEAN, cells, items, home)
    replace_order(e, slot, clock, orders, queue, p)


def matching_order(e, plate, items, orders, kind, kidx, recipes):
    """The slot of the oldest order the plate serves (orders.plate_recipe / matching_order)."""
    if items[e, I_STATE, plate] != _CLEAN:
        return -1
    c0 = c1 = c2 = c3 = 0
    for i in range(items.shape[2]):
        if on_plate(e, i, plate, items):
            if not plateable(e, i, items, kind):
                return -1
            j = kidx[kind[i]]
            if j == 0:
                c0 += 1
            elif j == 1:
                c1 += 1
            elif j == 2:
                c2 += 1
            else:
                c3 += 1
    if c0 + c1 + c2 + c3 == 0:
        return -1
    for o in range(orders.shape[2]):
        r = orders[e, O_RECIPE, o]
        if recipes[r, 0] == c0 and recipes[r, 1] == c1 and recipes[r, 2] == c2 \
                and recipes[r, 3] == c3:
            return o
    return -1


# ---------------------------------------------------------------- observations
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
        if w == _CELL:
            cell = loc
        elif w == _HAND:
            cell = agents[e, A_POS, loc]
        elif w == _PLATE:
            if items[e, I_WHERE, loc] == _CELL:
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
        if prog != 0 and w != _PLATE:
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
        if kind[held] == _PLATE_KIND:
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


KERNELS = (
    "step_range", "reset_some", "observe_some", "draw", "put_order", "replace_order",
    "expire_orders", "step_env", "record_bump", "resolve_moves", "occupant", "in_chain",
    "tick_pan", "maybe_switch", "is_veg", "plateable", "fresh_veg", "on_plate", "interact",
    "plate_exchange", "pick", "put", "advance", "send_home", "deliver", "matching_order",
    "observe_env", "window_index", "entries",
)

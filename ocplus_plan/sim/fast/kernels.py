"""The kitchen's rules as array kernels: the step of :mod:`ocplus_plan.sim.step`, one env row
at a time, written in the subset of Python that numba compiles.

Plain Python as it stands (the fallback, and what ``numba`` compiles: see
:func:`ocplus_plan.sim.fast.batch.kernels`). The state of ``E`` kitchens lives in a few integer
arrays whose first axis is the env (:class:`.arrays.KitchenArrays`); the tables of one rule set in
:class:`.arrays.StaticArrays`. The functions follow ``step.py`` rule for rule and in the same order
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
* observations are kept, not rebuilt, by :mod:`.observe_kernels` after every step;
* the codes and array layouts are :mod:`.arrays`' (the codes come from ``sim/codes.py``).
"""

from __future__ import annotations

from .arrays import (
    ACTION_STAY, A_HAND, A_POS, B_NONE, B_PLATE_ADD, B_PUTDOWN, CELL_COUNTER, CELL_DELIVERY,
    CELL_TRASH, COMPLETED, C_LAYOUT, C_ORDER_ID, C_QPOS, C_SWITCH, C_T, DISHES, EXPIRED,
    ITEM_LETTUCE, ITEM_ONION, ITEM_PLATE, ITEM_STEAK, ITEM_TOMATO, I_LIFE, I_LOC, I_OWNER,
    I_PROG, I_STATE, I_WHERE, O_CREATED, O_DEADLINE, O_ID, O_RECIPE, PN_DONE, PN_DURATION,
    PN_OVER_STAT, PN_OVER_STATE, PN_OVERRUN, PN_PLATES, PN_STAT, PN_TAKES, P_DIRTY, P_DYNAMIC,
    P_FIXED, P_LIMIT, P_OBSERVE, P_SHARED, P_SWITCH_STEP, R_BURNED, R_DISH, R_EXPIRED,
    R_STEP, R_SUBTASK, R_WRONG, STATE_CLEAN, STATE_DIRTY, STATE_FRESH, SWITCHES, WHERE_CELL,
    WHERE_HAND, WHERE_PLATE, WHERE_WAITING, WRONG,
)
from .observe_kernels import observe_env, on_plate


# ---------------------------------------------------------------- entry points
def step_range(k, g, actions, active, start, stop):
    """One step of every env ``e`` in ``start .. stop - 1`` with ``active[e]``, then their
    observations (compiled without the GIL: threads step disjoint ranges)."""
    clock, agents, cells, items, orders = k.clock, k.agents, k.cells, k.items, k.orders
    stats, queue, rewards, scratch, subtasks = k.stats, k.queue, k.rewards, k.scratch, k.subtasks
    bumps = k.bumps
    p, rw, terrain, walk, nbrs = g.params, g.rewards, g.terrain, g.walk, g.nbrs
    kind, home, kidx, recipes = g.kind, g.home, g.kind_index, g.recipes
    timed, switch_cells = g.timed, g.switch_cells
    proc_of, proc, accepts, works, plateable = g.proc_of, g.proc, g.accepts, g.works, g.plateable
    obs, static_at, ent_idx, ent_val, ent_n = k.obs, k.static_at, k.ent_idx, k.ent_val, k.ent_n
    view, prog_den, static_obs, gather = g.obs_layout, g.prog_den, g.static_obs, g.static_gather
    for e in range(start, stop):
        if active[e]:
            step_env(e, actions, clock, agents, cells, items, orders, stats, queue, rewards,
                     subtasks, bumps, scratch, p, rw, terrain, walk, nbrs, kind, home, kidx,
                     recipes, timed, switch_cells, proc_of, proc, accepts, works, plateable)
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
            items[e, I_STATE, i] = STATE_CLEAN if kind[i] == ITEM_PLATE else STATE_FRESH
            items[e, I_PROG, i] = 0
            items[e, I_WHERE, i] = WHERE_CELL
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
             bumps, scratch, p, rw, terrain, walk, nbrs, kind, home, kidx, recipes, timed,
             switch_cells, proc_of, proc, accepts, works, plateable):
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
        if act == ACTION_STAY:
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
                     subtasks, p, rw, terrain[lay, tgt], kind, home, kidx, recipes, proc_of,
                     proc, accepts, works, plateable)
            record_bump(e, a, tgt, held, here, agents, cells, items, bumps)
    waiting = False
    for i in range(items.shape[2]):
        if items[e, I_WHERE, i] == WHERE_WAITING:
            waiting = True
    if waiting:
        for i in range(items.shape[2]):
            at = items[e, I_LOC, i]
            if items[e, I_WHERE, i] == WHERE_WAITING and cells[e, at] < 0:
                cells[e, at] = i
                items[e, I_WHERE, i] = WHERE_CELL
    if moving:
        resolve_moves(e, agents, scratch)
    for j in range(len(timed)):
        it = cells[e, timed[j]]
        if it >= 0:
            tick(e, it, proc_of[terrain[0, timed[j]]], items, stats, rewards, subtasks, proc, rw)
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
        elif items[e, I_WHERE, held] == WHERE_PLATE:
            bumps[e, 0, a] = B_PLATE_ADD
            bumps[e, 1, a] = held
            bumps[e, 2, a] = items[e, I_LOC, held]
    elif here >= 0 and items[e, I_WHERE, here] == WHERE_PLATE and items[e, I_LOC, here] == held:
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


def tick(e, it, j, items, stats, rewards, subtasks, proc, rw):
    """One tick of the time-driven process ``j`` (step._tick)."""
    ticks = items[e, I_PROG, it] + 1
    items[e, I_PROG, it] = ticks
    st = items[e, I_STATE, it]
    owner = items[e, I_OWNER, it]
    if st == proc[j, PN_TAKES] and ticks >= proc[j, PN_DURATION]:
        st = proc[j, PN_DONE]
        items[e, I_STATE, it] = st
        stats[e, proc[j, PN_STAT]] += 1
        if owner >= 0:
            rewards[e, owner] += rw[R_SUBTASK]
            subtasks[e, owner] += 1
    over = proc[j, PN_OVER_STATE]
    if over >= 0 and st != over and ticks > proc[j, PN_OVERRUN]:
        items[e, I_STATE, it] = over
        stats[e, proc[j, PN_OVER_STAT]] += 1
        if owner >= 0:
            rewards[e, owner] += rw[R_BURNED]


def maybe_switch(e, clock, agents, cells, stats, p, terrain, walk, switch_cells):
    old = clock[e, C_LAYOUT]
    new = 1 - old
    for j in range(len(switch_cells)):
        f = switch_cells[j]
        if not walk[new, f] and occupant(e, f, agents) >= 0:
            return
        if terrain[old, f] == CELL_COUNTER and terrain[new, f] != CELL_COUNTER \
                and cells[e, f] >= 0:
            return
    clock[e, C_LAYOUT] = new
    clock[e, C_SWITCH] = clock[e, C_T] + p[P_SWITCH_STEP]
    stats[e, SWITCHES] += 1


# ---------------------------------------------------------------- bumps (queries.bump_effect)
def is_plateable(e, it, items, kind, plateable):
    return plateable[kind[it], items[e, I_STATE, it]]


def interact(e, a, cell, clock, agents, cells, items, orders, stats, queue, rewards, subtasks,
             p, rw, code, kind, home, kidx, recipes, proc_of, proc, accepts, works, plateable):
    """Agent ``a`` bumps the non-walkable ``cell`` of terrain ``code``."""
    held = agents[e, A_HAND, a]
    here = cells[e, cell]
    j = proc_of[code] if code >= 0 else -1
    if code == CELL_COUNTER or code == ITEM_TOMATO or code == ITEM_LETTUCE or code == ITEM_PLATE \
            or code == ITEM_ONION or code == ITEM_STEAK:
        if held < 0:
            if here >= 0:
                pick(e, a, cell, here, agents, cells, items)
        elif here >= 0:
            plate_exchange(e, a, cell, held, here, agents, cells, items, kind, plateable)
        else:
            put(e, a, cell, held, agents, cells, items)
    elif j >= 0:  # a process station: its record's tables say
        if held < 0:
            if here >= 0:
                if works[j, kind[here], items[e, I_STATE, here]]:
                    advance(e, a, here, proc[j, PN_DURATION], proc[j, PN_DONE], proc[j, PN_STAT],
                            items, stats, rewards, subtasks, rw)
                else:
                    pick(e, a, cell, here, agents, cells, items)
        elif here >= 0:
            if proc[j, PN_PLATES]:
                plate_exchange(e, a, cell, held, here, agents, cells, items, kind, plateable)
        elif accepts[j, kind[held], items[e, I_STATE, held]]:
            put(e, a, cell, held, agents, cells, items)
    elif code == CELL_DELIVERY:
        if held >= 0:
            deliver(e, a, held, clock, agents, cells, items, orders, stats, queue, rewards, p,
                    rw, kind, home, kidx, recipes, plateable)
    elif code == CELL_TRASH and held >= 0:
        if kind[held] != ITEM_PLATE:
            agents[e, A_HAND, a] = -1
            send_home(e, held, STATE_FRESH, cells, items, home)
        else:  # the plate is emptied (an empty one: nothing to throw away)
            for i in range(items.shape[2]):
                if on_plate(e, i, held, items):
                    send_home(e, i, STATE_FRESH, cells, items, home)


def plate_exchange(e, a, cell, held, here, agents, cells, items, kind, plateable):
    if kind[here] == ITEM_PLATE and items[e, I_STATE, here] == STATE_CLEAN \
            and is_plateable(e, held, items, kind, plateable):
        agents[e, A_HAND, a] = -1
        items[e, I_WHERE, held] = WHERE_PLATE
        items[e, I_LOC, held] = here
    elif kind[held] == ITEM_PLATE and items[e, I_STATE, held] == STATE_CLEAN \
            and is_plateable(e, here, items, kind, plateable):
        cells[e, cell] = -1
        items[e, I_WHERE, here] = WHERE_PLATE
        items[e, I_LOC, here] = held
        items[e, I_OWNER, here] = a


def pick(e, a, cell, it, agents, cells, items):
    cells[e, cell] = -1
    agents[e, A_HAND, a] = it
    items[e, I_WHERE, it] = WHERE_HAND
    items[e, I_LOC, it] = a
    items[e, I_OWNER, it] = a


def put(e, a, cell, it, agents, cells, items):
    agents[e, A_HAND, a] = -1
    cells[e, cell] = it
    items[e, I_WHERE, it] = WHERE_CELL
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
        items[e, I_WHERE, it] = WHERE_CELL
    else:
        items[e, I_WHERE, it] = WHERE_WAITING


def deliver(e, a, held, clock, agents, cells, items, orders, stats, queue, rewards, p, rw,
            kind, home, kidx, recipes, plateable):
    slot = -1
    if kind[held] == ITEM_PLATE:
        slot = matching_order(e, held, items, orders, kind, kidx, recipes, plateable)
    if slot < 0:
        stats[e, WRONG] += 1
        rewards[e, a] += rw[R_WRONG]
        return
    stats[e, DISHES] += 1
    stats[e, COMPLETED] += 1
    rewards[e, a] += rw[R_DISH + orders[e, O_RECIPE, slot]]  # the served dish's reward
    for i in range(items.shape[2]):
        if on_plate(e, i, held, items):
            send_home(e, i, STATE_FRESH, cells, items, home)
    agents[e, A_HAND, a] = -1
    send_home(e, held, STATE_DIRTY if p[P_DIRTY] else STATE_CLEAN, cells, items, home)
    replace_order(e, slot, clock, orders, queue, p)


def matching_order(e, plate, items, orders, kind, kidx, recipes, plateable):
    """The slot of the oldest order the plate serves (orders.plate_recipe / matching_order)."""
    if items[e, I_STATE, plate] != STATE_CLEAN:
        return -1
    c0 = c1 = c2 = c3 = 0
    for i in range(items.shape[2]):
        if on_plate(e, i, plate, items):
            if not is_plateable(e, i, items, kind, plateable):
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


KERNELS = (
    "step_range", "reset_some", "observe_some", "draw", "put_order", "replace_order",
    "expire_orders", "step_env", "record_bump", "resolve_moves", "occupant", "in_chain",
    "tick", "maybe_switch", "is_plateable", "interact",
    "plate_exchange", "pick", "put", "advance", "send_home", "deliver", "matching_order",
)
#: kernels of other modules these call: compiled there and put in place of the imports
KERNELS_FROM = {"observe_env": "ocplus_plan.sim.fast.observe_kernels",
                "on_plate": "ocplus_plan.sim.fast.observe_kernels"}

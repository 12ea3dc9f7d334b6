"""The RL baseline's features and reward shaping as array kernels over the batched engine's
state (:class:`ocplus_plan.sim.fast.arrays.KitchenArrays`), written in the subset of
Python that numba compiles (plain Python without the ``fast`` extra, as the engine's own
kernels: see :func:`ocplus_plan.sim.fast.batch.compile_kernels`).

They follow :class:`ocplus_plan.rl.features.FeatureEncoder` and
:class:`ocplus_plan.rl.shaping.RewardShaper` line for line and in the same order of
floating-point operations, so the values are the same bits (``tests/rl/fast/test_features_batch.py``
steps both side by side). The glue (tables, scratch, the per-call API) is
:mod:`ocplus_plan.rl.fast.features_batch`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...sim.fast.arrays import (
    A_HAND, A_POS, B_PLATE_ADD, B_PUTDOWN, C_LAYOUT, C_SWITCH, C_T, CELL_BOARD, CELL_DELIVERY,
    CELL_PAN, CELL_SINK, CELL_TRASH, I_LIFE, I_LOC, I_PROG, I_STATE, I_WHERE, ITEM_PLATE,
    ITEM_STEAK, O_RECIPE, STATE_CHOPPED, STATE_CLEAN, STATE_COOKED, STATE_DIRTY, STATE_FRESH,
    WHERE_PLATE,
)

_NO_PATH = 1 << 30
PATH_SCALE = 20.0
# target indices (features.TARGETS order)
(T_FRESH_TOMATO, T_FRESH_LETTUCE, T_FRESH_ONION, T_RAW_STEAK, T_BOARD_TO_CHOP,
 T_CHOPPED_TOMATO, T_CHOPPED_LETTUCE, T_CHOPPED_ONION, T_COOKING_STEAK, T_COOKED_STEAK,
 T_BURNT_STEAK, T_CLEAN_PLATE, T_DIRTY_PLATE, T_SINK_TO_WASH, T_FREE_BOARD, T_FREE_PAN,
 T_FREE_SINK, T_FREE_COUNTER, T_DELIVERY, T_TRASH, T_WANTED_FRESH, T_WANTED_READY) = range(22)
N_TARGETS = 22
# feature offsets (features.FeatureEncoder.feature_names; checked by the glue)
F_HAND = 6 * N_TARGETS
F_HAND_PLATE = F_HAND + 13
F_NEAR_PLATE = F_HAND_PLATE + 10
F_ORDERS = F_NEAR_PLATE + 10
MAX_ORDERS = 3
F_DEMAND = F_ORDERS + 5 * MAX_ORDERS
F_ADJ = F_DEMAND + 4
F_OTHERS = F_ADJ + 8
MAX_OTHERS = 2
F_CLOCK = F_OTHERS + 9 * MAX_OTHERS
N_FEATURES = F_CLOCK + 5
# params of FeatureTables
Q_ROWS, Q_COLS, Q_HORIZON, Q_DYNAMIC, Q_SWITCH_STEP, Q_COOK, Q_BURN = range(7)
# shaping weights (Shaping) and the rules' subtask reward
W_SUBTASK_SCALE, W_STAGE, W_USEFUL_PLATE, W_CARRY_FRESH, W_CARRY_READY, W_CARRY_DISH, \
    W_SUBTASK = range(7)


class FeatureTables(NamedTuple):
    """One rule set's tables (built by :mod:`ocplus_plan.rl.fast.features_batch`)."""

    params: np.ndarray  # int64 (7,) Q_*
    terrain: np.ndarray  # int64 (layouts, cells)
    walk: np.ndarray  # bool (layouts, cells)
    nbrs: np.ndarray  # int64 (cells, 4)
    interact: np.ndarray  # int64 (layouts, K): cells an agent can bump, -1 padded
    is_counter: np.ndarray  # bool (16,): cell code -> counter or spawn tile
    kind: np.ndarray  # int64 (items,)
    kind_index: np.ndarray  # int64 (16,): kind -> 0..4 (tomato lettuce onion steak plate)
    recipes: np.ndarray  # int64 (recipes, 4) ingredient counts
    to_delivery: np.ndarray  # int64 (layouts, cells): steps to a serving spot, -1
    weights: np.ndarray  # float64 (7,) W_*
    free_reach: np.ndarray  # int64 (layouts, cells, 2, K): reach_cells ignoring other agents


# ---------------------------------------------------------------- entry points
def features_range(k, g, out, active, start, stop):
    """Every agent's features of the envs ``e`` in ``start .. stop - 1`` with ``active[e]``
    into ``out`` (E, agents, size)."""
    n_cells = g.nbrs.shape[0]
    dist = np.empty(n_cells, np.int64)
    first = np.empty(n_cells, np.int64)
    queue = np.empty(n_cells, np.int64)
    n_k = g.interact.shape[1]
    reach = np.empty((2, n_k), np.int64)
    best = np.empty((3, N_TARGETS), np.int64)
    wanted = np.zeros(5, np.bool_)
    counts = np.zeros(4, np.int64)
    gap = np.zeros((2, 4), np.int64)
    for e in range(start, stop):
        if not active[e]:
            continue
        wanted_kinds(e, k.orders, g.recipes, wanted)
        for a in range(k.agents.shape[2]):
            encode(e, a, k.clock, k.agents, k.cells, k.items, k.orders, g, out, dist, first,
                   queue, reach, best, wanted, counts, gap)


def shaping_range(k, g, before, paid, coef, team, true, out, active, start, stop):
    """Each agent's training reward after a step (``RewardShaper.step`` then the vec env's
    mix): ``true`` gets the game reward without the subtask part, ``out`` the reward the
    learner sees before scaling; ``before`` (E, agents) holds the potentials and ``paid``
    (E, items) the life + 1 in which an item's ``stage`` milestone was paid; envs without
    ``active[e]`` are left alone."""
    w = g.weights
    n = k.agents.shape[2]
    counts = np.zeros(4, np.int64)
    for e in range(start, stop):
        if not active[e]:
            continue
        lay = k.clock[e, C_LAYOUT]
        team_true = 0.0
        for a in range(n):
            t = k.rewards[e, a]
            s = 0.0
            what = k.bumps[e, 0, a]
            it = k.bumps[e, 1, a]
            if what == B_PUTDOWN and w[W_STAGE] and paid[e, it] != k.items[e, I_LIFE, it] + 1:
                code = g.terrain[lay, k.bumps[e, 2, a]]
                st = k.items[e, I_STATE, it]
                need = needed(e, g.kind[it], k.orders, g.kind_index, g.recipes)
                if (code == CELL_BOARD and need) \
                        or (code == CELL_PAN and st == STATE_FRESH and need) \
                        or (code == CELL_SINK and st == STATE_DIRTY):
                    s += w[W_STAGE]
                    paid[e, it] = k.items[e, I_LIFE, it] + 1
            elif what == B_PLATE_ADD and w[W_USEFUL_PLATE]:
                if fits_order(e, k.bumps[e, 2, a], k.items, k.orders, g, counts, False):
                    s += w[W_USEFUL_PLATE]
            for _ in range(k.subtasks[e, a]):
                t -= w[W_SUBTASK]
                s += w[W_SUBTASK_SCALE] * w[W_SUBTASK]
            phi = potential(e, a, lay, k.agents, k.items, k.orders, g, counts)
            s += phi - before[e, a]
            before[e, a] = phi
            true[e, a] = t
            out[e, a] = s
            team_true += t
        for a in range(n):
            out[e, a] = (team_true if team else true[e, a]) + coef * out[e, a]


# ---------------------------------------------------------------- orders and plates
def wanted_kinds(e, orders, recipes, wanted):
    """``wanted[j]``: an active order needs ingredient ``j``."""
    for j in range(5):
        wanted[j] = False
    for o in range(orders.shape[2]):
        r = orders[e, O_RECIPE, o]
        for j in range(4):
            if recipes[r, j] > 0:
                wanted[j] = True


def needed(e, kind, orders, kidx, recipes):
    """Some active order's recipe contains ``kind`` (shaping._needed)."""
    j = kidx[kind]
    if j > 3:
        return False
    for o in range(orders.shape[2]):
        if recipes[orders[e, O_RECIPE, o], j] > 0:
            return True
    return False


def plate_contents(e, plate, items, kind, kidx, counts):
    """Count the plate's ingredients into ``counts``; True when all are ready (so the
    plate serves a recipe when clean and not empty: orders.plate_recipe)."""
    for j in range(4):
        counts[j] = 0
    ready = True
    for i in range(items.shape[2]):
        if items[e, I_WHERE, i] == WHERE_PLATE and items[e, I_LOC, i] == plate:
            counts[kidx[kind[i]]] += 1
            st = items[e, I_STATE, i]
            if kind[i] == ITEM_STEAK:
                if st != STATE_COOKED:
                    ready = False
            elif st != STATE_CHOPPED:
                ready = False
    return ready


def fits_order(e, plate, items, orders, g, counts, complete):
    """shaping._fits_an_order: the plate serves a recipe that is part of (equal to, if
    ``complete``) an active order."""
    ready = plate_contents(e, plate, items, g.kind, g.kind_index, counts)
    total = counts[0] + counts[1] + counts[2] + counts[3]
    if items[e, I_STATE, plate] != STATE_CLEAN or not ready or total == 0:
        return False
    for o in range(orders.shape[2]):
        r = orders[e, O_RECIPE, o]
        ok = True
        for j in range(4):
            c = g.recipes[r, j]
            if counts[j] > c or (complete and counts[j] != c):
                ok = False
        if ok:
            return True
    return False


def potential(e, a, lay, agents, items, orders, g, counts):
    """RewardShaper.potential: what agent ``a`` carries is worth."""
    held = agents[e, A_HAND, a]
    if held < 0:
        return 0.0
    w = g.weights
    k = g.kind[held]
    if k == ITEM_PLATE:
        if w[W_CARRY_DISH] and fits_order(e, held, items, orders, g, counts, True):
            d = g.to_delivery[lay, agents[e, A_POS, a]]
            near = 1.0 - min(d, 20) / 20 if d >= 0 else 0.0
            return w[W_CARRY_DISH] * (1.0 + near)
        return 0.0
    if not needed(e, k, orders, g.kind_index, g.recipes):
        return 0.0
    st = items[e, I_STATE, held]
    if (k == ITEM_STEAK and st == STATE_COOKED) or (k != ITEM_STEAK and st == STATE_CHOPPED):
        return w[W_CARRY_READY]
    return w[W_CARRY_FRESH] if st == STATE_FRESH else 0.0


def plate_summary(e, plate, items, orders, g, counts, gap, out, a, off):
    """FeatureEncoder._plate_summary of ``plate`` into ``out[e, a, off : off + 10]``."""
    ready = plate_contents(e, plate, items, g.kind, g.kind_index, counts)
    total = counts[0] + counts[1] + counts[2] + counts[3]
    best_sum = -1
    for o in range(orders.shape[2]):
        r = orders[e, O_RECIPE, o]
        fits = True
        gap_sum = 0
        for j in range(4):
            gap[0, j] = g.recipes[r, j] - counts[j]
            if gap[0, j] < 0:
                fits = False
            gap_sum += gap[0, j]
        if fits and (best_sum < 0 or gap_sum < best_sum):
            best_sum = gap_sum
            for j in range(4):
                gap[1, j] = gap[0, j]
    for j in range(4):
        out[e, a, off + j] = counts[j] / 2
    clean = items[e, I_STATE, plate] == STATE_CLEAN
    if best_sum >= 0 and clean and ((ready and total > 0) or total == 0):
        out[e, a, off + 4] = 1.0
        out[e, a, off + 5] = 1.0 if best_sum == 0 else 0.0
        for j in range(4):
            out[e, a, off + 6 + j] = gap[1, j] / 2
    else:
        for j in range(4, 10):
            out[e, a, off + j] = 0.0


# ---------------------------------------------------------------- paths
def bfs(e, me, lay, agents, walk, nbrs, avoid, dist, first, queue):
    """queries.walks from agent ``me``'s cell, around the other agents when ``avoid``."""
    for c in range(nbrs.shape[0]):
        dist[c] = -1
        first[c] = -1
    pos = agents[e, A_POS, me]
    dist[pos] = 0
    queue[0] = pos
    head, tail = 0, 1
    while head < tail:
        cur = queue[head]
        head += 1
        d = dist[cur] + 1
        for act in range(4):
            nxt = nbrs[cur, act]
            if nxt < 0 or dist[nxt] >= 0 or not walk[lay, nxt]:
                continue
            if avoid and occupied_by_other(e, me, nxt, agents):
                continue
            dist[nxt] = d
            first[nxt] = act if head <= 1 else first[cur]
            queue[tail] = nxt
            tail += 1


def occupied_by_other(e, me, cell, agents):
    for b in range(agents.shape[2]):
        if b != me and agents[e, A_POS, b] == cell:
            return True
    return False


def reach_cells(pos, lay, interact, nbrs, dist, first, reach):
    """FeatureEncoder._bfs: per interaction cell, path cost incl. the bump and first action
    (``_NO_PATH``, -1 when none)."""
    missing = False
    for idx in range(interact.shape[1]):
        c = interact[lay, idx]
        if c < 0:
            break
        best, act = _NO_PATH, -1
        for d in range(4):
            v = nbrs[c, d]
            if v >= 0 and 0 <= dist[v] < best:
                best = dist[v]
                if v == pos:
                    act = -1
                    for b in range(4):  # queries.direction: the first action into c
                        if act < 0 and nbrs[pos, b] == c:
                            act = b
                else:
                    act = first[v]
        reach[0, idx] = best + 1 if act >= 0 else _NO_PATH
        reach[1, idx] = act
        if act < 0:
            missing = True
    return missing


# ---------------------------------------------------------------- one agent's features
def target_of(code, it, st, k, kidx, is_counter):
    """The TARGETS index of an interaction cell (-1: none), as FeatureEncoder._encode."""
    if code == CELL_DELIVERY:
        return T_DELIVERY
    if code == CELL_TRASH:
        return T_TRASH
    if it < 0:
        if code == CELL_BOARD:
            return T_FREE_BOARD
        if code == CELL_PAN:
            return T_FREE_PAN
        if code == CELL_SINK:
            return T_FREE_SINK
        if is_counter[code]:
            return T_FREE_COUNTER
        return -1
    if k == ITEM_PLATE:
        if st == STATE_CLEAN:
            return T_CLEAN_PLATE
        return T_SINK_TO_WASH if code == CELL_SINK else T_DIRTY_PLATE
    if k == ITEM_STEAK:
        if st == STATE_FRESH:
            return T_COOKING_STEAK if code == CELL_PAN else T_RAW_STEAK
        if st == STATE_COOKED:
            return T_COOKED_STEAK
        return T_BURNT_STEAK
    if st == STATE_FRESH:
        return T_BOARD_TO_CHOP if code == CELL_BOARD else T_FRESH_TOMATO + kidx[k]
    if st == STATE_CHOPPED:
        return T_CHOPPED_TOMATO + kidx[k]
    return -1


def nearest(e, a, lay, pos, n, cells, items, agents, g, dist, first, queue, reach, best,
            wanted):
    """FeatureEncoder._nearest: per target, the cheapest walk's cost, first action and cell
    into ``best[0..2]`` (``_NO_PATH``, -1, -1: none reachable)."""
    nbrs, interact, kind, kidx = g.nbrs, g.interact, g.kind, g.kind_index
    bfs(e, a, lay, agents, g.walk, nbrs, n > 1, dist, first, queue)
    missing = reach_cells(pos, lay, interact, nbrs, dist, first, reach)
    if n > 1 and missing:  # cells reachable only through others: the path ignoring them
        for idx in range(interact.shape[1]):
            if reach[1, idx] < 0:
                reach[0, idx] = g.free_reach[lay, pos, 0, idx]
                reach[1, idx] = g.free_reach[lay, pos, 1, idx]
    for t in range(N_TARGETS):
        best[0, t] = _NO_PATH
        best[1, t] = -1
        best[2, t] = -1
    for idx in range(interact.shape[1]):
        c = interact[lay, idx]
        if c < 0:
            break
        cost, act = reach[0, idx], reach[1, idx]
        if act < 0:
            continue
        it = cells[e, c]
        k = kind[it] if it >= 0 else -1
        st = items[e, I_STATE, it] if it >= 0 else -1
        t = target_of(g.terrain[lay, c], it, st, k, kidx, g.is_counter)
        if t < 0:
            continue
        if cost < best[0, t]:
            best[0, t], best[1, t], best[2, t] = cost, act, c
        if it >= 0 and kidx[k] < 4 and wanted[kidx[k]]:
            w = -1
            if t == T_FRESH_TOMATO or t == T_FRESH_LETTUCE or t == T_FRESH_ONION \
                    or t == T_RAW_STEAK:
                w = T_WANTED_FRESH
            elif t == T_CHOPPED_TOMATO or t == T_CHOPPED_LETTUCE or t == T_CHOPPED_ONION \
                    or t == T_COOKED_STEAK:
                w = T_WANTED_READY
            if w >= 0 and cost < best[0, w]:
                best[0, w], best[1, w], best[2, w] = cost, act, c


def around(e, a, lay, pos, n, agents, g, out):
    """FeatureEncoder._around: the four neighbours (walkable, taken) and the other cooks."""
    p, nbrs, kind, kidx = g.params, g.nbrs, g.kind, g.kind_index
    for d in range(4):
        v = nbrs[pos, d]
        out[e, a, F_ADJ + 2 * d] = 1.0 if v >= 0 and g.walk[lay, v] else 0.0
        out[e, a, F_ADJ + 2 * d + 1] = 1.0 if v >= 0 and occupied_by_other(e, a, v, agents) \
            else 0.0

    rows, cols = p[Q_ROWS], p[Q_COLS]
    row, col = pos // cols, pos % cols
    for k in range(1, MAX_OTHERS + 1):
        if k < n:
            b = (a + k) % n
            bpos = agents[e, A_POS, b]
            off = F_OTHERS + 9 * (k - 1)
            out[e, a, off] = (bpos // cols - row) / rows
            out[e, a, off + 1] = (bpos % cols - col) / cols
            out[e, a, off + 2] = 1.0
            bh = agents[e, A_HAND, b]
            out[e, a, off + 3 + (0 if bh < 0 else 1 + kidx[kind[bh]])] = 1.0


def encode(e, a, clock, agents, cells, items, orders, g, out, dist, first, queue, reach, best,
           wanted, counts, gap):
    """FeatureEncoder._encode of agent ``a`` of env ``e`` into ``out[e, a]``."""
    p, kind, kidx = g.params, g.kind, g.kind_index
    n = agents.shape[2]
    lay = clock[e, C_LAYOUT]
    pos = agents[e, A_POS, a]
    nearest(e, a, lay, pos, n, cells, items, agents, g, dist, first, queue, reach, best,
            wanted)
    for j in range(N_FEATURES):
        out[e, a, j] = 0.0
    for t in range(N_TARGETS):
        if best[1, t] >= 0:
            out[e, a, 6 * t + best[1, t]] = 1.0
            out[e, a, 6 * t + 4] = min(best[0, t] / PATH_SCALE, 1.0)
            out[e, a, 6 * t + 5] = 1.0

    held = agents[e, A_HAND, a]
    if held < 0:
        out[e, a, F_HAND] = 1.0
    else:
        hk = kidx[kind[held]]
        out[e, a, F_HAND + 1] = 1.0 if hk < 4 and wanted[hk] else 0.0
        out[e, a, F_HAND + 2 + hk] = 1.0
        out[e, a, F_HAND + 7 + items[e, I_STATE, held]] = 1.0
        if kind[held] == ITEM_PLATE:
            plate_summary(e, held, items, orders, g, counts, gap, out, a, F_HAND_PLATE)
    near = best[2, T_CLEAN_PLATE]
    if near >= 0:
        plate_summary(e, cells[e, near], items, orders, g, counts, gap, out, a, F_NEAR_PLATE)

    for j in range(4):
        counts[j] = 0
    for o in range(min(MAX_ORDERS, orders.shape[2])):
        r = orders[e, O_RECIPE, o]
        for j in range(4):
            counts[j] += g.recipes[r, j]
            out[e, a, F_ORDERS + 5 * o + j] = float(g.recipes[r, j]) / 2
        out[e, a, F_ORDERS + 5 * o + 4] = 1.0
    for j in range(4):
        out[e, a, F_DEMAND + j] = min(float(counts[j]) / 3, 1.0)

    around(e, a, lay, pos, n, agents, g, out)

    t_now = clock[e, C_T]
    if p[Q_DYNAMIC]:
        out[e, a, F_CLOCK + 2] = min(max(clock[e, C_SWITCH] - t_now, 0) / p[Q_SWITCH_STEP], 1.0)
    out[e, a, F_CLOCK] = t_now / p[Q_HORIZON]
    out[e, a, F_CLOCK + 1] = float(lay)
    cooking = best[2, T_COOKING_STEAK]
    if cooking >= 0:
        out[e, a, F_CLOCK + 3] = min(items[e, I_PROG, cells[e, cooking]] / p[Q_COOK], 1.0)
    cooked = best[2, T_COOKED_STEAK]
    if cooked >= 0 and g.terrain[lay, cooked] == CELL_PAN:
        left = max(0, p[Q_BURN] + 1 - items[e, I_PROG, cells[e, cooked]])
        out[e, a, F_CLOCK + 4] = max(0.0, 1.0 - left / (p[Q_BURN] + 1 - p[Q_COOK]))


KERNELS = (
    "features_range", "shaping_range", "wanted_kinds", "needed", "plate_contents",
    "fits_order", "potential", "plate_summary", "bfs", "occupied_by_other", "reach_cells",
    "target_of", "nearest", "around", "encode",
)

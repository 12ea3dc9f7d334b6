"""What the batched engine's arrays hold: the codes the kernels compare with, the rows and
columns of the state arrays, and the two records of arrays (one rule set's tables, the
state of ``E`` kitchens).

The codes are those of :mod:`ocplus_plan.sim.codes`, taken from its enums as plain
module-level ints: numba compiles a global int as a constant, an enum member it would
look up (``tests/sim/fast/test_kernel_codes.py`` checks every one against the enums).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..codes import Action, Cell, Item, ItemState, Where

# cell, item, item-state, where and action codes (sim/codes.py)
CELL_COUNTER = int(Cell.COUNTER)
CELL_BOARD, CELL_DELIVERY, CELL_PAN = int(Cell.BOARD), int(Cell.DELIVERY), int(Cell.PAN)
CELL_SINK, CELL_TRASH = int(Cell.SINK), int(Cell.TRASH)
ITEM_TOMATO, ITEM_LETTUCE, ITEM_ONION = int(Item.TOMATO), int(Item.LETTUCE), int(Item.ONION)
ITEM_STEAK, ITEM_PLATE = int(Item.STEAK), int(Item.PLATE)
STATE_FRESH, STATE_CHOPPED = int(ItemState.FRESH), int(ItemState.CHOPPED)
STATE_COOKED, STATE_BURNT = int(ItemState.COOKED), int(ItemState.BURNT)
STATE_CLEAN, STATE_DIRTY = int(ItemState.CLEAN), int(ItemState.DIRTY)
WHERE_CELL, WHERE_HAND = int(Where.CELL), int(Where.HAND)
WHERE_PLATE, WHERE_WAITING = int(Where.PLATE), int(Where.WAITING)
ACTION_STAY = int(Action.STAY)
#: one more than the largest cell or item code: the length of code-indexed tables
N_CODES = max(int(c) for c in Cell) + 1
# columns and rows of the state arrays
C_T, C_LAYOUT, C_SWITCH, C_ORDER_ID, C_QPOS = range(5)  # clock (E, 5)
A_POS, A_HAND = range(2)  # agents (E, 2, n_agents)
# items (E, 6, n_items); I_LIFE counts the item's respawns (batch bookkeeping, not State)
I_STATE, I_PROG, I_WHERE, I_LOC, I_OWNER, I_LIFE = range(6)
O_ID, O_RECIPE, O_CREATED, O_DEADLINE = range(4)  # orders (E, 4, n_orders), oldest first
DISHES, COMPLETED, EXPIRED, BURNS, WRONG, CHOPS, COOKS, WASHES, SWITCHES = range(9)
STAT_NAMES = ("dishes_served", "orders_completed", "orders_expired", "burns",
              "wrong_deliveries", "chops", "cooks", "washes", "layout_switches")
# columns of the process table (one row per process record, sim/processes.py)
(PN_TIMED, PN_TAKES, PN_DURATION, PN_DONE, PN_OVER_STATE, PN_OVERRUN, PN_PLATES, PN_STAT,
 PN_OVER_STAT) = range(9)
# params (ints) and reward values (floats)
(P_CHOP, P_COOK, P_BURN, P_WASH, P_HORIZON, P_LIMIT, P_STOP, P_DIRTY, P_DYNAMIC,
 P_SWITCH_STEP, P_SHARED, P_FIXED, P_RADIUS, P_ROWS, P_COLS, P_HAS_SWITCH, P_OBSERVE) = range(17)
# (R_DISH + r: what serving recipe r earns, the dish's reward)
R_SUBTASK, R_CORRECT, R_WRONG, R_STEP, R_BURNED, R_EXPIRED, R_DISH = range(7)
# what each agent's bump did in the last step (bumps (E, 3, agents): kind, item, plate)
B_NONE, B_PUTDOWN, B_PLATE_ADD = range(3)
# observation layout: window cells and width, channel starts, feature offsets, static size
(V_CELLS, V_WW, V_KIND0, V_STATE0, V_PROG, V_SELF, V_OTHER, V_FEAT, V_ORDER0,
 V_STATIC) = range(10)


class StaticArrays(NamedTuple):
    """What one rule set fixes (built by :func:`ocplus_plan.sim.fast.batch.static_arrays`)."""

    params: np.ndarray  # int64 (17,)
    rewards: np.ndarray  # float64 (6 + recipes,): the values, then each recipe's dish
    terrain: np.ndarray  # int64 (layouts, cells)
    walk: np.ndarray  # bool (layouts, cells)
    nbrs: np.ndarray  # int64 (cells, 4)
    timed: np.ndarray  # int64 (n,) cells of time-driven process stations (the pans)
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
    proc_of: np.ndarray  # int64 (N_CODES,): cell code -> process row, -1
    proc: np.ndarray  # int64 (processes, 9) PN_*
    accepts: np.ndarray  # bool (processes, kinds, states): may be put down there
    works: np.ndarray  # bool (processes, kinds, states): an empty-handed bump works on it
    plateable: np.ndarray  # bool (kinds, states): goes on a plate


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

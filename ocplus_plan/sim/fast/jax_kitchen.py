"""The kitchen's rules in JAX: pure ``reset(key, params)`` / ``step(key, state, actions)``
over a state pytree of arrays, jit- and vmap-able (the ``jax`` extra).

The rules are those of :func:`ocplus_plan.sim.step.transition`, rule for rule and in the
same order (bumps in agent order, waiting respawns, simultaneous moves, pans, the layout
switch, order expiry); ``tests/sim/fast/test_jax_kitchen.py`` holds the two to the same
kitchen at every step. Every map is padded to :data:`GRID` x :data:`GRID` cells (cell
``row * GRID + col``; the padding is wall, and reads as ``unknown`` in observations), the
items to ``max_items`` and the recipe pool to ``max_recipes``, so one compiled step serves
kitchens of different layouts: their :class:`Params` are arrays of equal shapes, stacked and
vmapped like the states (:func:`stack_params`).

Orders: the recipe of order number ``k`` of an episode is
``randint(fold_in(state.key, k), 0, n_recipes)`` (:func:`order_draw`), so an episode is a
function of its reset key alone; there is no numpy generator in the loop (the reference's
``default_rng(seed)`` draws are replaced by these in the differential test).

Design notes: no Python branch on a traced value: every rule computes its outcome under
a mask and ``jnp.where`` keeps it; the agents' bumps are taken in agent order (they
see each other's effects), everything else acts on all items or cells at once (item
homes are distinct, so sending several items home never contends for a tile).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...errors import ConfigError, DependencyNotInstalled, InvalidActionError

try:
    import jax
    import jax.numpy as jnp
except ImportError as exc:  # pragma: no cover - exercised with jax absent
    raise DependencyNotInstalled(
        "the JAX kitchen needs jax: pip install 'ocplus-plan[jax]' (CPU), or jax with CUDA "
        "for a GPU (see docs/gpu.md)"
    ) from exc

from ..codes import COUNTERS, Cell, Item, ItemState, Where
from ..observe import ITEM_KINDS
from ..processes import ProcessTables
from ..rules import Rules
from ..state import geometry_for

#: side of the padded square grid every kitchen lives on
GRID = 12
CELLS = GRID * GRID
#: unroll the loop over the cooks' bumps: True / False, or None = unroll except on CPU (an
#: unrolled step runs in fewer kernels on a GPU; on CPU it compiles twice as slowly)
UNROLL_AGENTS: bool | None = None
_CELL, _HAND, _PLATE, _WAITING = (int(w) for w in (Where.CELL, Where.HAND, Where.PLATE,
                                                    Where.WAITING))
_NOWHERE = -1  # padded item slots
_FRESH, _CLEAN, _DIRTY = int(ItemState.FRESH), int(ItemState.CLEAN), int(ItemState.DIRTY)
_PLATE_KIND = int(Item.PLATE)
_COUNTER, _BLOCK = int(Cell.COUNTER), int(Cell.BLOCK)
_DELIVERY, _TRASH = int(Cell.DELIVERY), int(Cell.TRASH)
#: per cell code + 1 (BLOCK is -1): is it a counter (spawn tiles are counters)
_IS_COUNTER = np.array([c - 1 in {int(x) for x in COUNTERS} for c in range(16)])

# Params.ints columns
(P_CHOP, P_COOK, P_BURN, P_WASH, P_HORIZON, P_LIMIT, P_STOP, P_DIRTY, P_DYNAMIC,
 P_SWITCH_STEP, P_SHARED, P_FIXED, P_HAS_SWITCH, P_ROWS, P_COLS, P_N_RECIPES,
 P_CENTRED) = range(17)
# Params.code_proc columns: the process record of a station (sim/processes.py), all zero
# for a cell code that is no process station
(Q_IS, Q_TIMED, Q_TAKES, Q_DURATION, Q_DONE, Q_OVER_STATE, Q_OVERRUN, Q_PLATES, Q_STAT,
 Q_OVER_STAT) = range(10)
#: the rows of the code-indexed process tables (cell codes -1 .. 15)
_CODES = 17
# Params.rewards columns
R_SUBTASK, R_CORRECT, R_WRONG, R_STEP, R_BURNED, R_EXPIRED, R_DISH = range(7)  # + recipe
# KitchenState.stats columns (the reference's State.stats keys, in this order)
STAT_NAMES = ("dishes_served", "orders_completed", "orders_expired", "burns",
              "wrong_deliveries", "chops", "cooks", "washes", "layout_switches")
(S_DISHES, S_COMPLETED, S_EXPIRED, S_BURNS, S_WRONG, S_CHOPS, S_COOKS, S_WASHES,
 S_SWITCHES) = range(9)


class Params(NamedTuple):
    """One kitchen's rules and layout as arrays (numpy when built, jax once traced)."""

    ints: Any  # int32 (17,) P_*
    rewards: Any  # float32 (6 + recipes,) R_*, then each recipe's dish (R_DISH + r)
    terrain: Any  # int32 (2, CELLS) cell codes of the main and the switch layout
    walk: Any  # bool (2, CELLS)
    inside: Any  # bool (CELLS,) the map's own cells (not padding)
    timed: Any  # bool (CELLS,) cells of time-driven process stations (the pans)
    code_proc: Any  # int32 (CODES + 1, 10) per cell code + 1: Q_* of its process record
    accepts: Any  # bool (CODES + 1, kinds, states): may be put down on that station
    works: Any  # bool (CODES + 1, kinds, states): an empty-handed bump works on it there
    plateable: Any  # bool (kinds, states): goes on a plate
    item_kind: Any  # int32 (I,) item code (0 for a padded slot)
    item_kidx: Any  # int32 (I,) 0..4 tomato lettuce onion steak plate (-1 padded)
    item_home: Any  # int32 (I,) spawn tile (0 padded)
    item_valid: Any  # bool (I,)
    prog_den: Any  # float32 (I,) what the progress channel divides by
    recipes: Any  # int32 (R, 4) ingredient counts (tomato lettuce onion steak)
    fixed: Any  # int32 (O,) recipe indices of the fixed orders
    spawn: Any  # int32 (N,) start cells
    view: Any  # int32 (K, 2): observed cells, (row, col) or with P_CENTRED (drow, dcol)


class KitchenState(NamedTuple):
    """The state of one kitchen (arrays only; vmap adds a leading axis)."""

    t: Any
    layout: Any
    next_switch: Any
    next_order_id: Any
    pos: Any  # (N,) cell of each agent
    hand: Any  # (N,) item held, -1
    cell_item: Any  # (CELLS,) item lying there, -1
    item_state: Any  # (I,)
    item_prog: Any  # (I,)
    item_where: Any  # (I,) Where code, -1 for padded slots
    item_loc: Any  # (I,)
    item_owner: Any  # (I,)
    order_id: Any  # (O,) open orders, oldest first
    order_recipe: Any  # (O,)
    order_created: Any  # (O,)
    order_deadline: Any  # (O,) -1 = never
    stats: Any  # (9,)
    key: Any  # (2,) uint32: the episode's order draws
    params: Params


class StepOut(NamedTuple):
    state: KitchenState
    rewards: Any  # float32 (N,)
    terminated: Any
    truncated: Any


# ---------------------------------------------------------------- params (numpy)
def _neighbors() -> np.ndarray:
    """Per padded cell: the neighbour RIGHT, DOWN, LEFT, UP (-1 off the grid)."""
    f = np.arange(CELLS)
    r, c = f // GRID, f % GRID
    return np.stack([np.where(c + 1 < GRID, f + 1, -1), np.where(r + 1 < GRID, f + GRID, -1),
                     np.where(c > 0, f - 1, -1), np.where(r > 0, f - GRID, -1)], 1).astype(np.int32)


_NBRS = _neighbors()


def pad_cell(flat: int, cols: int) -> int:
    """A map's flat cell ``row * cols + col`` -> the padded grid's ``row * GRID + col``."""
    return (flat // cols) * GRID + flat % cols


def kitchen_params(rules: Rules, obs_radius: int = 0, *, max_items: int | None = None,
                   max_recipes: int | None = None, padded_view: bool = False) -> Params:
    """The :class:`Params` of one rule set. ``obs_radius`` r > 0: a ``2r+1`` window centred
    on the cook; 0: the whole map, ``rows x cols`` as the reference encoder, or the whole
    padded grid with ``padded_view`` (what kitchens of different shapes share)."""
    if isinstance(obs_radius, bool) or not isinstance(obs_radius, int) or obs_radius < 0:
        raise ConfigError(f"obs_radius must be an integer >= 0 (0 = whole map), got {obs_radius!r}")
    geo = geometry_for(rules)
    rows, cols = geo.rows, geo.cols
    if rows > GRID or cols > GRID:
        raise ConfigError(f"map {rules.layout.name!r} is {rows}x{cols}; the JAX kitchen pads "
                          f"maps to {GRID}x{GRID}: use a map of at most that size")
    n_items = len(geo.item_kind)
    max_items = n_items if max_items is None else max_items
    max_recipes = len(rules.recipes) if max_recipes is None else max_recipes
    if n_items > max_items or len(rules.recipes) > max_recipes:
        raise ConfigError(f"map {rules.layout.name!r} has {n_items} items and "
                          f"{len(rules.recipes)} recipes; raise max_items / max_recipes to fit")
    terrain = np.full((2, CELLS), _BLOCK, np.int32)
    inside = np.zeros(CELLS, bool)
    idx = np.array([pad_cell(f, cols) for f in range(rows * cols)])
    inside[idx] = True
    for k in range(2):
        terrain[k, idx] = geo.terrains[min(k, len(geo.terrains) - 1)]
    walk = (terrain == int(Cell.FLOOR)) | (terrain == int(Cell.SPAWN))
    timed = np.zeros(CELLS, bool)
    timed[[pad_cell(f, cols) for f in geo.timed]] = True
    kind = np.zeros(max_items, np.int32)
    kind[:n_items] = geo.item_kind
    kidx = np.full(max_items, -1, np.int32)
    kidx[:n_items] = [ITEM_KINDS.index(Item(k)) for k in geo.item_kind]
    home = np.zeros(max_items, np.int32)
    home[:n_items] = [pad_cell(h, cols) for h in geo.item_home]
    den = np.ones(max_items, np.float32)
    den[:n_items] = [rules.tables.progress_scale(k) for k in geo.item_kind]
    ingredients = ITEM_KINDS[:4]
    recipes = np.zeros((max_recipes, 4), np.int32)
    recipes[: len(rules.recipes)] = [[r.count(k) for k in ingredients] for r in rules.recipes]
    fixed = np.zeros(rules.n_orders, np.int32)
    if rules.fixed_orders is not None:
        fixed[:] = [rules.recipes.index(rules.fixed_orders[o % len(rules.fixed_orders)])
                    for o in range(rules.n_orders)]
    spawn = [pad_cell(geo.flat(r, c), cols) for r, c in rules.layout.spawn_points[: rules.n_agents]]
    r = obs_radius
    if r:
        view = [(dr, dc) for dr in range(-r, r + 1) for dc in range(-r, r + 1)]
    else:
        h, w = (GRID, GRID) if padded_view else (rows, cols)
        view = [(rr, cc) for rr in range(h) for cc in range(w)]
    limit, stop = rules.order_time_limit, rules.stop_after_orders
    ints = np.array([
        rules.chop_steps, rules.cook_time, rules.burn_time, rules.wash_steps, rules.horizon,
        -1 if limit is None else limit, -1 if stop is None else stop, rules.dirty_plates,
        rules.dynamic, rules.map_switch_step, rules.reward_mode == "shared",
        rules.fixed_orders is not None, len(geo.terrains) > 1, rows, cols, len(rules.recipes),
        r > 0], np.int32)
    rw = rules.rewards
    rewards = np.array([rw.subtask_finished, rw.correct_delivery, rw.wrong_delivery,
                        rw.step_penalty, rw.burned_penalty, rw.order_expired,
                        *rules.recipe_rewards, *[0.0] * (max_recipes - len(rules.recipes))],
                       np.float32)
    return Params(ints, rewards, terrain, walk, inside, timed, *_process_params(rules.tables),
                  kind, kidx, home, np.arange(max_items) < n_items, den, recipes, fixed,
                  np.array(spawn, np.int32), np.array(view, np.int32))


def _process_params(t: ProcessTables) -> tuple[np.ndarray, ...]:
    """(code_proc, accepts, works, plateable): the process tables indexed by cell code + 1,
    the same shape for every rule set (so kitchens of different rules stack)."""
    code_proc = np.zeros((_CODES, 10), np.int32)
    accepts = np.zeros((_CODES, *t.plateable.shape), bool)
    works = np.zeros_like(accepts)
    for code, j in t.by_code.items():
        q = t.processes[j]
        code_proc[code + 1] = [1, q.timed, int(q.takes_state), t.duration[j], t.done_state[j],
                               t.overrun_state[j], t.overrun[j], q.plates,
                               STAT_NAMES.index(q.stat), STAT_NAMES.index(q.overrun_stat)]
        accepts[code + 1], works[code + 1] = t.accepts[j], t.works[j]
    return code_proc, accepts, works, t.plateable.copy()


def params_for_many(rules_list: list[Rules], obs_radius: int = 0) -> Params:
    """Stacked :class:`Params` (leading axis: one per rule set) of kitchens that may differ
    in layout, recipes and rule values but share the number of cooks and open orders;
    one compiled step serves them all (whole-map views are the padded grid)."""
    shapes = {(r.n_agents, r.n_orders) for r in rules_list}
    if len(shapes) != 1:
        raise ConfigError(f"kitchens stepped together need the same n_agents and n_orders, "
                          f"got {sorted(shapes)}; group them by those")
    items = max(len(geometry_for(r).item_kind) for r in rules_list)
    recipes = max(len(r.recipes) for r in rules_list)
    return stack_params([kitchen_params(r, obs_radius, max_items=items, max_recipes=recipes,
                                        padded_view=True) for r in rules_list])


def stack_params(params: list[Params]) -> Params:
    """Params of equal shapes stacked on a new leading axis (for ``vmap``)."""
    return Params(*(np.stack(col) for col in zip(*params)))


# ---------------------------------------------------------------- reset
def order_draw(key: Any, order_id: Any, n_recipes: Any) -> Any:
    """The recipe index of order number ``order_id`` of the episode keyed ``key`` (a raw
    ``(2,)`` uint32 key): a murmur3-mixed hash of the two, modulo the pool size (a few
    integer operations: cheap to compile and to run, unlike a threefry draw)."""
    k = jnp.asarray(key).astype(jnp.uint32)
    h = _fmix32(k[0] ^ (jnp.asarray(order_id).astype(jnp.uint32) * jnp.uint32(0x9E3779B9)))
    h = _fmix32(h ^ k[1])
    return (h % jnp.asarray(n_recipes).astype(jnp.uint32)).astype(jnp.int32)


def _fmix32(h: Any) -> Any:
    h = h ^ (h >> 16)
    h = h * jnp.uint32(0x85EBCA6B)
    h = h ^ (h >> 13)
    h = h * jnp.uint32(0xC2B2AE35)
    return h ^ (h >> 16)


def raw_key(key: Any) -> Any:
    """A PRNG key (new-style typed or legacy raw) as ``(2,)`` uint32."""
    key = jnp.asarray(key) if not hasattr(key, "dtype") else key
    if jax.dtypes.issubdtype(key.dtype, jax.dtypes.prng_key):
        key = jax.random.key_data(key)
    return key.astype(jnp.uint32).reshape(-1)[:2]


def reset(key: Any, params: Params) -> KitchenState:
    """The first state of an episode: items on their spawn tiles, cooks on the spawn
    points, ``n_orders`` orders drawn with ``key``."""
    p = jax.tree_util.tree_map(jnp.asarray, params)
    ints = p.ints
    n_items, n_orders = p.item_kind.shape[0], p.fixed.shape[0]
    valid = p.item_valid
    slots = jnp.arange(n_items)
    cell_item = jnp.full(CELLS, -1, jnp.int32)
    hit = (jnp.arange(CELLS)[None, :] == p.item_home[:, None]) & valid[:, None]
    cell_item = jnp.where(hit.any(0), jnp.max(jnp.where(hit, slots[:, None], -1), 0), cell_item)
    ids = jnp.arange(n_orders, dtype=jnp.int32)
    key = raw_key(key)
    drawn = order_draw(key, ids, ints[P_N_RECIPES])
    limit = ints[P_LIMIT]
    i32 = jnp.int32
    return KitchenState(
        t=i32(0), layout=i32(0), next_switch=ints[P_SWITCH_STEP], next_order_id=i32(n_orders),
        pos=p.spawn, hand=jnp.full(p.spawn.shape, -1, i32), cell_item=cell_item,
        item_state=jnp.where(p.item_kind == _PLATE_KIND, _CLEAN, _FRESH).astype(i32),
        item_prog=jnp.zeros(n_items, i32),
        item_where=jnp.where(valid, _CELL, _NOWHERE).astype(i32),
        item_loc=jnp.where(valid, p.item_home, -1).astype(i32),
        item_owner=jnp.full(n_items, -1, i32), order_id=ids,
        order_recipe=jnp.where(ints[P_FIXED] > 0, p.fixed, drawn).astype(i32),
        order_created=jnp.zeros(n_orders, i32),
        order_deadline=jnp.full(n_orders, 1, i32) * jnp.where(limit >= 0, limit, -1),
        stats=jnp.zeros(9, i32), key=key, params=p)


# ---------------------------------------------------------------- orders
def _replace_orders(s: KitchenState, drop: Any) -> KitchenState:
    """Drop the open orders marked in ``drop`` (later ones move up, keeping their order)
    and append one replacement for each, in the dropped ones' order (orders.draw_order)."""
    ints = s.params.ints
    keep = ~drop
    n_keep = keep.sum()
    rank = jnp.cumsum(drop) - 1
    new_pos = jnp.where(keep, jnp.cumsum(keep) - 1, n_keep + rank)
    new_id = s.next_order_id + rank
    drawn = order_draw(s.key, new_id, ints[P_N_RECIPES])
    limit = ints[P_LIMIT]
    fields = (
        jnp.where(drop, new_id, s.order_id),
        jnp.where(drop, jnp.where(ints[P_FIXED] > 0, s.order_recipe, drawn), s.order_recipe),
        jnp.where(drop, s.t, s.order_created),
        jnp.where(drop, jnp.where(limit >= 0, s.t + limit, -1), s.order_deadline),
    )
    move = new_pos[:, None] == jnp.arange(drop.shape[0])[None, :]  # (old slot, new slot)
    ids, rec, created, deadline = (jnp.sum(jnp.where(move, f[:, None], 0), 0).astype(jnp.int32)
                                   for f in fields)
    return s._replace(order_id=ids, order_recipe=rec, order_created=created,
                      order_deadline=deadline, next_order_id=s.next_order_id + drop.sum())


# ---------------------------------------------------------------- items
def _send_home(s: KitchenState, mask: Any, new_state: Any) -> KitchenState:
    """Items in ``mask`` respawn with ``new_state`` on their spawn tile, or wait for it."""
    home = s.params.item_home
    free = s.cell_item[home] < 0
    placed = mask & free
    cells = jnp.arange(CELLS)
    cell_item = s.cell_item
    for i in range(home.shape[0]):
        cell_item = jnp.where((cells == home[i]) & placed[i], i, cell_item)
    return s._replace(
        cell_item=cell_item,
        item_state=jnp.where(mask, new_state, s.item_state),
        item_prog=jnp.where(mask, 0, s.item_prog),
        item_owner=jnp.where(mask, -1, s.item_owner),
        item_loc=jnp.where(mask, home, s.item_loc),
        item_where=jnp.where(mask, jnp.where(free, _CELL, _WAITING), s.item_where))


def _plate_counts(s: KitchenState, plate: Any) -> tuple[Any, Any]:
    """(ingredient counts (4,), is every item on it plateable) of the items on ``plate``."""
    p = s.params
    on = (s.item_where == _PLATE) & (s.item_loc == plate)
    counts = jnp.sum(on[:, None] & (p.item_kidx[:, None] == jnp.arange(4)[None, :]), 0)
    ok = jnp.all(~on | p.plateable[p.item_kind, s.item_state])
    return counts.astype(jnp.int32), ok


# ---------------------------------------------------------------- bumps (queries.bump_effect)
def _bump_effects(s: KitchenState, a: int, cell: Any, active: Any) -> dict[str, Any]:
    """What agent ``a`` bumping ``cell`` does (each a scalar bool; at most one is true)."""
    p = s.params
    code = p.terrain[s.layout, cell]
    held, here = s.hand[a], s.cell_item[cell]
    hc, ec = jnp.maximum(held, 0), jnp.maximum(here, 0)
    has_h, has_e = active & (held >= 0), active & (here >= 0)
    k_h, k_e = p.item_kind[hc], p.item_kind[ec]
    st_h, st_e = s.item_state[hc], s.item_state[ec]
    counter = jnp.asarray(_IS_COUNTER)[code + 1]
    q = p.code_proc[code + 1]  # the station's process record (all zero: none)
    station = q[Q_IS] > 0
    works = station & p.works[code + 1, k_e, st_e]
    exchange = (counter | (station & (q[Q_PLATES] > 0))) & has_h & has_e
    onto = exchange & (k_e == _PLATE_KIND) & (st_e == _CLEAN) & p.plateable[k_h, st_h]
    take = exchange & ~onto & (k_h == _PLATE_KIND) & (st_h == _CLEAN) & p.plateable[k_e, st_e]
    pick = ~has_h & has_e & (counter | (station & ~works))
    put = has_h & ~has_e & (counter | (station & p.accepts[code + 1, k_h, st_h]))
    on_held = (s.item_where == _PLATE) & (s.item_loc == held)
    empty_plate = (k_h == _PLATE_KIND) & ~on_held.any()
    return dict(held=held, here=here, hc=hc, ec=ec, k_h=k_h, onto=onto, take=take, pick=pick,
                put=put, work=~has_h & has_e & works, q=q,
                deliver=(code == _DELIVERY) & has_h,
                trash=(code == _TRASH) & has_h & ~empty_plate, on_held=on_held)


def _interact(s: KitchenState, a: int, cell: Any, active: Any, rewards: Any,
              ) -> tuple[KitchenState, Any]:
    """Agent ``a`` bumps the non-walkable ``cell`` (where ``active``): step._interact."""
    p, ints, rw = s.params, s.params.ints, s.params.rewards
    e = _bump_effects(s, a, cell, active)
    held, here, hc, ec = e["held"], e["here"], e["hc"], e["ec"]
    pick, put, onto, take = e["pick"], e["put"], e["onto"], e["take"]
    work, q = e["work"], e["q"]
    items = jnp.arange(p.item_kind.shape[0])
    is_h, is_e = items == hc, items == ec
    at = jnp.arange(CELLS) == cell
    # pick up / put down / plate exchanges
    cell_item = jnp.where(at & (pick | take), -1, jnp.where(at & put, held, s.cell_item))
    where = jnp.where(is_h & put, _CELL, jnp.where(is_h & onto, _PLATE, s.item_where))
    where = jnp.where(is_e & pick, _HAND, jnp.where(is_e & take, _PLATE, where))
    loc = jnp.where(is_h & put, cell, jnp.where(is_h & onto, here, s.item_loc))
    loc = jnp.where(is_e & pick, a, jnp.where(is_e & take, held, loc))
    owner = jnp.where(is_e & (pick | take | work), a, s.item_owner)
    # one unit of work of a bump-driven process (chop, wash)
    prog = s.item_prog + (is_e & work)
    done = work & (prog[ec] >= q[Q_DURATION])
    item_state = jnp.where(is_e & done, q[Q_DONE], s.item_state)
    prog = jnp.where(is_e & done, 0, prog)
    stats = s.stats.at[q[Q_STAT]].add(done)
    reward = jnp.where(done, rw[R_SUBTASK], 0.0)
    s = s._replace(cell_item=cell_item, item_where=where, item_loc=loc, item_owner=owner,
                   item_prog=prog, item_state=item_state, stats=stats)
    # deliver
    counts, all_ready = _plate_counts(s, held)
    plate_ok = (e["k_h"] == _PLATE_KIND) & (s.item_state[hc] == _CLEAN) & all_ready & (
        counts.sum() > 0)
    match = jnp.all(p.recipes[s.order_recipe] == counts[None, :], 1) & plate_ok
    served = e["deliver"] & match.any()
    wrong = e["deliver"] & ~served
    slot = jnp.argmax(match)
    dish = rw[R_DISH + s.order_recipe[slot]]  # the served dish's reward
    reward = reward + jnp.where(served, dish, 0.0) + jnp.where(wrong, rw[R_WRONG], 0.0)
    s = s._replace(stats=s.stats.at[S_DISHES].add(served).at[S_COMPLETED].add(served)
                   .at[S_WRONG].add(wrong))
    # what goes home: a served plate and its contents, trashed things
    trash, is_plate = e["trash"], e["k_h"] == _PLATE_KIND
    home_mask = (e["on_held"] & (served | (trash & is_plate))) | (
        is_h & (served | (trash & ~is_plate)))
    plate_back = jnp.where(ints[P_DIRTY] > 0, _DIRTY, _CLEAN)
    s = _send_home(s, home_mask, jnp.where(is_h & served, plate_back, _FRESH))
    empty_hand = put | onto | served | (trash & ~is_plate)
    hand = s.hand.at[a].set(jnp.where(pick, here, jnp.where(empty_hand, -1, held)))
    s = s._replace(hand=hand)
    s = _replace_orders(s, (jnp.arange(s.order_id.shape[0]) == slot) & served)
    return s, rewards.at[a].add(reward)



# ---------------------------------------------------------------- the step
def check_actions(actions: Any, n_agents: int | None = None) -> np.ndarray:
    """Check concrete actions on the host (outside ``jit``): an integer array (``(N,)`` or
    batched ``(..., N)``) of values 0..4. Anything else is an :class:`InvalidActionError`
    naming the first bad value. :func:`step` itself cannot raise on a traced value, so
    inside ``jit`` an integer outside 0..4 acts as stay; this is the checked mode's test
    (``JaxKitchenEnv(..., checked=True)``)."""
    try:
        arr = np.asarray(actions)
    except Exception:  # a traced value has no concrete contents  # noqa: BLE001
        raise ConfigError("check_actions needs concrete actions: call it (or a checked env's "
                          "step) outside jax.jit") from None
    if arr.dtype.kind not in "iu":
        raise InvalidActionError(f"actions must be integers 0..4, got dtype {arr.dtype}"
                                 + (f" (first value {arr.reshape(-1)[0].item()!r})"
                                    if arr.size else ""))
    bad = (arr < 0) | (arr > 4)
    if bad.any():
        raise InvalidActionError(f"action {arr[bad].reshape(-1)[0].item()} is out of range; "
                                 "moves are 0 right, 1 down, 2 left, 3 up, 4 stay")
    if n_agents is not None and (arr.ndim == 0 or arr.shape[-1] != n_agents):
        raise InvalidActionError(f"expected {n_agents} actions (one per cook), got shape "
                                 f"{arr.shape}")
    return arr


def step(key: Any, state: KitchenState, actions: Any) -> StepOut:
    """One joint action (``(N,)`` integers, 0 right 1 down 2 left 3 up 4 stay) applied to
    ``state`` (step.transition). Actions of a float or bool dtype are refused when the
    step is traced (an :class:`InvalidActionError`: 1.7 is not truncated, NaN is not read
    as 0); an integer outside 0..4 cannot be refused inside ``jit`` and acts as stay (use
    :func:`check_actions`, or the env's ``checked=True``, to refuse it). ``key`` is
    unused: the step is deterministic (order draws come from the episode's key); it is
    taken for the JaxMARL-style signature."""
    del key
    s, p = state, state.params
    ints, rw = p.ints, p.rewards
    n = s.pos.shape[0]
    actions = jnp.asarray(actions)
    if not jnp.issubdtype(actions.dtype, jnp.integer):  # static under jit: checked once
        raise InvalidActionError(f"JAX kitchen actions must be integers 0..4, got dtype "
                                 f"{actions.dtype}; round or cast them first")
    actions = actions.astype(jnp.int32)
    rewards = jnp.full(n, rw[R_STEP], jnp.float32)
    nbrs = jnp.asarray(_NBRS)

    def bump(a: Any, carry: tuple) -> tuple:  # agents in index order see each other's bumps
        s, rewards, targets = carry
        act = actions[a]
        nb = nbrs[s.pos[a], jnp.clip(act, 0, 3)]
        valid = (act >= 0) & (act < 4) & (nb >= 0)
        cell = jnp.maximum(nb, 0)
        walkable = p.walk[s.layout, cell]
        targets = targets.at[a].set(jnp.where(valid & walkable, cell, -1))
        s, rewards = _interact(s, a, cell, valid & ~walkable, rewards)
        return s, rewards, targets

    s, rewards, targets = jax.lax.fori_loop(
        0, n, bump, (s, rewards, jnp.full(n, -1, jnp.int32)),
        unroll=UNROLL_AGENTS if UNROLL_AGENTS is not None else jax.default_backend() != "cpu")
    s = _respawn_waiting(s)
    s = s._replace(pos=_resolve_moves(s.pos, targets))
    s, rewards = _tick_timed(s, rewards)
    s = s._replace(t=s.t + 1)
    s = _maybe_switch(s)
    s, rewards = _expire_orders(s, rewards)
    rewards = jnp.where(ints[P_SHARED] > 0, jnp.full(n, rewards.sum()), rewards)
    stop = ints[P_STOP]
    terminated = (stop >= 0) & (s.stats[S_COMPLETED] >= stop)
    truncated = ~terminated & (s.t >= ints[P_HORIZON])
    return StepOut(s, rewards, terminated, truncated)


def _respawn_waiting(s: KitchenState) -> KitchenState:
    loc = jnp.maximum(s.item_loc, 0)
    place = (s.item_where == _WAITING) & (s.cell_item[loc] < 0)
    cells = jnp.arange(CELLS)
    cell_item = s.cell_item
    for i in range(loc.shape[0]):
        cell_item = jnp.where((cells == loc[i]) & place[i], i, cell_item)
    return s._replace(cell_item=cell_item, item_where=jnp.where(place, _CELL, s.item_where))


def _resolve_moves(pos: Any, targets: Any) -> Any:
    """Simultaneous moves (step._resolve_moves): a mover moves when no one else wants its
    target and the target is free or its occupant moves (the least fixed point: cycles,
    swaps and contested cells block everyone in them)."""
    n = pos.shape[0]
    same = (targets[:, None] == targets[None, :]).sum(1)
    free_claim = (targets >= 0) & (same == 1)
    occ_hit = targets[:, None] == pos[None, :]  # (mover, occupant)
    occupied = occ_hit.any(1)
    occupant = jnp.argmax(occ_hit, 1)
    moves = jnp.zeros(n, bool)
    for _ in range(n):
        moves = free_claim & (~occupied | moves[occupant])
    return jnp.where(moves, targets, pos)


def _tick_timed(s: KitchenState, rewards: Any) -> tuple[KitchenState, Any]:
    """One tick of every item on a time-driven process station (step._tick)."""
    p, rw = s.params, s.params.rewards
    loc = jnp.maximum(s.item_loc, 0)
    on = (s.item_where == _CELL) & p.timed[loc]
    q = p.code_proc[p.terrain[0, loc] + 1]  # (I, 10): the process of each item's cell
    ticks = s.item_prog + 1
    done = on & (s.item_state == q[:, Q_TAKES]) & (ticks >= q[:, Q_DURATION])
    st = jnp.where(done, q[:, Q_DONE], s.item_state)
    over = on & (q[:, Q_OVER_STATE] >= 0) & (st != q[:, Q_OVER_STATE]) & (ticks > q[:, Q_OVERRUN])
    st = jnp.where(over, q[:, Q_OVER_STATE], st)
    gain = jnp.where(done, rw[R_SUBTASK], 0.0) + jnp.where(over, rw[R_BURNED], 0.0)
    mine = s.item_owner[None, :] == jnp.arange(rewards.shape[0])[:, None]
    rewards = rewards + jnp.sum(jnp.where(mine, gain[None, :], 0.0), 1)
    stats = s.stats.at[q[:, Q_STAT]].add(done).at[q[:, Q_OVER_STAT]].add(over)
    return s._replace(item_prog=jnp.where(on, ticks, s.item_prog), item_state=st,
                      stats=stats), rewards


def _maybe_switch(s: KitchenState) -> KitchenState:
    """dynamics.maybe_switch: a due switch waits while a cook stands on a cell that would
    stop being walkable or an item lies on a counter that would stop being one."""
    p, ints = s.params, s.params.ints
    old, new = s.layout, 1 - s.layout
    due = (ints[P_DYNAMIC] > 0) & (ints[P_HAS_SWITCH] > 0) & (s.t >= s.next_switch)
    cells = jnp.arange(CELLS)
    stood = (cells[None, :] == s.pos[:, None]).any(0)
    lost_counter = (p.terrain[old] == _COUNTER) & (p.terrain[new] != _COUNTER)
    blocked = jnp.any(stood & ~p.walk[new]) | jnp.any(lost_counter & (s.cell_item >= 0))
    go = due & ~blocked
    return s._replace(layout=jnp.where(go, new, old),
                      next_switch=jnp.where(go, s.t + ints[P_SWITCH_STEP], s.next_switch),
                      stats=s.stats.at[S_SWITCHES].add(go))


def _expire_orders(s: KitchenState, rewards: Any) -> tuple[KitchenState, Any]:
    limit = s.params.ints[P_LIMIT]
    dl = s.order_deadline
    gone = (limit >= 0) & (dl >= 0) & (dl <= s.t)
    n = rewards.shape[0]
    share = s.params.rewards[R_EXPIRED] / n
    rewards = rewards + gone.sum() * share
    s = s._replace(stats=s.stats.at[S_EXPIRED].add(gone.sum()))
    return _replace_orders(s, gone), rewards

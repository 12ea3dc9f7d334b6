"""Potential-based reward shaping for the JAX trainer (:mod:`ocplus_plan.rl.fast.jax_ppo`;
the ``jax`` extra).

The trainer learns from the rules' reward *without* its subtask part (``subtask_finished``
for a chop, a cook or a wash, ``infos["shaped_reward"]``): that part pays a finished
subtask and charges nothing when the work is undone (a chopped onion thrown in the trash
comes back fresh and pays again), and it says nothing about the steps between subtasks.
In its place the trainer pays ``F = gamma * phi(s') - phi(s)`` (Ng, Harada and Russell
1999; ``gamma`` the learner's discount), with ``phi(s')`` taken as 0 when the step ends
the episode, so the discounted shaping of an episode sums to ``-phi(s_0)``, fixed by the
episode's first state: whatever a policy does, shaping earns it nothing in total, and a
loop (pick up and put back, chop and trash) earns exactly what standing still for as long
earns, as the learner counts it. It only moves credit earlier in the episode. (Without the
``gamma``, a cook that reaches a high potential and holds it, a finished dish in its
hand, loses it only at the episode's end, discounted: holding paid more than serving.)

``phi`` adds, for every ingredient of a kind that an open order needs (the kinds of the
recipes of the open orders), the value of its stage::

    held while it still needs processing        carry
    on a station that processes it              stage + work * progress / duration
    processed (chopped, cooked), anywhere       ready (+ carry while held)
    on a plate                                  plated

(``plated`` only while the plate's contents still fit an open order's recipe), for every
held clean plate ``carry``, for a held plate whose contents equal an open order's recipe
``dish + near * closeness`` (closeness: 1 next to a serving window, 0 at the farthest floor
cell), and ``-spoiled`` for a plate holding what no open order fits (without a trash can
it serves nothing until such an order comes). A burnt steak or a dirty plate is worth 0.
An ingredient no open order needs costs ``busy`` while held. (``spoiled`` and ``busy`` are
0 by default: with them the cooks of some training seeds learned to touch nothing.) Per cook with
free hands, ``fetch`` times its closeness to the next thing to fetch: the nearest needed
fresh ingredient, or a clean plate once a needed ingredient is ready; with a clean plate
in hand, the nearest needed ready ingredient.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...sim.fast.jax_kitchen import (
    _CELL,
    _CLEAN,
    _DELIVERY,
    _FRESH,
    _HAND,
    _NBRS,
    _PLATE,
    _PLATE_KIND,
    CELLS,
    Q_DURATION,
    Q_IS,
    KitchenState,
    Params,
    jax,
    jnp,
)
from ...sim.grid import distances, interaction_spots


class Potential(NamedTuple):
    """Weights of the potential's terms, in the rules' reward units (a dish pays 200)."""

    carry: float = 10.0
    stage: float = 20.0
    work: float = 20.0
    ready: float = 40.0
    plated: float = 60.0
    dish: float = 80.0
    near: float = 40.0
    spoiled: float = 0.0
    busy: float = 0.0
    fetch: float = 5.0


class Tables(NamedTuple):
    """What the potential reads of a kitchen's layouts (numpy; :func:`tables`)."""

    window: Any  # (2, CELLS): closeness of each cell to a serving window
    reach: Any  # (2, CELLS, CELLS): [layout, cook cell, target cell] closeness


def _closeness(dist: np.ndarray) -> np.ndarray:
    far = max(1, int(dist.max()))
    return np.where(dist >= 0, 1.0 - dist / far, 0.0).astype(np.float32)


def tables(params: Params) -> Tables:
    """Per layout: each cell's closeness (1 next to the target, falling linearly with the
    walking distance to 0 at the farthest reachable cell, 0 where unreachable) to a serving
    window, and to each cell (a counter a cook bumps: closeness to a floor cell beside it)."""
    terrain, walk = np.asarray(params.terrain), np.asarray(params.walk)
    nbrs = _NBRS.tolist()
    window = np.zeros(terrain.shape, np.float32)
    reach = np.zeros((terrain.shape[0], CELLS, CELLS), np.float32)
    for k in range(terrain.shape[0]):
        open_ = walk[k].tolist()

        def closeness(cells: Any) -> np.ndarray:  # from the cells a cook bumps them from
            spots = [n for c in cells for n in interaction_spots(nbrs, open_, int(c))]
            return _closeness(np.asarray(distances(nbrs, open_, spots)))

        window[k] = closeness(np.flatnonzero(terrain[k] == _DELIVERY))
        for target in range(CELLS):
            if not open_[target] and interaction_spots(nbrs, open_, target):
                reach[k, :, target] = closeness([target])
    return Tables(window, reach)


def potential(s: KitchenState, near: Tables, w: Potential = Potential()) -> Any:
    """``phi(s)``, a float32 scalar, of one kitchen state with its params attached
    (``JaxKitchenEnv.kitchen_state``); ``near`` is :func:`tables` of its params (as jax
    arrays)."""
    p = s.params
    kidx = p.item_kidx
    ingredient = p.item_valid & (kidx >= 0) & (kidx < 4)
    need = p.recipes[s.order_recipe].sum(0)  # (4,) open orders' ingredient counts
    needed = ingredient & (need[jnp.clip(kidx, 0, 3)] > 0)
    kind, state = p.item_kind, s.item_state
    ready = p.plateable[kind, state]
    held = s.item_where == _HAND
    on_cell = s.item_where == _CELL
    loc = jnp.clip(s.item_loc, 0, CELLS - 1)
    code = p.terrain[s.layout, loc] + 1
    proc = p.code_proc[code]
    staged = on_cell & (proc[:, Q_IS] > 0) & p.accepts[code, kind, state] & ~ready
    progress = s.item_prog / jnp.maximum(proc[:, Q_DURATION], 1)
    raw = state == _FRESH
    items = jnp.arange(kind.shape[0])
    on = (s.item_where[None, :] == _PLATE) & (s.item_loc[None, :] == items[:, None])
    counts = jnp.sum(on[:, :, None] & (kidx[None, :, None] == jnp.arange(4)), 1)  # (I, 4)
    recipes = p.recipes[s.order_recipe]  # (O, 4)
    fits = jnp.any(jnp.all(counts[:, None, :] <= recipes[None, :, :], -1), -1)  # per plate
    done = jnp.any(jnp.all(counts[:, None, :] == recipes[None, :, :], -1), -1) \
        & jnp.any(counts > 0, -1)
    plated = s.item_where == _PLATE
    value = jnp.where(
        plated, jnp.where(fits[jnp.clip(s.item_loc, 0, kind.shape[0] - 1)], w.plated, 0.0),
        jnp.where(ready, w.ready + w.carry * held,
                  jnp.where(staged, w.stage + w.work * progress,
                            jnp.where(held & raw, w.carry, 0.0))))
    total = jnp.sum(jnp.where(needed | plated, value, 0.0)) \
        - w.busy * jnp.sum(ingredient & held & ~needed)  # a hand busy with what no order needs
    # plates: one holding what no open order fits costs spoiled (easy has no trash to
    # empty it: it is lost until such an order comes); a clean one in a hand is worth
    # carry, a finished dish more near a window
    plate = p.item_valid & (kind == _PLATE_KIND)
    spoiled = plate & ~fits
    in_hand = plate & held & (state == _CLEAN)
    holder = jnp.clip(s.item_loc, 0, s.pos.shape[0] - 1)
    where_now = near.window[s.layout, s.pos[holder]]
    plates = jnp.where(in_hand, w.carry + jnp.where(done, w.dish + w.near * where_now, 0.0),
                       0.0) - w.spoiled * spoiled
    # the next thing to fetch, for a cook with free hands: a needed fresh ingredient, or a
    # clean plate once a needed ingredient is ready; with a plate, a needed ready one
    reach = near.reach[s.layout][s.pos][:, loc] * on_cell[None, :]  # (N, I)
    free = s.hand < 0
    loose = needed & ready & ~plated
    targets = jnp.stack([needed & raw & ~staged, plate & (state == _CLEAN) & fits
                         & jnp.any(loose), loose & on_cell])  # (3, I)
    best = jnp.max(jnp.where(targets[:, None, :], reach[None], 0.0), -1)  # (3, N)
    hc = jnp.clip(s.hand, 0, kind.shape[0] - 1)
    with_plate = ~free & in_hand[hc] & fits[hc] & ~done[hc]
    fetch = jnp.where(free, jnp.maximum(best[0], best[1]), jnp.where(with_plate, best[2], 0.0))
    return (total + plates.sum() + w.fetch * fetch.sum()).astype(jnp.float32)


def shaping_step(env: Any, before: KitchenState, after: KitchenState, done: Any,
                 near: Tables, gamma: float = 1.0, w: Potential = Potential()) -> Any:
    """``F = gamma * phi(after) - phi(before)`` for one step of ``env`` (a
    :class:`~ocplus_plan.sim.fast.jax_env.JaxKitchenEnv`; its states carry no params), with
    ``phi(after) = 0`` where the step ended the episode (``after`` is then the next
    episode's first state and is not used). With the learner's discount as ``gamma`` the
    discounted sum of ``F`` over an episode is ``-phi(s_0) = 0``: holding a high potential
    is not worth more than cashing it in."""
    phi_before = potential(env.kitchen_state(before), near, w)
    phi_after = potential(env.kitchen_state(after), near, w)
    return jnp.where(done, 0.0, gamma * phi_after) - phi_before


__all__ = ["Potential", "Tables", "tables", "jax", "potential", "shaping_step"]

"""The trainer's features and reward shaping for all kitchens of a :class:`BatchSim` at once.

:class:`BatchFeatures` reads the batched engine's arrays and gives, per kitchen and agent,
exactly what :class:`ocplus_plan.rl.features.FeatureEncoder` and
:class:`ocplus_plan.rl.shaping.RewardShaper` (mixed as :class:`KitchenVecEnv` mixes them)
give for the same state: the same bits, held so by ``tests/rl/fast/test_features_batch.py``.
The work is done by the kernels of :mod:`ocplus_plan.rl.fast.features_kernels`, compiled by
numba when the batch is (the ``fast`` extra), plain Python otherwise.

The shaping needs two things the engine's arrays keep for it and ``transition`` reports as
events: each agent's putdown / plate_add of the step (``KitchenArrays.bumps``) and each
item's respawn count (``items[:, I_LIFE]``: a ``stage`` milestone is paid once per life).
"""

from __future__ import annotations

import numpy as np

from ...sim.fast.batch import BatchSim, compile_kernels
from ...sim.codes import COUNTERS, Cell, Item
from ...sim.rules import Rules
from ...sim.state import geometry_for
from . import features_kernels as fk
from ..features import FeatureEncoder
from ..shaping import Shaping, delivery_distances

_KINDS = (Item.TOMATO, Item.LETTUCE, Item.ONION, Item.STEAK, Item.PLATE)


def feature_tables(rules: Rules, shaping: Shaping) -> fk.FeatureTables:
    """The kernels' tables for one rule set and shaping."""
    geo = geometry_for(rules)
    i64 = np.int64
    interact_cells = FeatureEncoder(rules).interact
    interact = np.full((len(interact_cells), max(map(len, interact_cells))), -1, i64)
    for lay, cells in enumerate(interact_cells):
        interact[lay, : len(cells)] = cells
    params = np.array([geo.rows, geo.cols, rules.horizon, rules.dynamic, rules.map_switch_step,
                       rules.tables.duration_at(Cell.PAN), rules.tables.overrun_at(Cell.PAN)], i64)
    is_counter = np.zeros(16, bool)
    is_counter[[int(c) for c in COUNTERS]] = True
    kind_index = np.full(16, 5, i64)
    kind_index[[int(k) for k in _KINDS]] = np.arange(len(_KINDS))
    recipes = np.array([[r.count(k) for k in _KINDS[:4]] for r in rules.recipes], i64)
    to_delivery = np.array([delivery_distances(geo, lay) for lay in range(len(geo.terrains))],
                           i64)
    weights = np.array([shaping.subtask_scale, shaping.stage, shaping.useful_plate,
                        shaping.carry_fresh, shaping.carry_ready, shaping.carry_dish,
                        rules.rewards.subtask_finished], np.float64)
    walk, nbrs = np.array(geo.walkables, bool), np.array(geo.neighbors, i64)
    return fk.FeatureTables(
        params, np.array(geo.terrains, i64), walk, nbrs, interact, is_counter,
        np.array(geo.item_kind, i64), kind_index, recipes, to_delivery, weights,
        _free_reach(walk, nbrs, interact))


def _free_reach(walk: np.ndarray, nbrs: np.ndarray, interact: np.ndarray) -> np.ndarray:
    """Per layout and cell, the kernels' ``reach_cells`` from there ignoring other agents
    (static: the fallback of a path that only other agents block)."""
    n_lay, n_cells = walk.shape
    out = np.zeros((n_lay, n_cells, 2, interact.shape[1]), np.int64)
    agents = np.zeros((1, 2, 1), np.int64)  # one agent, moved over every cell
    dist, first, queue = (np.empty(n_cells, np.int64) for _ in range(3))
    for lay in range(n_lay):
        for pos in range(n_cells):
            agents[0, 0, 0] = pos
            fk.bfs(0, 0, lay, agents, walk, nbrs, False, dist, first, queue)
            fk.reach_cells(pos, lay, interact, nbrs, dist, first, out[lay, pos])
    return out


class BatchFeatures:
    """Features and shaped training rewards of every kitchen of ``sim``.

    Call :meth:`reset` for the kitchens that start an episode (after
    :meth:`BatchSim.reset_envs`), :meth:`rewards` after each step, :meth:`encode` for the
    observations.
    """

    size = fk.N_FEATURES

    def __init__(self, sim: BatchSim, shaping: Shaping | None = None) -> None:
        self.sim = sim
        self.tables = feature_tables(sim.rules, shaping or Shaping())
        self._k = compile_kernels(fk, sim.compiled, nrt=True)
        shape = (sim.n_envs, sim.n_agents)
        #: ``(n_envs, n_agents, size)`` float32, written by :meth:`encode`
        self.obs = np.zeros((*shape, self.size), np.float32)
        self._potential = np.zeros(shape)
        self._paid = np.zeros((sim.n_envs, len(self.tables.kind)), np.int32)
        self.true = np.zeros(shape)  # game reward without the subtask part, last step
        self.reward = np.zeros(shape)  # what the learner sees (before scaling), last step
        self._all = np.ones(sim.n_envs, bool)

    def reset(self, envs: np.ndarray) -> None:
        """Kitchens ``envs`` start an episode: nothing carried, no milestone paid."""
        self._potential[envs] = 0.0
        self._paid[envs] = 0

    def encode(self, active: np.ndarray | None = None) -> np.ndarray:
        """Every agent's features now (:attr:`obs`, rewritten in place; only the kitchens
        with ``active``, all by default)."""
        self.sim.split(self._k.features_range, self.sim.arrays, self.tables, self.obs,
                       self._all if active is None else active)
        return self.obs

    def rewards(self, coef: float, team: bool, active: np.ndarray | None = None) -> np.ndarray:
        """After a step of the kitchens with ``active`` (all by default): per agent, the
        true reward (the team's sum when ``team``) plus ``coef`` times the shaping, as
        :attr:`reward`."""
        self.sim.split(self._k.shaping_range, self.sim.arrays, self.tables, self._potential,
                       self._paid, float(coef), bool(team), self.true, self.reward,
                       self._all if active is None else active)
        return self.reward

    def memory_per_kitchen(self) -> int:
        arrays = (self.obs, self._potential, self._paid, self.true, self.reward)
        return sum(x.nbytes for x in arrays) // self.sim.n_envs


__all__ = ["BatchFeatures", "feature_tables"]

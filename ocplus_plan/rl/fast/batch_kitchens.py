"""The kitchens of a :class:`~ocplus_plan.rl.vec_env.KitchenVecEnv` on the batched engine.

One :class:`BatchSim` (with its :class:`BatchFeatures`) per rule set in use, each as wide
as the vec env; kitchen ``j`` is *active* in the one whose rules its current episode
plays and idle in the others (the kernels skip idle kitchens). A curriculum (several rule
sets, changed by ``set_rules`` between episodes) is then a kitchen moving to another
engine at its next reset. Episode seeds are given by the caller, so they follow the
kitchen, not the engine: the same as on the loop engine.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...errors import ConfigError
from ...sim.fast.batch import BatchSim
from ...sim.fast.kernels import C_T, DISHES
from ...sim.rules import Rules
from .features_batch import BatchFeatures
from ..shaping import Shaping


class BatchKitchens:
    """``n_kitchens`` kitchens, each playing an episode of one of several rule sets.

    ``grid_scale(rules)``: the factor of ``grid`` observations (None: ``features``);
    ``features`` with a ``grid_scale``: both, features first (``window`` observations).
    ``threads``: the engines' threads (:class:`BatchSim`'s; None: the cores available).
    """

    def __init__(self, n_kitchens: int, seed: int, shaping: Shaping, obs_radius: int = 0,
                 grid_scale: Any = None, threads: int | None = None,
                 features: bool | None = None) -> None:
        self.n_kitchens = n_kitchens
        self.seed = seed
        self.shaping = shaping
        self.obs_radius = obs_radius
        self.grid_scale = grid_scale
        self.features = grid_scale is None if features is None else features
        self.threads = threads
        #: id(rules) -> (rules, engine, features, kitchens active in it)
        self.engines: dict[int, tuple[Rules, BatchSim, BatchFeatures, np.ndarray]] = {}
        self.rules: list[Rules | None] = [None] * n_kitchens  # each kitchen's episode rules

    def engine(self, rules: Rules) -> tuple[Rules, BatchSim, BatchFeatures, np.ndarray]:
        hit = self.engines.get(id(rules))
        if hit is None:
            sim = BatchSim(rules, self.n_kitchens, seed=self.seed, obs_radius=self.obs_radius,
                           observe=self.grid_scale is not None, threads=self.threads)
            hit = (rules, sim, BatchFeatures(sim, self.shaping),
                   np.zeros(self.n_kitchens, bool))
            self.engines[id(rules)] = hit
        return hit

    def start(self, kitchens: list[int], rules: list[Rules], seeds: list[int]) -> None:
        """Kitchen ``kitchens[i]`` starts an episode of ``rules[i]`` seeded ``seeds[i]``."""
        for j in kitchens:
            if self.rules[j] is not None:
                self.engine(self.rules[j])[3][j] = False
        for r in {id(r): r for r in rules}.values():
            _, sim, feats, active = self.engine(r)
            mine = [i for i, ri in enumerate(rules) if ri is r]
            envs = np.array([kitchens[i] for i in mine], np.int64)
            sim.reset_envs(envs, [seeds[i] for i in mine])
            feats.reset(envs)
            active[envs] = True
        for j, r in zip(kitchens, rules):
            self.rules[j] = r

    def step(self, actions: np.ndarray, coef: float, team: bool,
             ) -> tuple[np.ndarray, np.ndarray]:
        """Step every kitchen; returns (episode ended, training reward) per kitchen and
        (kitchen, agent)."""
        ended = np.zeros(self.n_kitchens, bool)
        reward = np.zeros((self.n_kitchens, actions.shape[1]))
        for _, sim, feats, active in self.engines.values():
            if active.any():
                terminated, truncated = sim.step_active(actions, active)
                ended |= terminated | truncated
                reward[active] = feats.rewards(coef, team, active)[active]
        return ended, reward

    def obs(self) -> np.ndarray:
        """``(n_kitchens, n_agents, size)`` float32, a new array."""
        out: np.ndarray | None = None
        for rules, sim, feats, active in self.engines.values():
            if not active.any():
                continue
            parts = [feats.encode(active)] if self.features else []
            if self.grid_scale is not None:
                parts.append(sim.obs * self.grid_scale(rules))
            part = parts[0] if len(parts) == 1 else np.concatenate(parts, axis=2)
            if out is None:
                out = np.empty((self.n_kitchens, *part.shape[1:]), np.float32)
            out[active] = part[active]
        if out is None:
            raise ConfigError("call reset() before step()")
        return out

    def game_rewards(self) -> np.ndarray:
        """Each kitchen's game reward of the last step, summed over its cooks."""
        total = np.zeros(self.n_kitchens)
        for _, sim, _, active in self.engines.values():
            total[active] = sim.arrays.rewards[active].sum(axis=1)
        return total

    def episode(self, j: int) -> dict[str, Any]:
        """Kitchen ``j``'s current episode: its rules, seed, steps and dishes."""
        rules, sim, _, _ = self.engine(self.rules[j])  # type: ignore[arg-type]
        return {"rules": rules, "seed": sim.seeds[j], "steps": int(sim.arrays.clock[j, C_T]),
                "dishes": int(sim.arrays.stats[j, DISHES])}

    def close(self) -> None:
        for _, sim, _, _ in self.engines.values():
            sim.close()


__all__ = ["BatchKitchens"]

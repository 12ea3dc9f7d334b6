"""``gymnasium.make_vec("OvercookedPlus-v0", num_envs=N, vectorization_mode="vector_entry_point")``:
N kitchens in one :class:`gymnasium.vector.VectorEnv`, stepped by the batched engine.

Every kitchen is an :class:`~ocplus_plan.env.gym_env.OvercookedPlusEnv` in ``vector``
mode with the same keywords, spaces and rewards (the same rules, bit for bit: the engine
is held to ``transition`` by ``tests/sim/fast/test_batch.py``), stepped together by
:class:`ocplus_plan.sim.fast.batch.BatchSim` instead of one by one.
"""

from __future__ import annotations

from copy import deepcopy
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..errors import ConfigError
from ..sim.fast.batch import BatchSim
from .core import parse_env_kwargs, whole_numbers

#: the most kitchens one vector env holds (each keeps its grids and observations in memory)
MAX_NUM_ENVS = 1 << 16


class BatchedBox(spaces.Box):
    """``n`` stacked copies of the Box ``single`` (shape ``(n, *single.shape)``) whose
    bounds are read-only broadcast views of ``single``'s: the space holds the bounds of one
    kitchen however many kitchens it covers, where Gymnasium's ``batch_space`` repeats
    them ``n`` times. ``contains``, ``sample``, ``shape``, ``dtype``, ``==`` and pickling
    behave as for the repeated Box (``sample`` draws the same values from the same seed).
    """

    def __init__(self, single: spaces.Box, n: int, seed: Any = None) -> None:
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ConfigError(f"a batched Box needs a positive number of copies, got {n!r}")
        spaces.Space.__init__(self, (int(n), *single.shape), single.dtype, seed)
        self.single = single
        self._broadcast()

    def _broadcast(self) -> None:
        one, shape = self.single, self._shape
        self.low = np.broadcast_to(one.low, shape)
        self.high = np.broadcast_to(one.high, shape)
        self.bounded_below = np.broadcast_to(one.bounded_below, shape)
        self.bounded_above = np.broadcast_to(one.bounded_above, shape)
        self.low_repr = self.high_repr = None

    def __getstate__(self) -> dict[str, Any]:
        # the views would pickle as n full copies: keep ``single`` and rebuild them
        state = dict(self.__dict__)
        for name in ("low", "high", "bounded_below", "bounded_above"):
            del state[name]
        return state

    def __setstate__(self, state: Any) -> None:
        self.__dict__.update(state)
        self._broadcast()


def batch_tuple_of_boxes(single: spaces.Tuple, n: int) -> spaces.Tuple:
    """``gymnasium.vector.utils.batch_space`` of a Tuple of Boxes, with :class:`BatchedBox`
    entries (bounds held once, not ``n`` times)."""
    return spaces.Tuple([BatchedBox(box, n, seed=deepcopy(box.np_random)) for box in single.spaces],
                        seed=deepcopy(single.np_random))


class OvercookedPlusVectorEnv(VectorEnv):
    """``num_envs`` Overcooked Plus kitchens (same keywords as ``OvercookedPlus-v0``).

    **Spaces** (per kitchen, batched on a first axis of ``num_envs``): observations a
    ``Tuple`` of one ``Box`` float32 per cook (the ``vector`` encoding of the ``obs_radius``
    window; batched as a :class:`BatchedBox`, whose bounds are one kitchen's, broadcast);
    actions ``MultiDiscrete([5] * n_agents)``; the reward is the team's (the sum over
    cooks, or once the shared reward), or per cook with ``reward_scope="per_agent"`` (then
    ``(num_envs, n_agents)`` float64).

    **Autoreset**: ``autoreset_mode`` is ``AutoresetMode.NEXT_STEP`` (Gymnasium's default:
    the step after an episode ends resets that kitchen and ignores its action) or
    ``SAME_STEP`` (the kitchen restarts in the step that ended it; the last observation
    is in ``info["final_obs"]``, masked by ``info["_final_obs"]``).

    **Copies**: by default (``copy=False``) the observations returned by :meth:`reset`
    and :meth:`step` are read-only views of the engine's live buffer: the next ``step``
    or ``reset`` rewrites them in place, so ``np.copy`` what you keep across steps (a
    rollout buffer that stores them by assignment, ``buf[t] = obs[a]``, already copies).
    ``copy=True`` returns fresh arrays each step, at the price of copying every
    kitchen's observations (2.5x slower at 1,024 kitchens in ``docs/speed.md``).

    Only the ``vector`` mode without communication or rendering is batched; the engine
    reports no per-step events (``info`` is empty); use the single env for those.
    """

    def __init__(self, num_envs: int = 1, preset: str = "hard", *,
                 autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
                 copy: bool = False, reward_scope: str = "team",
                 max_episode_steps: int | None = None, compiled: bool | None = None,
                 **kwargs: Any) -> None:
        if max_episode_steps is not None:
            kwargs.setdefault("horizon", max_episode_steps)
        rules, config = parse_env_kwargs(preset, **kwargs)
        if config.mode != "vector" or config.comm is not None or config.render_mode is not None:
            raise ConfigError(
                "the vector env batches the 'vector' observation mode without communication "
                "or rendering; use gymnasium.make_vec(..., vectorization_mode='sync') for "
                f"mode={config.mode!r}, communication or render_mode"
            )
        if reward_scope not in ("team", "per_agent"):
            raise ConfigError(f"reward_scope must be 'team' or 'per_agent', got {reward_scope!r}")
        mode = AutoresetMode(autoreset_mode)
        if mode not in (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP):
            raise ConfigError(f"autoreset_mode must be NEXT_STEP or SAME_STEP, got {mode!r}")
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) \
                or not 1 <= num_envs <= MAX_NUM_ENVS:
            raise ConfigError(f"num_envs must be a whole number from 1 to {MAX_NUM_ENVS}, "
                              f"got {num_envs!r}")
        num_envs = int(num_envs)
        self.rules = rules
        self.num_envs = num_envs
        self.sim = BatchSim(rules, num_envs, obs_radius=config.obs_radius, compiled=compiled)
        self.n_agents = n = rules.n_agents
        enc = self.sim.encoder
        box = spaces.Box(enc.low, enc.high, shape=(enc.size,), dtype=np.float32)
        self.single_observation_space = spaces.Tuple([box] * n)
        self.single_action_space = spaces.MultiDiscrete([5] * n)
        # bounds held once, not per kitchen (batch_space's Boxes held 46 KB per kitchen)
        self.observation_space = batch_tuple_of_boxes(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.metadata = {"autoreset_mode": mode}
        self.render_mode = None
        self.copy = copy
        self.reward_scope = reward_scope
        self._needs_reset = np.zeros(num_envs, bool)
        self._seeded = False
        self._shared = rules.reward_mode == "shared"

    def reset(self, *, seed: int | list[int] | None = None,
              options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        """Start every kitchen anew. ``seed`` (an int) reseeds the kitchens' episode-seed
        sequences (kitchen ``e`` draws from ``default_rng([seed, e])``)."""
        super().reset(seed=seed)
        if isinstance(seed, list):
            raise ConfigError("seed must be one int for all kitchens (each gets its own stream)")
        if seed is None and not self._seeded:  # a first reset without a seed: draw one
            seed = int(self.np_random.integers(2**31 - 1))
        if seed is not None:
            self.sim.reseed(seed)
            self._seeded = True
        self.sim.reset()
        self._needs_reset[:] = False
        return self._obs(), {}

    def step(self, actions: Any) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict]:
        acts = np.asarray(actions)
        if acts.dtype.kind not in "iu":  # 1.7 or NaN is refused, never truncated
            acts = whole_numbers(actions).reshape(acts.shape)
        info: dict[str, Any] = {}
        if self.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP:
            restart = np.flatnonzero(self._needs_reset)
            terminated, truncated = self.sim.step_active(acts, ~self._needs_reset)
            if len(restart):
                self.sim.reset_envs(restart)
            rewards = self._rewards()
            rewards[restart] = 0.0
            self._needs_reset = terminated | truncated
        else:
            out = self.sim.step(acts)
            terminated, truncated, rewards = out.terminated, out.truncated, self._rewards()
            if out.final_obs:
                mask = np.zeros(self.num_envs, bool)
                mask[list(out.final_obs)] = True
                final = np.empty(self.num_envs, object)
                for e, o in out.final_obs.items():
                    final[e] = tuple(o.copy())
                info = {"final_obs": final, "_final_obs": mask}
        return self._obs(), rewards, terminated, truncated, info

    def close_extras(self, **kwargs: Any) -> None:
        self.sim.close()

    def _rewards(self) -> np.ndarray:
        r = self.sim.arrays.rewards
        if self.reward_scope == "per_agent":
            return r.copy()
        return r[:, 0].copy() if self._shared else r.sum(axis=1)

    def _obs(self) -> tuple[np.ndarray, ...]:
        obs = self.sim.obs
        if self.copy:
            obs = obs.copy()
            return tuple(obs[:, a] for a in range(self.n_agents))
        views = tuple(obs[:, a] for a in range(self.n_agents))
        for v in views:  # a write would corrupt the engine's incremental observations
            v.flags.writeable = False
        return views


__all__ = ["BatchedBox", "OvercookedPlusVectorEnv", "batch_tuple_of_boxes"]

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
from ..sim.fast.arrays import C_T as _C_T
from ..sim.fast.arrays import STAT_NAMES
from ..sim.fast.batch import BatchSim
from .core import parse_env_kwargs, whole_numbers

#: the most kitchens one vector env holds (each keeps its grids and observations in memory)
MAX_NUM_ENVS = 1 << 16

_STAT = {name: i for i, name in enumerate(STAT_NAMES)}


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

    **Seeds** follow ``SyncVectorEnv``: ``reset(seed=s)`` starts kitchen ``e`` on seed
    ``s + e``; ``reset(seed=[s0, s1, ...])`` takes one per kitchen. **Episode statistics**
    (return, length, dishes, orders, expired orders, burns) come in ``info["episode"]``
    when a kitchen's episode ends (see :meth:`step`).

    Only the ``vector`` mode without communication or rendering is batched; the engine
    reports no per-step events; use the single env for those.
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
        shape = (num_envs, self.n_agents) if reward_scope == "per_agent" else (num_envs,)
        self._returns = np.zeros(shape)
        self._shared = rules.reward_mode == "shared"

    def reset(self, *, seed: int | list[int | None] | None = None,
              options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        """Start every kitchen anew, seeded as Gymnasium's ``SyncVectorEnv`` seeds its envs:
        an int ``seed`` starts kitchen ``e`` on episode seed ``seed + e``; a list gives
        kitchen ``e`` the seed ``seed[e]`` (one per kitchen; ``None`` entries draw one).
        Later episodes of kitchen ``e`` draw their seeds from ``default_rng(seed + e)``
        (resp. ``seed[e]``), as that env's own generator would: kitchen ``e`` plays the
        same episodes as ``gymnasium.make("OvercookedPlus-v0")`` reset with that seed."""
        seeds = self._seed_list(seed)
        super().reset(seed=None)  # Gymnasium's own check refuses lists with a generic error
        if seeds is not None:
            seeds = [int(self.np_random.integers(2**31 - 1)) if s is None else s for s in seeds]
        elif not self._seeded:  # a first reset without a seed: draw one
            start = int(self.np_random.integers(2**31 - 1))
            seeds = [start + e for e in range(self.num_envs)]
        if seeds is not None:
            self.sim.reseed_each(seeds)
            self._seeded = True
            self.sim.reset(seeds)
        else:
            self.sim.reset()
        self._needs_reset[:] = False
        self._returns[:] = 0.0
        return self._obs(), {}

    def _seed_list(self, seed: Any) -> list[int | None] | None:
        """``seed`` as one seed (or None) per kitchen; a bad value is refused here, naming
        what is accepted."""
        usage = (f"seed must be None, an int (kitchen e gets seed + e) or a list of "
                 f"{self.num_envs} ints or None (one per kitchen)")
        if seed is None:
            return None
        if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            if seed < 0:
                raise ConfigError(f"{usage}; got the negative seed {seed}")
            return [int(seed) + e for e in range(self.num_envs)]
        if isinstance(seed, (list, tuple)):
            if len(seed) != self.num_envs:
                raise ConfigError(f"{usage}; got a list of {len(seed)}")
            for s in seed:
                if s is not None and (isinstance(s, bool) or not isinstance(s, (int, np.integer))
                                      or s < 0):
                    raise ConfigError(f"{usage}; got {s!r} in the list")
            return [None if s is None else int(s) for s in seed]
        raise ConfigError(f"{usage}; got {type(seed).__name__}")

    def step(self, actions: Any) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, dict]:
        """Step every kitchen. A kitchen whose episode ends reports its statistics as
        Gymnasium's ``RecordEpisodeStatistics`` does: ``info["episode"]`` holds arrays
        ``r`` (return), ``l`` (length), ``dishes``, ``orders`` (completed), ``expired``,
        ``burns`` over all kitchens, each with its ``_key`` mask, and ``info["_episode"]``
        marks the kitchens that ended. With ``SAME_STEP`` autoreset they sit in
        ``info["final_info"]`` (masked by ``info["_final_info"]``), as ``SyncVectorEnv``
        puts an ended env's info."""
        acts = np.asarray(actions)
        if acts.dtype.kind not in "iu":  # 1.7 or NaN is refused, never truncated
            acts = whole_numbers(actions).reshape(acts.shape)
        info: dict[str, Any] = {}
        if self.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP:
            restart = np.flatnonzero(self._needs_reset)
            if len(restart):
                self._returns[restart] = 0.0
            terminated, truncated = self.sim.step_active(acts, ~self._needs_reset)
            if len(restart):
                self.sim.reset_envs(restart)
            rewards = self._rewards()
            rewards[restart] = 0.0
            self._returns += rewards
            self._needs_reset = ended = terminated | truncated
            if ended.any():
                info = self._episode_info(ended)
        else:
            terminated, truncated = self.sim.step_active(acts)
            rewards = self._rewards()
            self._returns += rewards
            ended = terminated | truncated
            if ended.any():
                done = np.flatnonzero(ended)
                final = np.empty(self.num_envs, object)
                last = self.sim.obs[done].copy()
                for j, e in enumerate(done.tolist()):
                    final[e] = tuple(last[j])
                info = {"final_obs": final, "_final_obs": ended.copy(),
                        "final_info": self._episode_info(ended), "_final_info": ended.copy()}
                self.sim.reset_envs(done)
                self.sim.episodes[done] += 1
                self._returns[done] = 0.0
        return self._obs(), rewards, terminated, truncated, info

    def _episode_info(self, ended: np.ndarray) -> dict[str, Any]:
        """The statistics of the episodes that ``ended`` (Gymnasium's masked-array form)."""
        stats = self.sim.arrays.stats
        names = {"dishes": "dishes_served", "orders": "orders_completed",
                 "expired": "orders_expired", "burns": "burns"}
        mask = ended.copy()
        episode: dict[str, Any] = {
            "r": np.where(ended if self._returns.ndim == 1 else ended[:, None],
                          self._returns, 0.0),
            "l": np.where(ended, self.sim.arrays.clock[:, _C_T], 0).astype(np.int64)}
        for key, stat in names.items():
            episode[key] = np.where(ended, stats[:, _STAT[stat]], 0).astype(np.int64)
        for key in list(episode):
            episode["_" + key] = mask
        return {"episode": episode, "_episode": mask}

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

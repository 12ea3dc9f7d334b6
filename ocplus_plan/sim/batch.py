"""Many independent kitchens stepped together, for learner throughput (numpy only).

:class:`BatchSim` holds ``n_envs`` states of one :class:`Rules`; ``step(actions)`` with an
``(n_envs, n_agents)`` int array applies :func:`transition` to each and encodes all the
observations in one vectorised :meth:`VectorEncoder.encode_many` call. Finished episodes
restart at once (the returned observation is the new episode's first; the last one is in
:attr:`BatchStep.final_obs`). Episode seeds come from one generator per kitchen,
``default_rng([seed, env_index])``, so a batch is reproducible from ``seed`` alone.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..errors import ConfigError, InvalidActionError
from .observe import VectorEncoder
from .rules import Rules
from .state import Geometry, State, new_state
from .step import transition

_SEED_HIGH = 2**31 - 1


class BatchStep(NamedTuple):
    obs: np.ndarray  # (n_envs, n_agents, size) float32, after any restart
    rewards: np.ndarray  # (n_envs, n_agents) float32
    terminated: np.ndarray  # (n_envs,) bool
    truncated: np.ndarray  # (n_envs,) bool
    final_obs: dict[int, np.ndarray]  # env index -> (n_agents, size), for envs that ended


class BatchSim:
    """``n_envs`` kitchens of ``rules`` with vector observations of radius ``obs_radius``."""

    def __init__(self, rules: Rules, n_envs: int, *, seed: int = 0, obs_radius: int = 0) -> None:
        if isinstance(n_envs, bool) or not isinstance(n_envs, int) or n_envs < 1:
            raise ConfigError(f"n_envs must be a positive integer, got {n_envs!r}")
        self.rules = rules
        self.n_envs = n_envs
        self.n_agents = rules.n_agents
        self.encoder = VectorEncoder(rules, obs_radius)
        self._geo = Geometry.build(rules)
        self._rngs = [np.random.default_rng([seed, e]) for e in range(n_envs)]
        self.states: list[State] = []
        self.episodes = np.zeros(n_envs, np.int64)

    def _new(self, e: int) -> State:
        return new_state(self.rules, int(self._rngs[e].integers(_SEED_HIGH)), geometry=self._geo)

    def reset(self) -> np.ndarray:
        """Start a new episode everywhere; ``(n_envs, n_agents, size)`` observations."""
        self.states = [self._new(e) for e in range(self.n_envs)]
        return self.encoder.encode_many(self.states)

    def step(self, actions: np.ndarray) -> BatchStep:
        if not self.states:
            raise ConfigError("call reset() before step()")
        acts = np.asarray(actions)
        if acts.shape != (self.n_envs, self.n_agents):
            raise InvalidActionError(
                f"actions must have shape (n_envs, n_agents) = {(self.n_envs, self.n_agents)}, "
                f"got {acts.shape}"
            )
        rows = acts.tolist()
        rewards = np.empty((self.n_envs, self.n_agents), np.float32)
        terminated = np.zeros(self.n_envs, bool)
        truncated = np.zeros(self.n_envs, bool)
        ended = []
        for e, (state, joint) in enumerate(zip(self.states, rows)):
            res = transition(state, joint)
            rewards[e] = res.rewards
            if res.terminated or res.truncated:
                terminated[e], truncated[e] = res.terminated, res.truncated
                ended.append(e)
        final: dict[int, np.ndarray] = {}
        if ended:
            last = self.encoder.encode_many([self.states[e] for e in ended])
            for k, e in enumerate(ended):
                final[e] = last[k]
                self.states[e] = self._new(e)
                self.episodes[e] += 1
        obs = self.encoder.encode_many(self.states)
        return BatchStep(obs, rewards, terminated, truncated, final)


__all__ = ["BatchSim", "BatchStep"]

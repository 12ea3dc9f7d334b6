"""PettingZoo ``ParallelEnv`` over the same simulator (pettingzoo is an optional extra).

Agents are named ``cook_0 .. cook_{n-1}``. Spaces per agent are those of one entry of
:class:`~ocplus_plan.env.gym_env.OvercookedPlusEnv` (``Discrete(5)`` moves, or
``MultiDiscrete([5, comm_vocab])`` with communication); rewards are the simulator's
per-agent rewards; every agent is truncated together at the horizon. Keywords are the
Gymnasium env's (see its docstring). Build one with :func:`ocplus_plan.env.parallel_env`.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from ..errors import ConfigError, DependencyNotInstalled, InvalidActionError

try:
    from gymnasium import spaces
    from pettingzoo import ParallelEnv
except ImportError as exc:  # pragma: no cover - exercised only without the extra
    raise DependencyNotInstalled(
        f"the PettingZoo env needs pettingzoo ({exc}); install it with "
        "pip install 'ocplus-plan[test]' (or pip install pettingzoo)"
    ) from exc

from ..sim import Action, State
from .core import KitchenCore, parse_env_kwargs
from .gym_env import agent_action_space, agent_observation_space

_SEED_HIGH = 2**31 - 1


class OvercookedPlusParallelEnv(ParallelEnv):
    """All cooks act at once; ``step`` takes ``{agent: action}`` for the live agents."""

    metadata = {  # noqa: RUF012
        "name": "overcooked_plus_v0", "render_modes": ["rgb_array"], "is_parallelizable": True,
    }

    def __init__(self, preset: str = "hard", **kwargs: Any) -> None:
        rules, config = parse_env_kwargs(preset, **kwargs)
        if config.render_mode == "human":
            raise ConfigError(
                "the PettingZoo env draws rgb_array frames only; use render_mode='rgb_array', "
                "or the Gymnasium env with render_mode='human' for a window"
            )
        self.rules = rules
        self.config = config
        self.render_mode = config.render_mode
        self.core = KitchenCore(rules, config)
        self.possible_agents = [f"cook_{i}" for i in range(rules.n_agents)]
        self.agents: list[str] = []
        self._index = {name: i for i, name in enumerate(self.possible_agents)}
        self._obs_space = agent_observation_space(self.core)
        self._act_space = agent_action_space(self.core)
        self._rng = np.random.default_rng()

    @functools.cache  # noqa: B019 - one space object per agent, by contract
    def observation_space(self, agent: str) -> spaces.Space:
        return self._obs_space

    @functools.cache  # noqa: B019
    def action_space(self, agent: str) -> spaces.Space:
        return self._act_space

    @property
    def state_now(self) -> State:
        """The live simulator state."""
        return self.core.state

    def _observations(self) -> dict[str, Any]:
        obs = self.core.observe()
        return {a: obs[self._index[a]] for a in self.agents}

    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, Any], dict[str, dict[str, Any]]]:
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        episode_seed = seed if seed is not None else int(self._rng.integers(_SEED_HIGH))
        self.core.reset(episode_seed)
        self.agents = list(self.possible_agents)
        return self._observations(), {a: {"episode_seed": episode_seed} for a in self.agents}

    def step(self, actions: dict[str, Any]) -> tuple[dict, dict, dict, dict, dict]:
        if not self.agents:
            raise InvalidActionError("the episode is over: call reset() before step()")
        unknown = sorted(set(actions) - set(self.agents))
        if unknown:
            raise InvalidActionError(f"actions for unknown or finished agents {unknown}; "
                                     f"live agents: {self.agents}")
        comm = self.core.comm is not None
        joint: list[int] = []
        for name in self.possible_agents:
            act = actions.get(name)
            if act is None:  # an agent without an action stays (and says token 0)
                joint += [int(Action.STAY), 0] if comm else [int(Action.STAY)]
            elif comm:
                pair = np.asarray(act, dtype=np.int64).reshape(-1)
                if pair.size != 2:
                    raise InvalidActionError(f"{name}: expected [move, token], got {act!r}")
                joint += pair.tolist()
            else:
                joint.append(int(np.asarray(act).reshape(-1)[0]))
        moves, tokens = self.core.split_action(joint)
        result = self.core.step(moves, tokens)
        names = self.agents
        obs = self._observations()
        rewards = {a: float(result.rewards[self._index[a]]) for a in names}
        terminated = dict.fromkeys(names, bool(result.terminated))
        truncated = dict.fromkeys(names, bool(result.truncated))
        infos = {a: {"t": self.core.state.t} for a in names}
        if result.terminated or result.truncated:
            self.agents = []
        return obs, rewards, terminated, truncated, infos

    def render(self) -> np.ndarray | None:
        if self.render_mode == "rgb_array":
            from ..render.rgb import render_frame

            return render_frame(self.core.state)
        return None

    def close(self) -> None:
        pass

    def state(self) -> np.ndarray:
        """A global view for centralised critics: the whole-map rgb frame."""
        from ..render.rgb import render_frame

        return render_frame(self.core.state)


__all__ = ["OvercookedPlusParallelEnv"]

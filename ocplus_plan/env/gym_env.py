"""Gymnasium envs over the simulator: all agents in one env, and a single-agent view."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, SupportsFloat

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded

from ..errors import ConfigError, DependencyNotInstalled, InvalidActionError
from ..sim import Action, Rules, State, new_state
from ..sim.observe_text import TEXT_CHARSET, max_text_length
from .core import EnvConfig, KitchenCore, parse_env_kwargs, whole_numbers

_SEED_HIGH = 2**31 - 1


class StateSpace(spaces.Space):
    """The ``symbolic`` observation space: states (snapshots) of one rule set's kitchens."""

    def __init__(self, rules: Rules, seed: int | None = None) -> None:
        super().__init__(shape=None, dtype=None, seed=seed)
        self.rules = rules

    @property
    def is_np_flattenable(self) -> bool:
        return False

    def sample(self, mask: Any = None, probability: Any = None) -> State:
        """The initial state of a random episode (a valid, if unremarkable, member)."""
        return new_state(self.rules, int(self.np_random.integers(_SEED_HIGH)))

    def contains(self, x: Any) -> bool:
        return (isinstance(x, State) and x.geo.rows == self.rules.layout.rows
                and x.geo.cols == self.rules.layout.cols and x.n_agents == self.rules.n_agents)

    def __repr__(self) -> str:
        return f"StateSpace({self.rules.preset}, {self.rules.layout.name}, n={self.rules.n_agents})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, StateSpace) and other.rules is self.rules

    def __hash__(self) -> int:
        return hash(id(self.rules))


def agent_observation_space(core: KitchenCore) -> spaces.Space:
    """One agent's observation space for the core's mode (see :meth:`KitchenCore.observe`)."""
    if core.vector is not None:
        v = core.vector
        return spaces.Box(v.low, v.high, shape=(v.size,), dtype=np.float32)
    base: spaces.Space
    if core.rgb is not None:
        base = spaces.Box(0, 255, shape=core.rgb.shape, dtype=np.uint8)
    elif core.config.mode == "text":
        base = spaces.Text(max_text_length(core.state), charset=TEXT_CHARSET)
    else:
        base = StateSpace(core.rules)
    if core.comm is None:
        return base
    vocab = core.comm.config.vocab
    return spaces.Dict({"obs": base,
                        "messages": spaces.MultiDiscrete([vocab + 1] * (core.n_agents - 1))})


def agent_action_space(core: KitchenCore) -> spaces.Space:
    """One agent's action space: a move, or with communication ``[move, token]``."""
    if core.comm is None:
        return spaces.Discrete(5)
    return spaces.MultiDiscrete([5, core.comm.config.vocab])


class _Base(gym.Env):
    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 8}  # noqa: RUF012

    def _setup(self, preset: str, kwargs: dict[str, Any]) -> None:
        rules, config = parse_env_kwargs(preset, **kwargs)
        self.rules: Rules = rules
        self.config: EnvConfig = config
        self.render_mode = config.render_mode
        self.core = KitchenCore(rules, config)
        self._needs_reset = True
        self._window: Any = None

    @property
    def state(self) -> State:
        """The live simulator state (mutated by :meth:`step`; copy it to keep it)."""
        return self.core.state

    def _reset_core(self, seed: int | None) -> None:
        super().reset(seed=seed)
        episode_seed = seed if seed is not None else int(self.np_random.integers(_SEED_HIGH))
        self.core.reset(episode_seed)
        self._needs_reset = False

    def render(self) -> np.ndarray | None:
        """``rgb_array``: the whole map as an ``(H, W, 3)`` uint8 frame; ``human``: draw it in
        the pygame window (``ocplus-plan[gui]``); ``None``: nothing."""
        if self.render_mode == "rgb_array":
            from ..render.rgb import render_frame

            return render_frame(self.core.state)
        if self.render_mode == "human":
            if self._window is None:
                try:
                    from ..render.window import Window
                except ImportError as exc:
                    raise DependencyNotInstalled(
                        "render_mode='human' needs the pygame window (ocplus_plan.render.window) "
                        f"which could not be imported ({exc}); install ocplus-plan[gui] or use "
                        "render_mode='rgb_array'"
                    ) from exc
                self._window = Window("ocplus-plan", offscreen_ok=True)  # check_env tries it
            messages = []
            if self.core.comm is not None:
                for a, row in enumerate(self.core.received.tolist()):
                    got = [f"{(a + k + 1) % self.core.n_agents}:{t}" for k, t in enumerate(row)
                           if t >= 0]
                    messages.append(f"cook {a} heard " + (", ".join(got) or "nothing"))
            self._window.show(self.core.state, messages=messages,
                              humans=self.config.human_cooks)
            self._window.poll()
            self._window.tick(self.metadata["render_fps"])
        return None

    def close(self) -> None:
        if self._window is not None:
            self._window.close()
            self._window = None

    def _finish(
        self, result: Any, reward: float | np.ndarray
    ) -> tuple[Any, Any, bool, bool, dict[str, Any]]:
        """The common end of ``step``: episode bookkeeping, rendering, the 5-tuple."""
        if result.terminated or result.truncated:
            self._needs_reset = True
        if self.render_mode == "human":
            self.render()
        info = {"rewards": list(result.rewards), "events": result.events, "t": self.core.state.t}
        if not isinstance(reward, np.ndarray):
            reward = float(reward)
        return self._obs(), reward, result.terminated, result.truncated, info

    def _check_running(self) -> None:
        if self._needs_reset:
            raise ResetNeeded("call reset() before step(): the episode is over or never began")


class OvercookedPlusEnv(_Base):
    """Overcooked Plus kitchen with all cooks in one Gymnasium env (SPEC sections 1-9).

    **Description.** Cooks on a grid fetch ingredients, chop vegetables on boards, cook
    steak on pans (it burns if left), plate and deliver the active orders; on the hard
    preset plates come back dirty and must be washed, and walls move every
    ``map_switch_step`` steps. The rules are the simulator's (:mod:`ocplus_plan.sim`).

    **Keywords** (the paper's names and ours are both accepted): ``preset`` (``easy`` |
    ``medium`` | ``hard``), ``map_name`` / ``map`` (registered name, YAML path or dict),
    ``dynamic_map`` / ``dynamic``, ``rewardList`` / ``rewards`` (keys such as
    ``"correct delivery"`` or ``correct_delivery``), ``n_agent`` / ``n_agents``,
    ``horizon``, ``obs_radius`` (0 = whole map), ``mode`` / ``obs_mode`` (``vector`` |
    ``rgb`` (alias ``image``) | ``symbolic`` | ``text``), ``agent_communication`` with
    ``comm_vocab`` (8), ``comm_range`` (0 = unlimited), ``comm_failure_rate`` (0.0), ``comm_delay`` (1),
    ``GUI`` / ``GUI_enable`` / ``render_mode`` (``None`` | ``"rgb_array"`` | ``"human"``),
    ``reward_scope`` (``"team"`` | ``"per_agent"``), the paper's ``n_task``,
    ``fixed_task``, ``task_idx``, ``min_ing``, ``max_ing``, ``human_player`` and ``debug``
    (meanings in :mod:`ocplus_plan.env.paper`), and any other rule parameter of
    :func:`ocplus_plan.sim.make_rules`. The seed goes through
    ``reset(seed=...)``; ``reset()`` without one draws the episode seed from the env's
    generator, so a seeded first reset makes the whole sequence reproducible.

    **Actions.** ``MultiDiscrete([5] * n)``: per cook ``0 right, 1 down, 2 left, 3 up,
    4 stay``; moving into a non-walkable cell interacts with it. With
    ``agent_communication`` it is ``MultiDiscrete([5, comm_vocab] * n)``, interleaved
    ``[move0, token0, move1, token1, ...]``.

    **Observations.** A ``Tuple`` with one entry per cook. ``vector``: ``Box`` float32 of
    :attr:`VectorEncoder.size <ocplus_plan.sim.observe.VectorEncoder>` values (grid
    channels of the ``obs_radius`` window + hand, position, time, orders and received
    messages; the exact layout is ``env.unwrapped.core.vector.feature_names`` and
    ``GRID_CHANNELS``), with exact per-element bounds. ``rgb``: ``Box`` uint8 ``(H, W, 3)``
    picture of the window (``TILE_SIZE`` pixels per cell; whole map for r = 0). ``symbolic``:
    a :class:`StateSnapshot <ocplus_plan.sim.observe.StateSnapshot>` of the full state
    (the same object for every cook). ``text``: a ``Text`` string per cook, the kitchen,
    its items, orders and timers and what each action would do for that cook, in plain
    words (:mod:`ocplus_plan.sim.observe_text`; ``obs_radius`` must be 0). With
    communication, rgb, symbolic and text observations are
    ``Dict(obs=..., messages=MultiDiscrete([comm_vocab + 1] * (n - 1)))``: the token received from each other cook ``(a + k + 1) % n``, ``comm_vocab`` meaning none.

    **Rewards.** The scalar reward is the team sum of the per-cook rewards (with
    ``reward_mode="shared"`` every cook already gets the team's total, which is returned
    once); ``info["rewards"]`` holds the per-cook list and ``info["events"]`` the step's
    simulator events. ``reward_scope="per_agent"`` returns the per-cook rewards instead,
    as a float64 array (``reward[i]``, the paper's loop): that is not Gymnasium's scalar
    reward, so make it with ``gymnasium.make(..., disable_env_checker=True)`` (the passive
    checker tests the first reward as a scalar) or with :func:`~ocplus_plan.create_env`.
    Defaults: subtask +10, correct delivery +200, wrong delivery -5, step -0.1 per cook,
    burnt steak -2, expired order -20.

    **Termination.** ``truncated`` after ``horizon`` (200) steps; ``terminated`` only when
    ``stop_after_orders`` orders have been served (off by default).

    **Registered configurations.** ``OvercookedPlus-v0`` (this class, preset ``hard``, 2
    cooks, MapC), ``Overcooked-Plus`` (this class as the paper's constructor builds it:
    :func:`make_paper_env`) and ``OvercookedPlusSingle-v0``
    (:class:`OvercookedPlusSingleEnv`); ``import ocplus_plan`` registers them, or use
    ``gymnasium.make("ocplus_plan:OvercookedPlus-v0")`` with no import of ours first.
    """

    def __init__(self, preset: str = "hard", *, reward_scope: str = "team", **kwargs: Any) -> None:
        if reward_scope not in ("team", "per_agent"):
            raise ConfigError(f"reward_scope must be 'team' or 'per_agent', got {reward_scope!r}")
        self.reward_scope = reward_scope
        self._setup(preset, kwargs)
        n = self.core.n_agents
        agent_obs = agent_observation_space(self.core)
        self.observation_space = spaces.Tuple([agent_obs] * n)
        if self.core.comm is None:
            self.action_space = spaces.MultiDiscrete([5] * n)
        else:
            self.action_space = spaces.MultiDiscrete([5, self.core.comm.config.vocab] * n)

    def _obs(self) -> tuple[Any, ...]:
        return tuple(self.core.observe())

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[tuple[Any, ...], dict[str, Any]]:
        self._reset_core(seed)
        if self.render_mode == "human":
            self.render()
        return self._obs(), {"episode_seed": self.core.episode_seed, "t": 0}

    def step(
        self, action: Any
    ) -> tuple[tuple[Any, ...], SupportsFloat | np.ndarray, bool, bool, dict[str, Any]]:
        self._check_running()
        moves, tokens = self.core.split_action(action)
        result = self.core.step(moves, tokens)
        rewards = result.rewards
        if self.reward_scope == "per_agent":
            return self._finish(result, np.array(rewards, dtype=np.float64))
        return self._finish(result, rewards[0] if self.rules.reward_mode == "shared" else sum(rewards))


Partner = Callable[[State], Sequence[int]]


class OvercookedPlusSingleEnv(_Base):
    """Single-agent view of :class:`OvercookedPlusEnv` for standard RL libraries.

    The learner drives cook ``agent_id`` (0); the others are driven by ``partner``: None
    (they stay), a controller with ``act(state) -> list[int]`` (one action per other cook,
    in index order; its ``reset(state, agent_ids)`` is called at every reset when present),
    or a plain callable ``state -> list[int]``. Partners send token 0 when
    communication is on.

    Spaces: the observation is the learner's own entry of the multi-agent tuple (``Box``
    for vector and rgb, a state for symbolic); the action is ``Discrete(5)``, or
    ``MultiDiscrete([5, comm_vocab])`` with communication. The reward is the team sum
    (``reward_scope="team"``) or the learner's own (``"own"``); ``info["rewards"]`` has
    every cook's. Other keywords, termination and registration: see
    :class:`OvercookedPlusEnv` (registered as ``OvercookedPlusSingle-v0``).
    """

    def __init__(self, preset: str = "hard", *, agent_id: int = 0, partner: Any = None,
                 reward_scope: str = "team", **kwargs: Any) -> None:
        self._setup(preset, kwargs)
        n = self.core.n_agents
        if isinstance(agent_id, bool) or not isinstance(agent_id, int) or not 0 <= agent_id < n:
            raise ConfigError(f"agent_id must be one of 0..{n - 1}, got {agent_id!r}")
        if reward_scope not in ("team", "own"):
            raise ConfigError(f"reward_scope must be 'team' or 'own', got {reward_scope!r}")
        if partner is not None and not (hasattr(partner, "act") or callable(partner)):
            raise ConfigError(
                "partner must be None (stay), a controller with act(state), or a callable "
                f"state -> actions; got {type(partner).__name__}"
            )
        self.agent_id = agent_id
        self.partner = partner
        self.reward_scope = reward_scope
        self.others = [a for a in range(n) if a != agent_id]
        self.observation_space = agent_observation_space(self.core)
        self.action_space = agent_action_space(self.core)

    def _obs(self) -> Any:
        return self.core.observe()[self.agent_id]

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        self._reset_core(seed)
        if self.partner is not None and hasattr(self.partner, "reset"):
            self.partner.reset(self.core.state, self.others)
        if self.render_mode == "human":
            self.render()
        return self._obs(), {"episode_seed": self.core.episode_seed, "t": 0}

    def _partner_moves(self) -> list[int]:
        if not self.others:
            return []
        if self.partner is None:
            return [int(Action.STAY)] * len(self.others)
        act = self.partner.act if hasattr(self.partner, "act") else self.partner
        moves = [int(m) for m in act(self.core.state)]
        if len(moves) != len(self.others):
            raise ConfigError(
                f"partner returned {len(moves)} actions but drives {len(self.others)} cooks "
                f"{self.others}"
            )
        return moves

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        self._check_running()
        n = self.core.n_agents
        others = iter(self._partner_moves())
        if self.core.comm is None:
            flat = whole_numbers(action)
            if flat.size != 1:
                raise InvalidActionError(f"this env drives one cook: give one move (0..4), "
                                         f"got {flat.size} values")
            own = int(flat[0])
            joint: list[int] = [own if a == self.agent_id else next(others) for a in range(n)]
        else:
            pair = whole_numbers(action)
            if pair.size != 2:
                raise InvalidActionError(
                    f"with agent_communication the action is [move, token], got {action!r}"
                )
            joint = []
            for a in range(n):
                joint += [int(pair[0]), int(pair[1])] if a == self.agent_id else [next(others), 0]
        moves, tokens = self.core.split_action(joint)
        result = self.core.step(moves, tokens)
        rewards = result.rewards
        if self.reward_scope == "own":
            reward = rewards[self.agent_id]
        else:
            reward = rewards[0] if self.rules.reward_mode == "shared" else sum(rewards)
        return self._finish(result, reward)


def make_paper_env(**kwargs: Any) -> Any:
    """The entry point of ``gymnasium.make("Overcooked-Plus", **kwargs)``: the env the
    paper's constructor builds from ``kwargs`` (see :func:`paper_config`), so ``make`` and
    ``create_env(**kwargs)`` give the same kitchen on every map the paper ships (mapA-D, F)."""
    from .paper import paper_config

    config = paper_config(kwargs)
    return OvercookedPlusEnv(config.pop("preset"), **config)



__all__ = ["OvercookedPlusEnv", "OvercookedPlusSingleEnv", "StateSpace", "make_paper_env"]

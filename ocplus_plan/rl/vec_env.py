"""A stable-baselines3 ``VecEnv`` whose slots are agents: parameter sharing for free.

``KitchenVecEnv`` runs ``n_kitchens`` simulator instances with ``n_agents`` agents each
and exposes ``n_kitchens * n_agents`` slots (slot ``j * n_agents + a`` is agent ``a`` of
kitchen ``j``; with a partner, below, the slots list each kitchen's learner cooks in
turn). One PPO policy acts for every slot, so every agent is driven by the same
network from its own observation, and every agent's experience trains it.

Two engines step the kitchens, with the same results bit for bit. ``engine="loop"``
(default) runs ``transition``, the encoder and :class:`RewardShaper` per kitchen: the
reference. ``engine="batch"`` steps all kitchens in the batched engine
(:class:`ocplus_plan.sim.fast.batch.BatchSim`, one per rule set of a curriculum:
:class:`ocplus_plan.rl.fast.batch_kitchens.BatchKitchens`) and computes ``features``
observations and the full shaping as arrays
(:class:`ocplus_plan.rl.fast.features_batch.BatchFeatures`; ``grid`` observations are the
engine's own). Episodes end at the rules' horizon; kitchen ``j`` then resets with the
next seed of its own sequence (:func:`ocplus_plan.sim.fast.batch.seed_sequence`, the same on
both engines, so the same actions give the same observations and rewards: see
``tests/rl/fast/test_features_batch.py``). Finished episodes are queued in
:attr:`KitchenVecEnv.finished` for the logging callback.

A partner (``partner``: a factory ``seed -> Controller``, e.g. the greedy cook, passed in by
the caller) drives the last cook of the first ``partner_kitchens`` kitchens (loop engine):
it acts on the kitchen's state before each step, as in an evaluation with ``--partner``,
and its cook has no slot, so its steps are never the learner's samples. The other cooks of
those kitchens, and every cook of the rest, are the policy's slots.

With ``obs="choice"`` a task-choice controller per kitchen (``chooser``, the caller's:
:class:`ocplus_plan.agents.task_choice.TaskChoice`) encodes the learner cooks' observations
and turns the policy's actions, one subtask slot per cook, into moves (loop engine).

Imports stable-baselines3 at module level: import it only where the ``rl`` extra is
known to be installed (:mod:`ocplus_plan.rl.train` does so lazily).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from gymnasium import spaces
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from ..errors import ConfigError
from ..sim.fast.batch import next_seed, seed_sequence
from ..sim.rules import Rules
from ..sim.state import State, new_state
from ..sim.step import transition
from .obs import make_encoder
from .shaping import RewardShaper, Shaping


class _Size:
    """The observation size of a rule set where the chooser encodes (``obs="choice"``)."""

    def __init__(self, size: int) -> None:
        self.size = size


class KitchenVecEnv(VecEnv):
    """``n_kitchens`` kitchens x ``n_agents`` agents as one vectorised env.

    ``rules`` may be one rule set or a list (a curriculum mixture: kitchen ``j`` uses
    ``rules[j % len(rules)]``; with ``draw=True`` each episode of kitchen ``j`` plays a
    rule set drawn uniformly from the list by kitchen ``j``'s own generator: a kitchen
    distribution); all must have the same number of agents.
    ``team_reward``: each agent receives the team's summed true reward (plus its own
    shaping), so the agent that chops shares the delivery. ``reward_scale`` multiplies
    everything the learner sees (the logged game reward is unscaled). ``threads``: the
    batched engine's threads (it splits 256 kitchens or more over them; None: every core).
    ``partner`` (``seed -> Controller``) drives the last cook of kitchens
    ``0..partner_kitchens-1`` (loop engine); those cooks have no slot.
    """

    def __init__(
        self,
        rules: Rules | Sequence[Rules],
        n_kitchens: int = 8,
        seed: int = 0,
        *,
        obs: str = "features",
        obs_radius: int = 0,
        shaping: Shaping | None = None,
        team_reward: bool = True,
        reward_scale: float = 0.02,
        engine: str = "loop",
        threads: int | None = None,
        draw: bool = False,
        partner: Callable[[int], Any] | None = None,
        partner_kitchens: int = 0,
        chooser: Any = None,
    ) -> None:
        rule_list = [rules] if isinstance(rules, Rules) else list(rules)
        if not rule_list:
            raise ConfigError("KitchenVecEnv needs at least one rule set")
        if isinstance(n_kitchens, bool) or not isinstance(n_kitchens, int) or n_kitchens < 1:
            raise ConfigError(f"n_kitchens must be a positive integer, got {n_kitchens!r}")
        n_agents = {r.n_agents for r in rule_list}
        if len(n_agents) != 1:
            raise ConfigError(
                f"all rule sets of a KitchenVecEnv need the same n_agents, got {sorted(n_agents)}"
            )
        for r in rule_list:
            if r.reward_mode != "individual":
                raise ConfigError(
                    "training needs reward_mode='individual' (per-agent rewards are split into "
                    "true and shaping parts); use team_reward=True for a shared team reward"
                )
        self.n_agents = n_agents.pop()
        self.n_kitchens = n_kitchens
        self._partner_slots(partner, partner_kitchens, engine, seed)
        self._choice_slots(chooser, obs, engine, seed)
        self.rule_list = rule_list
        self._obs_kind, self._obs_radius = obs, obs_radius
        self._encoders: dict[int, Any] = {}  # id(rules) -> encoder (Rules holds arrays)
        sizes = {self._encoder(r).size for r in rule_list}
        if len(sizes) != 1:
            raise ConfigError(
                f"the rule sets give observations of different sizes {sorted(sizes)}; "
                "use obs='features' or 'window' (map-independent) for a curriculum over maps"
            )
        self.obs_size = sizes.pop()
        self.team_reward = team_reward
        self.reward_scale = float(reward_scale)
        self.shaping_coef = 1.0
        self.base_seed = int(seed)
        self._seed_rngs = [seed_sequence(self.base_seed, j) for j in range(n_kitchens)]
        self.draw = bool(draw)
        self._draw_rngs = [np.random.default_rng([self.base_seed, j, 1]) for j in range(n_kitchens)]
        self.finished: list[dict[str, Any]] = []
        #: id(rules) -> a name for the episode log (curriculum stages); default: the preset
        self.rule_labels: dict[int, str] = {}
        self.shapers = [RewardShaper(shaping or Shaping()) for _ in range(n_kitchens)]
        self.batch = self._batch_engine(engine, shaping or Shaping(), seed, threads)
        self.states: list[State] = []
        self._game_return = [0.0] * n_kitchens
        self._train_return = np.zeros((n_kitchens, self.n_agents))
        self._actions = np.zeros(self._n_slots, dtype=np.int64)
        obs_space = spaces.Box(-1.0, 1.0, shape=(self.obs_size,), dtype=np.float32)
        if obs != "features":
            obs_space = spaces.Box(-np.inf, np.inf, shape=(self.obs_size,), dtype=np.float32)
        self.render_mode = None  # nothing to render (SB3 warns when the attribute is missing)
        actions = 5 if chooser is None else chooser.n_actions
        super().__init__(self._n_slots, obs_space, spaces.Discrete(actions))

    def _partner_slots(self, partner: Callable[[int], Any] | None, kitchens: int, engine: str,
                       seed: int) -> None:
        """Kitchen ``j``'s first slot (``_lo[j]``) and its learner cooks (``_cooks[j]``):
        every cook but the last where a partner plays it."""
        if isinstance(kitchens, bool) or not isinstance(kitchens, int) \
                or not 0 <= kitchens <= self.n_kitchens:
            raise ConfigError(f"partner_kitchens must be 0..{self.n_kitchens}, got {kitchens!r}")
        if kitchens and partner is None:
            raise ConfigError("partner_kitchens needs the partner's factory (partner=)")
        if kitchens and self.n_agents < 2:
            raise ConfigError("a partner plays the last cook beside the learner's: the "
                              f"kitchens need at least 2 cooks, they have {self.n_agents}")
        if kitchens and engine != "loop":
            raise ConfigError("a partner acts on the simulator's state: it needs the loop "
                              f"engine, not {engine!r}")
        self.partner_kitchens = kitchens
        self.partners = [partner(seed + j) for j in range(kitchens)] if kitchens else []
        self._cooks = [self.n_agents - (j < kitchens) for j in range(self.n_kitchens)]
        self._lo = np.concatenate([[0], np.cumsum(self._cooks)[:-1]]).astype(int).tolist()
        self._n_slots = int(sum(self._cooks))
        self.partner_name = self.partners[0].name if self.partners else ""

    def _choice_slots(self, chooser: Any, obs: str, engine: str, seed: int) -> None:
        """With ``obs="choice"``, one task-choice controller per kitchen (``chooser``:
        ``seed -> controller`` with ``obs_size(rules)``, ``n_actions``, ``prepare`` and
        ``drive``) drives its learner cooks: the policy's actions choose subtasks."""
        if (chooser is None) != (obs != "choice"):
            raise ConfigError("obs 'choice' goes with a task-choice controller (chooser=: "
                              "ocplus train passes it), and a chooser with obs 'choice'")
        if chooser is not None and engine != "loop":
            raise ConfigError(f"obs 'choice' runs the greedy cook's skills on the simulator's "
                              f"state: it needs the loop engine, not {engine!r}")
        self._chooser = chooser
        self.choosers = [] if chooser is None else \
            [chooser(seed + j) for j in range(self.n_kitchens)]

    # ------------------------------------------------------------ kitchens
    def _encoder(self, rules: Rules) -> Any:
        enc = self._encoders.get(id(rules))
        if enc is None and self._chooser is not None:
            enc = self._encoders[id(rules)] = _Size(self._chooser.obs_size(rules))
        if enc is None:
            enc = self._encoders[id(rules)] = make_encoder(self._obs_kind, rules, self._obs_radius)
        return enc

    def set_rules(self, rules: Rules | Sequence[Rules]) -> None:
        """Switch the mixture of rule sets (a curriculum stage). Running episodes finish
        under their old rules; each kitchen picks up the new ones at its next reset."""
        rule_list = [rules] if isinstance(rules, Rules) else list(rules)
        for r in rule_list:
            if r.n_agents != self.n_agents or self._encoder(r).size != self.obs_size:
                raise ConfigError(
                    f"curriculum rule set {r.preset!r} does not match this env "
                    f"({self.n_agents} agents, observation size {self.obs_size})"
                )
        self.rule_list = rule_list

    def _new_episode(self, kitchen: int) -> State:
        seed = next_seed(self._seed_rngs[kitchen])
        state = new_state(self._pick(kitchen), seed)
        self.shapers[kitchen].reset(state)
        if kitchen < self.partner_kitchens:
            self.partners[kitchen].reset(state, [self.n_agents - 1])
        if self.choosers:
            self.choosers[kitchen].reset(state, list(range(self._cooks[kitchen])))
        self._game_return[kitchen] = 0.0
        self._train_return[kitchen] = 0.0
        return state

    def _pick(self, kitchen: int) -> Rules:
        """The rules of kitchen ``kitchen``'s next episode."""
        rules = self.rule_list
        if self.draw:
            return rules[int(self._draw_rngs[kitchen].integers(len(rules)))]
        return rules[kitchen % len(rules)]

    def _encode(self, kitchen: int) -> np.ndarray:
        """The observations of kitchen ``kitchen``'s learner cooks."""
        state = self.states[kitchen]
        if self.choosers:  # its learner cooks are 0..m-1: the rows are theirs
            return self.choosers[kitchen].prepare(state)
        return self._encoder(state.rules).encode_all(state)[: self._cooks[kitchen]]

    def _batch_engine(self, engine: str, shaping: Shaping, seed: int,
                      threads: int | None) -> Any:
        if engine == "loop":
            return None
        if engine != "batch":
            raise ConfigError(f"engine must be 'loop' or 'batch', got {engine!r}")
        from .fast.batch_kitchens import BatchKitchens

        scale = None
        if self._obs_kind in ("grid", "window"):
            def scale(rules: Rules) -> np.ndarray:
                enc = self._encoder(rules)
                return (enc._grid if self._obs_kind == "window" else enc)._scale
        return BatchKitchens(self.n_kitchens, seed, shaping, self._obs_radius, scale, threads,
                             features=self._obs_kind != "grid")

    def _batch_obs(self) -> np.ndarray:
        """Every slot's observation (a new array: SB3 keeps the last one across a step)."""
        return self.batch.obs().reshape(self.num_envs, self.obs_size)

    def _start_batch(self, kitchens: list[int]) -> None:
        rules = [self._pick(j) for j in kitchens]
        self.batch.start(kitchens, rules, [next_seed(self._seed_rngs[j]) for j in kitchens])
        for j in kitchens:
            self._game_return[j] = 0.0
            self._train_return[j] = 0.0

    # ------------------------------------------------------------ VecEnv API
    def reset(self) -> np.ndarray:
        if self.batch is not None:
            self._start_batch(list(range(self.n_kitchens)))
            return self._batch_obs()
        self.states = [self._new_episode(j) for j in range(self.n_kitchens)]
        return np.concatenate([self._encode(j) for j in range(self.n_kitchens)])

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions, dtype=np.int64).reshape(-1)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        if self.batch is not None:
            return self._step_batch()
        n = self.n_agents
        obs = np.empty((self.num_envs, self.obs_size), dtype=np.float32)
        rewards = np.zeros(self.num_envs, dtype=np.float32)
        dones = np.zeros(self.num_envs, dtype=bool)
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        coef = self.shaping_coef
        for j, state in enumerate(self.states):
            lo, m = self._lo[j], self._cooks[j]
            joint = self._actions[lo : lo + m].tolist()
            if self.choosers:
                joint = self.choosers[j].drive(state, joint)
            if m < n:
                joint += [int(a) for a in self.partners[j].act(state)]
            result = transition(state, joint)
            if m < n:
                self.partners[j].observe(state, result.events)
            true, shaped = self.shapers[j].step(state, result.events, result.rewards)
            if self.team_reward:
                team = sum(true)
                r = [team + coef * s for s in shaped]
            else:
                r = [t + coef * s for t, s in zip(true, shaped)]
            rewards[lo : lo + m] = r[:m]
            self._train_return[j] += r
            self._game_return[j] += sum(result.rewards)
            if result.terminated or result.truncated:
                final = self._encode(j)
                self.finished.append({
                    "kitchen": j,
                    "preset": state.rules.preset,
                    "rules": self.rule_labels.get(id(state.rules), state.rules.preset),
                    "map": state.rules.layout.name,
                    "seed": state.seed,
                    "steps": state.t,
                    "game_reward": self._game_return[j],
                    "train_return": float(self._train_return[j].mean()),
                    "dishes": state.stats["dishes_served"],
                    "shaping_coef": coef,
                    "partner": self.partner_name if m < n else "",
                })
                for a in range(m):
                    infos[lo + a]["terminal_observation"] = final[a]
                    infos[lo + a]["episode"] = {
                        "r": float(self._train_return[j, a]), "l": state.t,
                    }
                    dones[lo + a] = True
                self.states[j] = self._new_episode(j)
            obs[lo : lo + m] = self._encode(j)
        return obs, rewards * self.reward_scale, dones, infos

    def _step_batch(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        """:meth:`step_wait` on the batched engine (the same bookkeeping, as arrays)."""
        n = self.n_agents
        ended, r = self.batch.step(self._actions.reshape(self.n_kitchens, n),
                                   self.shaping_coef, self.team_reward)
        self._train_return += r
        for j, g in enumerate(self.batch.game_rewards().tolist()):
            self._game_return[j] += g
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        dones = np.repeat(ended, n)
        obs = self._batch_obs()
        kitchens = np.flatnonzero(ended).tolist()
        for j in kitchens:
            ep = self.batch.episode(j)
            rules = ep["rules"]
            self.finished.append({
                "kitchen": j, "preset": rules.preset,
                "rules": self.rule_labels.get(id(rules), rules.preset),
                "map": rules.layout.name, "seed": ep["seed"], "steps": ep["steps"],
                "game_reward": self._game_return[j],
                "train_return": float(self._train_return[j].mean()),
                "dishes": ep["dishes"], "shaping_coef": self.shaping_coef,
            })
            for a in range(n):
                infos[j * n + a]["terminal_observation"] = obs[j * n + a]
                infos[j * n + a]["episode"] = {"r": float(self._train_return[j, a]),
                                               "l": ep["steps"]}
        if kitchens:
            self._start_batch(kitchens)
            obs = self._batch_obs()
        rewards = r.reshape(-1).astype(np.float32)
        return obs, rewards * self.reward_scale, dones, infos

    def close(self) -> None:
        self.states = []
        if self.batch is not None:
            self.batch.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self, attr_name) for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> list[Any]:
        return [getattr(self, method_name)(*args, **kw) for _ in self._get_indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False for _ in self._get_indices(indices)]


__all__ = ["KitchenVecEnv"]

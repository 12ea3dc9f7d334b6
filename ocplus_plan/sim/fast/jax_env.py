"""The JAX kitchen behind JaxMARL's ``MultiAgentEnv`` interface (the ``jax`` extra; no
dependency on jaxmarl): ``agents``, ``observation_space(agent)``, ``action_space(agent)``,
``reset(key) -> (obs, state)`` and ``step(key, state, actions) -> (obs, state, rewards,
dones, infos)`` with auto-reset, observations and rewards as dicts keyed by agent name, so
JaxMARL's IPPO / MAPPO code runs on it as on its own envs::

    import jax, ocplus_plan
    env = ocplus_plan.make_jax_env("hard", obs_radius=2)
    keys = jax.random.split(jax.random.PRNGKey(0), 4096)
    obs, state = jax.vmap(env.reset)(keys)

Built by :func:`ocplus_plan.make_jax_env` from the Gymnasium env's keywords.
"""

from __future__ import annotations

from functools import partial
from typing import Any

from ...errors import ConfigError
from ..observe import VectorEncoder
from ..rules import Rules
from . import jax_kitchen as jk
from .jax_kitchen import jax, jnp
from .jax_observe import observe


class Discrete:
    """JaxMARL's ``Discrete`` space: integers ``0 .. n-1``."""

    def __init__(self, n: int) -> None:
        self.n, self.shape, self.dtype = n, (), jnp.int32

    def sample(self, key: Any) -> Any:
        return jax.random.randint(key, self.shape, 0, self.n).astype(self.dtype)

    def contains(self, x: Any) -> Any:
        return jnp.logical_and(x >= 0, x < self.n)


class Box:
    """JaxMARL's ``Box`` space: float32 arrays between ``low`` and ``high``."""

    def __init__(self, low: Any, high: Any, shape: tuple[int, ...]) -> None:
        self.low, self.high, self.shape, self.dtype = low, high, shape, jnp.float32

    def sample(self, key: Any) -> Any:
        return jax.random.uniform(key, self.shape, minval=self.low, maxval=self.high)

    def contains(self, x: Any) -> Any:
        return jnp.all((x >= self.low) & (x <= self.high))


class JaxKitchenEnv:
    """``n_agents`` cooks in one kitchen of ``rules``, as a JaxMARL ``MultiAgentEnv``.

    Observations: each cook's :class:`~ocplus_plan.sim.observe.VectorEncoder` vector
    (``obs_radius`` 0 = whole map). Actions: ``Discrete(5)`` per cook (0 right, 1 down,
    2 left, 3 up, 4 stay). Rewards: ``reward_scope="team"`` gives every cook the team's
    reward (the Gymnasium env's scalar), ``"per_agent"`` each cook its own. ``step``
    restarts a finished episode at once (the returned observation is the new episode's);
    ``infos`` holds per cook ``terminated``, ``truncated``, the cook's own reward and the
    dishes the episode has served (before any restart), and
    ``infos["shaped_reward"]``, keyed by cook like the rewards: the part of the reward paid
    for subtasks (a chop, a wash, a cooked steak; the rules' ``subtask_finished``), as
    JaxMARL's Overcooked reports its dense shaping, so JaxMARL's ``ippo_ff_overcooked``
    (which adds it, annealed, to the reward) runs unchanged. The rewards include that part
    unless ``sparse_reward=True``, which leaves it out of them (as JaxMARL's Overcooked
    does: then the shaping is only what the trainer adds back).
    """

    def __init__(self, rules: Rules, obs_radius: int = 0, reward_scope: str = "team",
                 checked: bool = False, sparse_reward: bool = False) -> None:
        if reward_scope not in ("team", "per_agent"):
            raise ConfigError(f"reward_scope must be 'team' or 'per_agent', got {reward_scope!r}")
        self.sparse_reward = bool(sparse_reward)
        self.rules = rules
        self.reward_scope = reward_scope
        self.obs_radius = obs_radius
        self.params = jk.kitchen_params(rules, obs_radius)
        self.num_agents = rules.n_agents
        self.agents = [f"agent_{i}" for i in range(self.num_agents)]
        self.name = f"ocplus_{rules.preset}_{rules.layout.name}"
        enc = VectorEncoder(rules, obs_radius)
        self.obs_size = enc.size
        space = Box(0.0, jnp.asarray(enc.high), (enc.size,))
        self.observation_spaces = {a: space for a in self.agents}
        self.action_spaces = {a: Discrete(5) for a in self.agents}
        self.checked = checked
        if checked:  # a debugging mode: every action is checked on the host first
            self.step = self._checked_step  # type: ignore[method-assign]
            self.step_env = self._checked_step_env  # type: ignore[method-assign]

    def _checked_step(self, key: Any, state: jk.KitchenState, actions: dict[str, Any],
                      reset_state: jk.KitchenState | None = None) -> tuple[Any, ...]:
        self._check(actions)
        return JaxKitchenEnv.step(self, key, state, actions, reset_state)

    def _checked_step_env(self, key: Any, state: jk.KitchenState,
                          actions: dict[str, Any]) -> tuple[Any, ...]:
        self._check(actions)
        return JaxKitchenEnv.step_env(self, key, state, actions)

    def _check(self, actions: dict[str, Any]) -> None:
        if not isinstance(actions, dict) or set(actions) != set(self.agents):
            raise ConfigError(f"actions are a dict keyed by {', '.join(self.agents)}")
        for agent in self.agents:
            try:
                jk.check_actions(actions[agent])
            except jk.InvalidActionError as exc:
                raise jk.InvalidActionError(f"{agent}: {exc}") from None

    @classmethod
    def from_options(cls, rules: Rules, *, mode: str = "vector", obs_radius: int = 0,
                     comm: Any = None, render_mode: str | None = None,
                     reward_scope: str = "team", checked: bool = False,
                     sparse_reward: bool = False) -> JaxKitchenEnv:
        """The env for the Gymnasium env's parsed options; refuses what it cannot do."""
        if mode != "vector":
            raise ConfigError(f"the JAX kitchen observes vectors only, got mode={mode!r}; "
                              "use mode='vector' (or the Gymnasium env for other modes)")
        if comm is not None:
            raise ConfigError("the JAX kitchen has no message channel: drop agent_communication "
                              "(or use the Gymnasium env, which has one)")
        if render_mode is not None:
            raise ConfigError(f"the JAX kitchen draws nothing (render_mode={render_mode!r}); "
                              "render a state with the Gymnasium env instead")
        return cls(rules, obs_radius, reward_scope, checked, sparse_reward)

    def observation_space(self, agent: str) -> Box:
        return self.observation_spaces[agent]

    def action_space(self, agent: str) -> Discrete:
        return self.action_spaces[agent]

    # ------------------------------------------------------------ the MultiAgentEnv API
    @partial(jax.jit, static_argnums=(0,))
    def reset(self, key: Any) -> tuple[dict[str, Any], jk.KitchenState]:
        state = jk.reset(key, self.params)
        return self.get_obs(state), state._replace(params=None)

    def get_obs(self, state: jk.KitchenState) -> dict[str, Any]:
        obs = observe(self.kitchen_state(state))
        return {a: obs[i] for i, a in enumerate(self.agents)}

    def kitchen_state(self, state: jk.KitchenState) -> jk.KitchenState:
        """The env's state with its :class:`~ocplus_plan.sim.fast.jax_kitchen.Params`
        attached (what :func:`jax_kitchen.step` takes). The env's own states carry none:
        the env holds them once, as constants of the compiled step, so XLA folds the rules
        this kitchen does not use and no kitchen copies the tables."""
        return state._replace(params=jax.tree_util.tree_map(jnp.asarray, self.params))

    @partial(jax.jit, static_argnums=(0,))
    def step(self, key: Any, state: jk.KitchenState, actions: dict[str, Any],
             reset_state: jk.KitchenState | None = None) -> tuple[Any, ...]:
        """One step; a finished episode restarts (from ``reset_state`` or a fresh reset
        with a key split from ``key``) and the observation is the new episode's first."""
        key, key_reset = jax.random.split(key)
        before = state
        out = self._advance(state, actions)
        done = out.terminated | out.truncated
        if reset_state is None:
            fresh = jk.reset(key_reset, self.params)._replace(params=None)
        else:
            fresh = reset_state._replace(params=None)
        state = jax.tree_util.tree_map(lambda r, s: jnp.where(done, r, s), fresh, out.state)
        return self.get_obs(state), state, *self._report(out, before, actions)

    def step_env(self, key: Any, state: jk.KitchenState, actions: dict[str, Any],
                 ) -> tuple[Any, ...]:
        """One step without the restart."""
        out = self._advance(state, actions)
        return self.get_obs(out.state), out.state, *self._report(out, state, actions)

    # ------------------------------------------------------------ internals
    def _advance(self, state: jk.KitchenState, actions: dict[str, Any],
                 rewards: Any = None) -> jk.StepOut:
        joint = jnp.stack([jnp.asarray(actions[a]).reshape(()) for a in self.agents])
        kitchen = self.kitchen_state(state)
        if rewards is not None:  # the same step paying other reward values
            kitchen = kitchen._replace(params=kitchen.params._replace(rewards=rewards))
        out = jk.step(None, kitchen, joint)
        return out._replace(state=out.state._replace(params=None))

    def _shaping(self, out: jk.StepOut, before: jk.KitchenState, actions: dict[str, Any]) -> Any:
        """Per cook, the subtask part of what :meth:`_report` pays. The team's is the
        subtasks done this step (chops, washes, cooked steaks: the stats) times their
        reward; a cook's own is the same step replayed paying only subtasks."""
        value = float(self.rules.rewards.subtask_finished)
        n = self.num_agents
        if self.reward_scope == "team":
            done = (out.state.stats - before.stats)[jnp.array([jk.S_CHOPS, jk.S_COOKS,
                                                               jk.S_WASHES])].sum()
            return jnp.full(n, value * done, jnp.float32)
        size = len(self.params.rewards)  # the values, then the dishes
        unit = jnp.zeros(size, jnp.float32).at[jk.R_SUBTASK].set(value)
        return self._advance(before, actions, unit).rewards

    def _report(self, out: jk.StepOut, before: jk.KitchenState, actions: dict[str, Any],
                ) -> tuple[dict, dict, dict]:
        n = self.num_agents
        own = out.rewards
        if self.reward_scope == "team":
            shared = self.rules.reward_mode == "shared"
            team = own[0] if shared else own.sum()
            paid = jnp.full(n, team)
        else:
            paid = own
        shaped = self._shaping(out, before, actions)
        if self.sparse_reward:
            paid = paid - shaped
        rewards = {a: paid[i] for i, a in enumerate(self.agents)}
        done = out.terminated | out.truncated
        dones = {a: done for a in self.agents} | {"__all__": done}
        infos = {"terminated": jnp.full(n, out.terminated), "truncated": jnp.full(n, out.truncated),
                 "own_reward": own, "dishes": jnp.full(n, out.state.stats[jk.S_DISHES]),
                 "shaped_reward": {a: shaped[i] for i, a in enumerate(self.agents)}}
        return rewards, dones, infos


__all__ = ["Box", "Discrete", "JaxKitchenEnv"]

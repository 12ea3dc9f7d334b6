"""The JAX kitchen behind JaxMARL's MultiAgentEnv interface (``ocplus_plan.make_jax_env``):
spaces, dict observations and rewards, auto-reset, the Gymnasium env's keywords, refusals,
and the extra named when jax is missing."""

from __future__ import annotations

import builtins
import sys

import numpy as np
import pytest

import ocplus_plan
from ocplus_plan.errors import ConfigError, DependencyNotInstalled

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")


def test_the_env_speaks_the_multiagentenv_interface():
    env = ocplus_plan.make_jax_env("hard", obs_radius=2)
    assert env.agents == ["agent_0", "agent_1"] and env.num_agents == 2
    assert env.action_space("agent_0").n == 5
    assert env.observation_space("agent_1").shape == (env.obs_size,)
    obs, state = jax.vmap(env.reset)(jax.random.split(jax.random.PRNGKey(0), 3))
    assert set(obs) == set(env.agents) and obs["agent_0"].shape == (3, env.obs_size)
    acts = {a: np.full(3, 4) for a in env.agents}
    obs2, state2, rew, dones, infos = jax.vmap(env.step)(
        jax.random.split(jax.random.PRNGKey(1), 3), state, acts)
    assert set(dones) == {*env.agents, "__all__"}
    assert rew["agent_0"].shape == (3,) and infos["own_reward"].shape == (3, 2)
    assert bool(env.observation_space("agent_0").contains(obs2["agent_0"][0]))
    assert np.asarray(state2.t).tolist() == [1, 1, 1]


def test_a_finished_episode_restarts_inside_step():
    env = ocplus_plan.make_jax_env("easy", horizon=3)
    _, state = env.reset(jax.random.PRNGKey(0))
    stay = {"agent_0": 4}
    for t in range(1, 3):
        _, state, _, dones, _ = env.step(jax.random.PRNGKey(t), state, stay)
        assert int(state.t) == t and not bool(dones["__all__"])
    obs, state, _, dones, infos = env.step(jax.random.PRNGKey(9), state, stay)
    assert bool(dones["__all__"]) and bool(infos["truncated"][0]) and int(state.t) == 0
    _, key_reset = jax.random.split(jax.random.PRNGKey(9))
    first, _ = env.reset(key_reset)
    np.testing.assert_array_equal(obs["agent_0"], first["agent_0"])


def test_team_and_per_agent_rewards():
    team = ocplus_plan.make_jax_env("easy", n_agents=2)
    own = ocplus_plan.make_jax_env("easy", n_agents=2, reward_scope="per_agent")
    acts = {"agent_0": 4, "agent_1": 4}
    for env, expect in ((team, -0.2), (own, -0.1)):
        _, state = env.reset(jax.random.PRNGKey(0))
        _, _, rew, _, _ = env.step(jax.random.PRNGKey(1), state, acts)
        assert float(rew["agent_1"]) == pytest.approx(expect)


def test_the_gymnasium_keywords_reach_the_rules():
    env = ocplus_plan.make_jax_env("medium", map_name="medium_ring", n_agent=2, horizon=50)
    assert env.rules.layout.name == "medium_ring" and env.rules.horizon == 50
    assert env.num_agents == 2


@pytest.mark.parametrize("kwargs, words", [
    (dict(mode="rgb"), "vectors only"),
    (dict(agent_communication=True), "message channel"),
    (dict(render_mode="rgb_array"), "draws nothing"),
    (dict(reward_scope="everyone"), "reward_scope"),
])
def test_what_the_jax_kitchen_cannot_do_is_refused(kwargs, words):
    with pytest.raises(ConfigError, match=words):
        ocplus_plan.make_jax_env("hard", **kwargs)


def test_without_jax_the_extra_is_named(monkeypatch):
    real_import = builtins.__import__

    def no_jax(name, *args, **kwargs):
        if name == "jax" or name.startswith("jax."):
            raise ImportError("no jax here")
        return real_import(name, *args, **kwargs)

    saved = {k: v for k, v in sys.modules.items() if k.startswith("ocplus_plan.sim.fast.jax_")}
    for k in saved:
        monkeypatch.delitem(sys.modules, k)
    monkeypatch.setattr(builtins, "__import__", no_jax)
    with pytest.raises(DependencyNotInstalled, match=r"ocplus-plan\[jax\]"):
        ocplus_plan.make_jax_env("hard")
    monkeypatch.undo()
    sys.modules.update(saved)


def test_infos_report_the_subtask_part_as_shaped_reward_keyed_by_cook():
    from ocplus_plan.agents import make_controller
    from ocplus_plan.sim import make_rules, new_state, transition

    rules = make_rules("easy", n_agents=2, horizon=60)
    state, greedy = new_state(rules, 0), make_controller("greedy", 0)
    greedy.reset(state)
    joint = []
    while not state.done:  # the greedy cook's actions, played on the reference simulator
        acts = greedy.act(state)
        greedy.observe(state, transition(state, acts).events)
        joint.append(acts)
    from ocplus_plan.sim.fast import jax_kitchen as jk

    team = ocplus_plan.make_jax_env("easy", n_agents=2, horizon=60)
    own = ocplus_plan.make_jax_env("easy", n_agents=2, horizon=60, reward_scope="per_agent",
                                   sparse_reward=True)
    totals = {}
    for name, env in (("team", team), ("own", own)):
        _, s = env.reset(jax.random.PRNGKey(0))
        shaped = paid = full = 0.0
        for t, acts in enumerate(joint[:-1]):  # the last step restarts the episode
            _, s, rew, _, infos = env.step(jax.random.PRNGKey(t), s,
                                           {"agent_0": acts[0], "agent_1": acts[1]})
            assert set(infos["shaped_reward"]) == set(env.agents)
            shaped += sum(float(infos["shaped_reward"][a]) for a in env.agents)
            paid += sum(float(rew[a]) for a in env.agents)
            full += float(np.asarray(infos["own_reward"]).sum())
        subtasks = int(sum(s.stats[k] for k in (jk.S_CHOPS, jk.S_COOKS, jk.S_WASHES)))
        totals[name] = (shaped, paid, full, subtasks)
    value = rules.rewards.subtask_finished
    subtasks = totals["team"][3]
    assert subtasks > 0 and totals["own"][3] == subtasks
    assert totals["team"][0] == pytest.approx(2 * value * subtasks)  # each cook gets the team's
    assert totals["own"][0] == pytest.approx(value * subtasks)
    assert totals["own"][1] == pytest.approx(totals["own"][2] - totals["own"][0])  # sparse

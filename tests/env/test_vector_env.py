"""``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`` gives the batched
vector env, and each of its kitchens is the single env's kitchen step for step."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, VectorEnv

import ocplus_plan.env  # noqa: F401  (registers the ids)
from ocplus_plan.env.vector_env import OvercookedPlusVectorEnv
from ocplus_plan.errors import ConfigError

KW = dict(preset="hard", n_agents=2, horizon=12, obs_radius=2, compiled=False)


def _singles(venv: OvercookedPlusVectorEnv, **kw) -> list[gym.Env]:
    """One single env per kitchen, started on the kitchen's episode seed."""
    envs = []
    for e in range(venv.num_envs):
        env = gym.make("OvercookedPlus-v0", **kw).unwrapped
        env.reset(seed=venv.sim.seeds[e])
        envs.append(env)
    return envs


def test_make_vec_returns_the_batched_vector_env_with_batched_spaces():
    venv = gym.make_vec("OvercookedPlus-v0", num_envs=3, vectorization_mode="vector_entry_point",
                        preset="hard", n_agents=2, compiled=False)
    assert isinstance(venv, OvercookedPlusVectorEnv) and isinstance(venv, VectorEnv)
    obs, info = venv.reset(seed=0)
    assert obs in venv.observation_space and info == {}
    assert venv.single_action_space == gym.spaces.MultiDiscrete([5, 5])
    obs, rewards, terminated, truncated, _ = venv.step(venv.action_space.sample())
    assert obs in venv.observation_space and rewards.shape == terminated.shape == (3,)


def test_each_kitchen_steps_like_the_single_env_and_restarts_on_the_next_step():
    venv = OvercookedPlusVectorEnv(3, **KW)
    obs, _ = venv.reset(seed=5)
    kw = {k: v for k, v in KW.items() if k != "compiled"}
    singles = _singles(venv, **kw)
    rng = np.random.default_rng(0)
    restarted = 0
    for _ in range(30):
        acts = rng.integers(0, 5, size=(3, 2))
        ended = venv._needs_reset.copy()
        obs, rewards, terminated, truncated, _ = venv.step(acts)
        for e, env in enumerate(singles):
            if ended[e]:  # NEXT_STEP: this step reset the kitchen and ignored its action
                env.reset(seed=venv.sim.seeds[e])
                single_obs, reward, te, tr = env._obs(), 0.0, False, False
                restarted += 1
            else:
                single_obs, reward, te, tr, _ = env.step(acts[e])
            assert (rewards[e], terminated[e], truncated[e]) == (reward, te, tr)
            for a in range(2):
                np.testing.assert_array_equal(obs[a][e], single_obs[a])
    assert restarted == 6


def test_same_step_autoreset_reports_the_final_observation():
    venv = OvercookedPlusVectorEnv(2, autoreset_mode=AutoresetMode.SAME_STEP, **KW)
    venv.reset(seed=1)
    for _ in range(11):
        _, _, _, truncated, info = venv.step(np.full((2, 2), 4))
        assert not truncated.any() and info == {}
    last = tuple(o.copy() for o in venv.sim.obs.transpose(1, 0, 2))
    obs, _, _, truncated, info = venv.step(np.full((2, 2), 4))
    assert truncated.all() and info["_final_obs"].all()
    assert [venv.sim.state(e).t for e in range(2)] == [0, 0]  # already restarted
    for e in range(2):
        assert len(info["final_obs"][e]) == 2 and info["final_obs"][e][0].shape == last[0][e].shape


def test_copy_false_returns_live_views_and_copy_true_fresh_arrays():
    live = OvercookedPlusVectorEnv(2, copy=False, **KW)
    fresh = OvercookedPlusVectorEnv(2, **KW)
    obs_live, _ = live.reset(seed=0)
    obs_fresh, _ = fresh.reset(seed=0)
    assert np.shares_memory(obs_live[0], live.sim.obs)
    assert not np.shares_memory(obs_fresh[0], fresh.sim.obs)


@pytest.mark.parametrize("bad", [dict(mode="rgb"), dict(agent_communication=True),
                                 dict(reward_scope="mine")])
def test_unbatchable_options_are_refused_with_the_alternative(bad):
    with pytest.raises(ConfigError, match="sync|reward_scope"):
        OvercookedPlusVectorEnv(2, preset="hard", compiled=False, **bad)

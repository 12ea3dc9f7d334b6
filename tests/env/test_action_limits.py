"""The Gymnasium envs refuse actions that are not whole numbers, and sizes past their
limits, with the package's own errors (never a MemoryError, never a silent truncation)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import ocplus_plan  # noqa: F401 - registers the ids
from ocplus_plan.env.core import MAX_OBS_RADIUS, whole_numbers
from ocplus_plan.env.vector_env import MAX_NUM_ENVS
from ocplus_plan.errors import ConfigError, InvalidActionError


@pytest.fixture
def env():
    e = gym.make("OvercookedPlus-v0", preset="easy", n_agents=1)
    e.reset(seed=0)
    yield e
    e.close()


@pytest.mark.parametrize("action, shown", [
    ([1.7], "1.7"), (1.7, "1.7"), (np.array([1.7]), "1.7"), ([float("nan")], "nan"),
    ([float("inf")], "inf"), ([2**40], str(2**40)), ([True], "True"), (["a"], "'a'"),
])
def test_a_bad_action_is_refused_naming_it(env, action, shown):
    with pytest.raises(InvalidActionError) as info:
        env.step(action)
    assert shown in str(info.value) and "-9223372036854775808" not in str(info.value)


def test_whole_floats_and_integers_still_act(env):
    env.step([2.0])
    env.step(np.array([3], np.int32))
    env.step([4])
    assert whole_numbers(np.array([[1.0, 2.0]])).tolist() == [1, 2]


def test_the_single_cook_env_refuses_a_float():
    e = gym.make("OvercookedPlusSingle-v0", preset="easy", n_agents=2) \
        if "OvercookedPlusSingle-v0" in gym.registry else None
    if e is None:
        pytest.skip("no single-cook env registered")
    e.reset(seed=0)
    with pytest.raises(InvalidActionError, match="1.7"):
        e.step(1.7)


def test_obs_radius_and_num_envs_are_bounded_before_allocating():
    with pytest.raises(ConfigError, match=f"to {MAX_OBS_RADIUS}"):
        gym.make("OvercookedPlus-v0", obs_radius=10**6)
    with pytest.raises(ConfigError, match=f"1 to {MAX_NUM_ENVS}"):
        gym.make_vec("OvercookedPlus-v0", num_envs=10**7,
                     vectorization_mode="vector_entry_point")


def test_the_vector_env_refuses_a_float_action():
    v = gym.make_vec("OvercookedPlus-v0", num_envs=2, preset="easy", n_agents=1,
                     vectorization_mode="vector_entry_point")
    v.reset(seed=0)
    with pytest.raises(InvalidActionError, match="1.7"):
        v.step(np.array([[1.7], [1.0]]))
    v.step(np.array([[1], [0]]))
    v.close()

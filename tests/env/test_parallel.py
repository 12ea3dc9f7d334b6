"""The PettingZoo ParallelEnv view (skipped without pettingzoo)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pettingzoo", reason="pettingzoo not installed (pip install 'ocplus-plan[test]')")

from pettingzoo.test import parallel_api_test

import ocplus_plan.env as ocenv
from ocplus_plan.errors import InvalidActionError


@pytest.mark.parametrize("mode", ["vector", "rgb", "symbolic", "text"])
@pytest.mark.parametrize("comm", [False, True], ids=["nocomm", "comm"])
def test_parallel_api_test_passes(mode, comm):
    kw = {"agent_communication": True, "comm_failure_rate": 0.25} if comm else {}
    parallel_api_test(ocenv.parallel_env("hard", mode=mode, horizon=40, **kw), num_cycles=60)


def test_parallel_env_matches_the_gym_env_step_for_step():
    par = ocenv.parallel_env("hard", n_agents=2, agent_communication=True, comm_failure_rate=0.3)
    gym_env = ocenv.OvercookedPlusEnv("hard", n_agents=2, agent_communication=True,
                                      comm_failure_rate=0.3)
    obs_p, _ = par.reset(seed=5)
    obs_g, _ = gym_env.reset(seed=5)
    rng = np.random.default_rng(0)
    for _ in range(120):
        np.testing.assert_array_equal(obs_p["cook_0"], obs_g[0])
        np.testing.assert_array_equal(obs_p["cook_1"], obs_g[1])
        act = rng.integers(0, [5, 8, 5, 8])
        obs_p, rew_p, _, trunc_p, _ = par.step({"cook_0": act[:2], "cook_1": act[2:]})
        obs_g, _, _, trunc_g, info = gym_env.step(act)
        assert [rew_p["cook_0"], rew_p["cook_1"]] == info["rewards"]
        assert trunc_p["cook_0"] == trunc_g


def test_episode_end_removes_agents_and_bad_input_is_refused():
    par = ocenv.parallel_env("easy", n_agents=2, horizon=3)
    par.reset(seed=0)
    with pytest.raises(InvalidActionError, match="unknown"):
        par.step({"cook_9": 0})
    for _ in range(3):
        _, _, _, trunc, _ = par.step({a: 4 for a in par.agents})
    assert all(trunc.values()) and par.agents == []
    with pytest.raises(InvalidActionError, match="reset"):
        par.step({})

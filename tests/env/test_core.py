"""KitchenCore: the env's incrementally encoded vector observations equal the
from-scratch encoding of the same state and received tokens, through episodes, resets
and messages (hypothesis)."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocplus_plan.env.gym_env import OvercookedPlusEnv

SETUPS = [
    {"preset": "hard", "n_agents": 1},
    {"preset": "hard", "n_agents": 2},
    {"preset": "hard", "map": "trio_kitchen", "n_agents": 3},
    {"preset": "easy", "map": "corridor3", "n_agents": 3},
]


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(setup=st.sampled_from(SETUPS), radius=st.sampled_from([0, 1, 3, 25]),
       comm=st.booleans(), seed=st.integers(0, 2**31 - 1),
       resets=st.lists(st.integers(1, 80), min_size=1, max_size=4))
def test_env_observations_equal_the_from_scratch_encoding(setup, radius, comm, seed, resets):
    kw = dict(setup, obs_radius=radius, horizon=60, map_switch_step=6)
    if setup["preset"] != "hard":
        kw.pop("map_switch_step")
    comm = comm and setup["n_agents"] > 1
    if comm:
        kw.update(agent_communication=True, comm_vocab=3, comm_failure_rate=0.3, comm_range=3)
    env = OvercookedPlusEnv(kw.pop("preset"), **kw)
    core = env.core
    rng = np.random.default_rng(seed)
    obs, _ = env.reset(seed=seed)
    for length in resets:  # episodes cut short by reset(), or ended by the horizon
        for _ in range(length):
            want = core.vector.encode(core.state, core.received if comm else None)
            assert np.array_equal(np.stack(obs), want)
            action = rng.integers(0, 5, size=env.action_space.shape)
            if comm:
                action = np.stack([rng.integers(0, 5, core.n_agents),
                                   rng.integers(0, 3, core.n_agents)], axis=1).reshape(-1)
            obs, _, terminated, truncated, _ = env.step(action)
            if terminated or truncated:
                break
        want = core.vector.encode(core.state, core.received if comm else None)
        assert np.array_equal(np.stack(obs), want)
        obs, _ = env.reset()

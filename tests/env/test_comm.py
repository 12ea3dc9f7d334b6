"""Communication (SPEC section 9): drop rate and range statistics over 10,000 messages,
delay, determinism, and independence from the simulator's own random stream."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ocplus_plan.env.comm import CommChannel, CommConfig
from ocplus_plan.env.gym_env import OvercookedPlusEnv
from ocplus_plan.errors import ConfigError

COLS = 20
Z = 4.0  # a 4-sigma band: a correct channel fails it about once in 16,000 runs


def band(n: int, p: float) -> tuple[float, float]:
    sd = math.sqrt(n * p * (1 - p))
    return n * p - Z * sd, n * p + Z * sd


def test_drop_rate_is_within_the_binomial_band_over_10000_messages():
    p_fail = 0.3
    ch = CommChannel(CommConfig(vocab=4, failure_rate=p_fail), n_agents=2, cols=COLS)
    ch.reset(7)
    delivered = 0
    for step in range(5000):  # 2 copies per step
        got = ch.exchange([step % 4, (step + 1) % 4], [0, 1])
        delivered += int((got >= 0).sum())
        assert ((got == -1) | (got == np.array([[(step + 1) % 4], [step % 4]]))).all()
    assert ch.sent == 10_000
    lo, hi = band(10_000, 1 - p_fail)
    assert lo <= delivered <= hi


def test_range_is_exact_and_drops_apply_inside_it():
    rng = np.random.default_rng(1)
    cfg = CommConfig(vocab=2, range=3, failure_rate=0.2)
    ch = CommChannel(cfg, n_agents=3, cols=COLS)
    ch.reset(3)
    in_range = delivered = 0
    for _ in range(10_000 // 6):  # 6 copies per step
        pos = rng.integers(0, 10, size=(3, 2))
        flat = [int(r * COLS + c) for r, c in pos]
        got = ch.exchange([1, 1, 1], flat)
        for a in range(3):
            for k in range(2):
                b = (a + k + 1) % 3
                near = np.abs(pos[a] - pos[b]).max() <= 3
                in_range += near
                if not near:
                    assert got[a, k] == -1  # never heard out of range
                delivered += got[a, k] >= 0
    lo, hi = band(in_range, 0.8)
    assert lo <= delivered <= hi


def test_delay_and_reset():
    ch = CommChannel(CommConfig(vocab=5, delay=3), n_agents=2, cols=COLS)
    assert (ch.reset(0) == -1).all()
    seen = [ch.exchange([t % 5, 4], [0, 1])[:, 0].tolist() for t in range(5)]
    assert seen == [[-1, -1], [-1, -1], [4, 0], [4, 1], [4, 2]]


def test_same_seed_same_drops_and_other_seed_differs():
    def run(seed):
        ch = CommChannel(CommConfig(vocab=3, failure_rate=0.5), n_agents=3, cols=COLS)
        ch.reset(seed)
        return [ch.exchange([0, 1, 2], [0, 1, 2]).tolist() for _ in range(50)]

    assert run(4) == run(4) and run(4) != run(5)


def test_communication_leaves_the_simulator_stream_alone():
    """Same seed and moves: the same kitchen with and without the (lossy) channel."""
    quiet = OvercookedPlusEnv("hard", n_agents=2, mode="symbolic")
    talky = OvercookedPlusEnv("hard", n_agents=2, mode="symbolic", agent_communication=True,
                              comm_failure_rate=0.5)
    quiet.reset(seed=9)
    talky.reset(seed=9)
    rng = np.random.default_rng(0)
    for _ in range(200):
        moves = rng.integers(0, 5, size=2)
        quiet.step(moves)
        talky.step([moves[0], 1, moves[1], 2])
        assert quiet.state.state_hash() == talky.state.state_hash()


def test_received_tokens_appear_in_the_next_observation():
    env = OvercookedPlusEnv("hard", n_agents=2, agent_communication=True, comm_vocab=6)
    obs, _ = env.reset(seed=0)
    names = env.core.vector.feature_names
    start = env.core.vector.grid_size
    feats = dict(zip(names, obs[0][start:]))
    assert feats["msg1:none"] == 1
    obs, *_ = env.step([4, 2, 4, 5])
    f0 = dict(zip(names, obs[0][start:]))
    f1 = dict(zip(names, obs[1][start:]))
    assert f0["msg1:token5"] == 1 and f0["msg1:none"] == 0  # agent 0 heard agent 1's 5
    assert f1["msg1:token2"] == 1


@pytest.mark.parametrize("kw", [{"vocab": 0}, {"range": -1}, {"failure_rate": 1.5},
                                {"delay": 0}, {"failure_rate": "x"}])
def test_bad_parameters_are_config_errors(kw):
    with pytest.raises(ConfigError, match="comm_"):
        CommConfig(**kw)


def test_communication_needs_two_agents():
    with pytest.raises(ConfigError, match="two agents"):
        OvercookedPlusEnv("easy", n_agents=1, agent_communication=True)


def test_rgb_and_symbolic_observations_carry_the_received_tokens():
    for mode in ("rgb", "symbolic"):
        env = OvercookedPlusEnv("hard", n_agents=3, mode=mode, agent_communication=True,
                                comm_vocab=4)
        obs, _ = env.reset(seed=0)
        assert obs[0]["messages"].tolist() == [4, 4]  # 4 = nothing received
        obs, *_ = env.step([4, 1, 4, 2, 4, 3])
        assert obs[0]["messages"].tolist() == [2, 3]  # from cooks 1 and 2
        assert obs[2]["messages"].tolist() == [1, 2]  # from cooks 0 and 1
        assert obs[1] in env.observation_space[1]

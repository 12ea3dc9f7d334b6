"""``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`` gives the batched
vector env, and each of its kitchens is the single env's kitchen step for step."""

from __future__ import annotations

import pickle
import tracemalloc

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

import ocplus_plan.env  # noqa: F401  (registers the ids)
from ocplus_plan.env.vector_env import BatchedBox, OvercookedPlusVectorEnv, batch_tuple_of_boxes
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


def test_observations_are_read_only_views_of_the_live_buffer_by_default():
    venv = OvercookedPlusVectorEnv(2, **KW)
    obs, _ = venv.reset(seed=0)
    assert all(np.shares_memory(o, venv.sim.obs) and not o.flags.writeable for o in obs)
    kept = obs[0].copy()
    obs_next, *_ = venv.step(np.zeros((2, 2), np.int64))  # time advances: the buffer changes
    assert np.shares_memory(obs_next[0], obs[0])
    assert np.array_equal(obs[0], obs_next[0]) and not np.array_equal(obs[0], kept)


def test_copy_true_returns_fresh_arrays_that_survive_the_next_step():
    venv = OvercookedPlusVectorEnv(2, copy=True, **KW)
    obs, _ = venv.reset(seed=0)
    kept = obs[0].copy()
    assert not np.shares_memory(obs[0], venv.sim.obs) and obs[0].flags.writeable
    obs_next, *_ = venv.step(np.zeros((2, 2), np.int64))
    assert not np.shares_memory(obs_next[0], obs[0])
    assert np.array_equal(obs[0], kept) and not np.array_equal(obs_next[0], kept)


def test_copy_true_and_false_give_the_same_values():
    live, fresh = OvercookedPlusVectorEnv(3, **KW), OvercookedPlusVectorEnv(3, copy=True, **KW)
    pairs = [(live.reset(seed=4)[0], fresh.reset(seed=4)[0])]
    rng = np.random.default_rng(1)
    for _ in range(15):
        acts = rng.integers(0, 5, size=(3, 2))
        a, b = live.step(acts), fresh.step(acts)
        for x, y in zip(a[1:4], b[1:4]):
            np.testing.assert_array_equal(x, y)
        pairs.append((a[0], b[0]))
        for o_live, o_fresh in zip(*pairs[-1]):
            np.testing.assert_array_equal(o_live, o_fresh)


@pytest.mark.parametrize("bad", [dict(mode="rgb"), dict(agent_communication=True),
                                 dict(reward_scope="mine")])
def test_unbatchable_options_are_refused_with_the_alternative(bad):
    with pytest.raises(ConfigError, match="sync|reward_scope"):
        OvercookedPlusVectorEnv(2, preset="hard", compiled=False, **bad)


def _space_bytes(n: int) -> int:
    """Bytes allocated while building the batched observation space of ``n`` kitchens."""
    single = OvercookedPlusVectorEnv(1, **KW).single_observation_space
    single.seed(0)
    tracemalloc.start()
    try:
        space = batch_tuple_of_boxes(single, n)
        held = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    assert [box.shape for box in space] == [(n, single[0].shape[0])] * 2
    return held


def test_the_batched_observation_space_holds_one_kitchens_bounds():
    assert _space_bytes(4096) - _space_bytes(1) < 4096  # under a byte per kitchen
    venv = OvercookedPlusVectorEnv(4096, **KW)
    for box in venv.observation_space:
        assert isinstance(box, BatchedBox) and box.shape == (4096, box.single.shape[0])
        assert np.shares_memory(box.low, box.single.low) and box.low.strides[0] == 0


def test_the_batched_box_is_gymnasiums_batched_box_for_its_users():
    venv = OvercookedPlusVectorEnv(5, **KW)
    single = venv.single_observation_space
    reference = batch_space(single, 5)
    ours = batch_tuple_of_boxes(single, 5)
    assert ours == reference and reference == ours
    ours.seed(3)
    reference.seed(3)
    for x, y in zip(ours.sample(), reference.sample()):
        assert x.dtype == y.dtype == np.float32 and x.shape == y.shape == (5, single[0].shape[0])
        np.testing.assert_array_equal(x, y)
    obs, _ = venv.reset(seed=0)
    assert ours.contains(obs) and reference.contains(obs)
    bad = (obs[0].copy(), obs[1].copy())
    bad[1][2, 0] = -1.0  # below a bound, in one kitchen
    assert not ours.contains(bad) and not reference.contains(bad)
    assert not ours.contains((obs[0][:4], obs[1][:4]))  # the wrong number of kitchens


def test_the_batched_box_pickles_without_repeating_its_bounds():
    box = OvercookedPlusVectorEnv(1000, **KW).observation_space[0]
    box.seed(1)
    data = pickle.dumps(box)
    assert len(data) < 4 * box.single.low.nbytes + 4096  # not 1000 kitchens' bounds
    back = pickle.loads(data)
    assert back == box and back.low.strides[0] == 0
    np.testing.assert_array_equal(back.sample(), box.sample())
    with pytest.raises(ConfigError, match="positive number"):
        BatchedBox(box.single, 0)


# ---------------------------------------------------------------- Gymnasium conventions

def test_an_int_seed_starts_kitchen_e_like_a_sync_vector_env_seeded_seed_plus_e():
    kw = dict(preset="hard", n_agents=2, horizon=5, obs_radius=2)
    venv = OvercookedPlusVectorEnv(3, compiled=False, **kw)
    sync = gym.make_vec("OvercookedPlus-v0", num_envs=3, vectorization_mode="sync", **kw)
    obs, _ = venv.reset(seed=7)
    ref, _ = sync.reset(seed=7)
    assert venv.sim.seeds == [7, 8, 9]
    rng = np.random.default_rng(2)
    for _ in range(13):  # two autoresets: later episodes draw seeds as each env would
        for a in range(2):
            np.testing.assert_array_equal(obs[a], ref[a])
        acts = rng.integers(0, 5, size=(3, 2))
        obs, r, te, tr, _ = venv.step(acts)
        ref, r2, te2, tr2, _ = sync.step(acts)
        np.testing.assert_array_equal(r, r2)
        np.testing.assert_array_equal(te | tr, te2 | tr2)


def test_a_list_of_seeds_gives_one_seed_per_kitchen():
    venv = OvercookedPlusVectorEnv(3, **KW)
    venv.reset(seed=[4, 40, None])
    assert venv.sim.seeds[:2] == [4, 40] and isinstance(venv.sim.seeds[2], int)


@pytest.mark.parametrize("seed", [[1, 2], [1, "x", 3], -1, 1.5, [True, 1, 2]])
def test_a_bad_seed_is_refused_with_the_packages_message(seed):
    venv = OvercookedPlusVectorEnv(3, **KW)
    with pytest.raises(ConfigError, match="one per kitchen"):
        venv.reset(seed=seed)


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_finished_episodes_report_dishes_orders_and_burns_in_info(mode):
    venv = OvercookedPlusVectorEnv(2, autoreset_mode=mode, **KW)
    venv.reset(seed=3)
    rng = np.random.default_rng(0)
    total = np.zeros(2)
    for t in range(12):
        _, r, te, tr, info = venv.step(rng.integers(0, 5, size=(2, 2)))
        total += r
        if t < 11:
            assert "episode" not in info and "final_info" not in info
    stats = info["final_info"] if mode == AutoresetMode.SAME_STEP else info
    assert mode == AutoresetMode.NEXT_STEP or info["_final_info"].all()
    ep = stats["episode"]
    assert stats["_episode"].all() and ep["_dishes"].all()
    np.testing.assert_array_equal(ep["l"], [12, 12])
    np.testing.assert_allclose(ep["r"], total)
    for key in ("dishes", "orders", "expired", "burns"):
        assert ep[key].shape == (2,) and ep[key].dtype == np.int64 and (ep[key] >= 0).all()
    if mode == AutoresetMode.NEXT_STEP:  # the ended kitchens are not restarted yet
        for e in range(2):
            s = venv.sim.state(e).stats
            assert (ep["dishes"][e], ep["orders"][e], ep["expired"][e], ep["burns"][e]) == (
                s["dishes_served"], s["orders_completed"], s["orders_expired"], s["burns"])
    next_info = venv.step(np.zeros((2, 2), int))[4]
    assert "episode" not in next_info

"""The jitted JAX PPO: one whole training call runs, changes the weights, reports a finite
reward per update, and its weights save as a plain .npz whose MLP numpy can run."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

import ocplus_plan  # noqa: E402
from ocplus_plan.rl.fast.jax_ppo import (  # noqa: E402
    PPOConfig,
    agent_steps,
    forward,
    init_params,
    make_train,
    save_npz,
)


def test_a_tiny_training_run_updates_the_shared_policy_and_saves_it(tmp_path: Path):
    env = ocplus_plan.make_jax_env("easy", n_agents=2, obs_radius=1, horizon=6)
    config = PPOConfig(n_envs=2, n_steps=4, n_updates=2, n_epochs=1, n_minibatches=2,
                       hidden=8)
    params, rewards = jax.jit(make_train(env, config))(jax.random.PRNGKey(0))
    start = init_params(jax.random.split(jax.random.PRNGKey(0), 3)[0], env.obs_size + 2, 8)
    assert rewards.shape == (2,) and np.isfinite(np.asarray(rewards)).all()
    assert not np.allclose(np.asarray(params["w0"]), np.asarray(start["w0"]))
    assert agent_steps(config, 2) == 2 * 4 * 2 * 2
    save_npz(str(tmp_path / "policy.npz"), params)
    saved = dict(np.load(tmp_path / "policy.npz"))
    x = np.zeros((3, env.obs_size + 2), np.float32)
    h = np.tanh(np.tanh(x @ saved["w0"] + saved["b0"]) @ saved["w1"] + saved["b1"])
    logits, value = forward(params, x)
    np.testing.assert_allclose((h @ saved["w2"] + saved["b2"])[:, :-1], logits, rtol=1e-4,
                               atol=1e-5)


def test_ocplus_train_engine_jax_writes_the_policy_and_summary(tmp_path: Path, capsys):
    from ocplus_plan.cli import main

    code = main(["train", "--engine", "jax", "--preset", "easy", "--steps", "32",
                 "--n-kitchens", "2", "--n-steps", "4", "--n-epochs", "1", "--hidden", "8,8",
                 "--obs-radius", "1", "--out", str(tmp_path), "--quiet"])
    assert code == 0
    summary = json.loads((tmp_path / "train.json").read_text())
    assert summary["engine"] == "jax" and summary["timesteps"] == 32
    assert set(np.load(tmp_path / "policy.npz")) == {"w0", "b0", "w1", "b1", "w2", "b2"}
    assert "policy.npz" in capsys.readouterr().out


def test_a_jax_policy_plays_in_eval_on_the_cpu_with_numpy(tmp_path: Path, capsys):
    from ocplus_plan.agents import make_controller, run_episode
    from ocplus_plan.cli import main
    from ocplus_plan.rl.npz_policy import NpzInputs, NpzPolicy
    from ocplus_plan.sim import make_rules, new_state

    assert main(["train", "--engine", "jax", "--preset", "easy", "--timesteps", "32",
                 "--n-kitchens", "2", "--n-steps", "4", "--n-epochs", "1", "--hidden", "8,8",
                 "--obs-radius", "1", "--out", str(tmp_path / "run"), "--quiet"]) == 0
    policy = tmp_path / "run" / "policy.npz"
    loaded = NpzPolicy(policy)
    rules = make_rules("easy", n_agents=loaded.meta["n_agents"])
    state = new_state(rules, 0)
    inputs = NpzInputs(rules, loaded.meta).encode_all(state)
    saved = dict(np.load(policy))
    logits, _ = forward({k: jax.numpy.asarray(v) for k, v in saved.items()}, inputs)
    expected = np.asarray(jax.nn.softmax(logits, -1))
    np.testing.assert_allclose(loaded.probs(inputs), expected, rtol=1e-4, atol=1e-5)
    cook = make_controller(f"ppo:{policy}", 0)
    summary = run_episode(new_state(rules, 3), cook, steps=30)
    assert summary["t"] == 30
    out = tmp_path / "eval"
    assert main(["eval", "--preset", "easy", "--n-agents", str(rules.n_agents), "--agents",
                 f"ppo:{policy}@greedy", "--seeds", "1", "--horizon", "20", "--out", str(out),
                 "--quiet", "--json"]) == 0
    assert '"errors": 0' in capsys.readouterr().out


def test_a_jax_policy_refuses_a_kitchen_of_another_shape(tmp_path: Path):
    from ocplus_plan.errors import ConfigError
    from ocplus_plan.rl.npz_policy import NpzInputs

    meta = {"obs_radius": 0, "obs_size": 7, "n_agents": 1, "map": "x"}
    from ocplus_plan.sim import make_rules
    with pytest.raises(ConfigError, match="size 7"):
        NpzInputs(make_rules("easy", n_agents=1), meta)


def test_the_jax_trainer_prints_progress_and_writes_periodic_checkpoints(tmp_path: Path, capsys):
    from ocplus_plan.cli import main
    from ocplus_plan.rl.npz_policy import NpzPolicy

    code = main(["train", "--engine", "jax", "--preset", "easy", "--steps", "24",
                 "--n-kitchens", "2", "--n-steps", "4", "--n-epochs", "1", "--hidden", "8,8",
                 "--obs-radius", "1", "--out", str(tmp_path)])
    assert code == 0
    lines = [x for x in capsys.readouterr().err.splitlines() if x.startswith("update ")]
    assert [x.split()[1] for x in lines] == ["1/3", "2/3", "3/3"]
    assert "steps/s" in lines[0] and "dishes/episode" in lines[0]
    saved = sorted(p.name for p in (tmp_path / "checkpoints").glob("update_*.npz"))
    assert saved == ["update_000001.npz", "update_000002.npz", "update_000003.npz"]
    assert NpzPolicy(tmp_path / "checkpoints" / saved[0]).meta["n_agents"] == 1
    summary = json.loads((tmp_path / "train.json").read_text())
    assert len(summary["dishes_per_episode_by_update"]) == 3

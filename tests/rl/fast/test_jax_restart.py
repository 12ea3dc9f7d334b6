"""The JAX trainer starts a learner again when it has served no order in
``PPOConfig.restart_after`` of the run (since it started or since its last order): fresh
weights from a new key, fresh Adam, its own learning-rate decay over the updates left; a
learner that keeps serving is kept."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

import ocplus_plan  # noqa: E402
from ocplus_plan.rl.fast.jax_ppo import (  # noqa: E402
    PPOConfig,
    _learning_rate,
    init_params,
    should_restart,
    train_to_folder,
)

TINY = PPOConfig(n_envs=2, n_steps=4, n_updates=4, n_epochs=1, n_minibatches=2, hidden=8)


def test_only_a_learner_idle_for_its_span_is_started_again():
    config = PPOConfig(n_updates=100, restart_after=0.2)
    assert not bool(should_restart(config, 19, 0))  # its span is not over yet
    assert bool(should_restart(config, 20, 0))  # nothing served since update 0
    assert not bool(should_restart(config, 20, 11))  # it served an order in update 10
    assert not bool(should_restart(config, 30, 11))
    assert bool(should_restart(config, 31, 11))  # and none since: idle for 20 updates
    assert not bool(should_restart(config._replace(restart_after=0.0), 99, 0))


def test_a_started_again_learner_decays_its_learning_rate_over_the_updates_left():
    config = PPOConfig(n_updates=100, n_epochs=2, n_minibatches=4, lr=1e-3, lr_final=0.1)
    assert float(_learning_rate(config, 0, 60)) == pytest.approx(1e-3)
    assert float(_learning_rate(config, 40 * 8, 60)) == pytest.approx(1e-4)
    assert float(_learning_rate(config, 20 * 8, 60)) == pytest.approx(5.5e-4)
    assert float(_learning_rate(config, 50 * 8)) == pytest.approx(5.5e-4)  # never restarted


def test_the_restarted_learner_has_fresh_weights_from_a_new_key(tmp_path: Path, capsys):
    from ocplus_plan.cli import main

    env = ocplus_plan.make_jax_env("easy", n_agents=1, obs_radius=1, horizon=6)
    # lr 0: no update moves the weights, so what is saved is the last learner's start
    summary = train_to_folder(env, TINY._replace(lr=0.0, restart_after=0.5),
                              str(tmp_path / "a"), chunk=4)
    assert (summary["restarts"], summary["learner_start_update"]) == (1, 2)  # update 2 of 4
    assert json.loads((tmp_path / "a" / "train.json").read_text())["restarts"] == 1
    k_init = jax.random.split(jax.random.PRNGKey(0), 4)[0]
    fresh = init_params(jax.random.fold_in(k_init, 1), env.obs_size + 1, 8)
    first = init_params(k_init, env.obs_size + 1, 8)
    saved = np.load(tmp_path / "a" / "policy.npz")
    for name, value in fresh.items():
        np.testing.assert_allclose(saved[name], np.asarray(value), rtol=1e-6)
    assert not np.allclose(np.asarray(fresh["w0"]), np.asarray(first["w0"]))
    code = main(["train", "--preset", "easy", "--timesteps", "64", "--engine", "loop",
                 "--restart-after", "0.5", "--out", str(tmp_path / "b")])
    assert code == 2 and "--engine jax" in capsys.readouterr().err
    assert not (tmp_path / "b").exists()


def test_ocplus_train_passes_restart_after_to_the_jax_trainer(tmp_path: Path):
    from ocplus_plan.cli import main

    assert main(["train", "--engine", "jax", "--preset", "easy", "--timesteps", "32",
                 "--n-kitchens", "2", "--n-steps", "4", "--n-epochs", "1", "--hidden", "8,8",
                 "--obs-radius", "1", "--restart-after", "0.5", "--out", str(tmp_path),
                 "--quiet"]) == 0
    summary = json.loads((tmp_path / "train.json").read_text())
    assert summary["config"]["restart_after"] == 0.5
    assert (summary["restarts"], summary["learner_start_update"]) == (1, 2)  # of 4 updates

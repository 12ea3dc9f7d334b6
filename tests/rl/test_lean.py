"""The lean PPO loop (``ocplus train --algo lean``); skipped without the ``rl`` extra."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip(
    "stable_baselines3", reason="the rl extra is not installed: pip install -e '.[rl]'"
)

from ocplus_plan.agents import make_controller
from ocplus_plan.agents.base import run_episode
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.lean import LeanPPO, gae
from ocplus_plan.rl.policy import read_meta
from ocplus_plan.rl.train import TrainConfig, build, train
from ocplus_plan.sim import make_rules, new_state

TINY = dict(preset="easy", n_agents=2, n_kitchens=3, n_steps=8, batch_size=16, n_epochs=2,
            hidden=(16,), algo="lean")


def reference_gae(rewards, values, dones, last_values, gamma, lam):
    """Per slot, backwards over time, in plain Python floats."""
    steps, slots = len(rewards), len(rewards[0])
    adv = [[0.0] * slots for _ in range(steps)]
    for n in range(slots):
        running = 0.0
        for t in reversed(range(steps)):
            nxt = last_values[n] if t == steps - 1 else values[t + 1][n]
            alive = 0.0 if dones[t][n] else 1.0
            delta = rewards[t][n] + gamma * nxt * alive - values[t][n]
            running = delta + gamma * lam * alive * running
            adv[t][n] = running
    return adv


def test_gae_matches_a_plain_reference_across_episode_ends():
    rewards = [[1.0, 0.0], [0.0, -0.5], [2.0, 0.0], [0.0, 3.0], [-1.0, 0.5]]
    values = [[0.5, 0.1], [0.2, -0.3], [1.0, 0.0], [0.4, 0.7], [0.0, 0.2]]
    dones = [[False, False], [False, True], [True, False], [False, False], [False, True]]
    last = [0.9, -0.4]
    adv, ret = gae(torch.tensor(rewards), torch.tensor(values), torch.tensor(dones),
                   torch.tensor(last), 0.9, 0.8)
    expected = reference_gae(rewards, values, dones, last, 0.9, 0.8)
    np.testing.assert_allclose(adv.numpy(), expected, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(ret.numpy(), np.array(expected) + np.array(values), rtol=1e-6)


def test_two_rollouts_save_a_checkpoint_the_ppo_controller_plays(tmp_path: Path):
    summary = train(TrainConfig(**TINY, steps=2 * 3 * 2 * 8, out=str(tmp_path)),
                    command="test", progress=False)
    assert summary["timesteps"] == 2 * 3 * 2 * 8  # two whole rollouts, 6 slots x 8 steps
    assert set(summary["seconds"]) == {"env", "forward", "rollout_other", "update"}
    meta = read_meta(tmp_path / "policy.zip")
    assert meta["train"]["algo"] == "lean" and meta["n_agents"] == 2
    assert json.loads((tmp_path / "train.json").read_text())["config"]["algo"] == "lean"
    agent = make_controller(f"ppo:{tmp_path / 'policy.npz'}", seed=0)
    played = run_episode(new_state(make_rules("easy", n_agents=2, horizon=12), 0), agent)
    assert played["t"] == 12 and agent.info()["checkpoint"].endswith("policy.npz")


def test_lean_runs_a_curriculum_after_a_greedy_clone(tmp_path: Path):
    from functools import partial

    config = TrainConfig(**{**TINY, "n_agents": 1, "batch_size": 12}, steps=4 * 3 * 8,
                         out=str(tmp_path), curriculum=("medium:steak",),
                         curriculum_fraction=0.5, bc="greedy", bc_steps=50, bc_rounds=1,
                         bc_epochs=1)
    summary = train(config, command="test", progress=False,
                    teacher=partial(make_controller, "greedy"))
    assert summary["timesteps"] == 4 * 3 * 8  # 2 rollouts per stage, 3 kitchens x 8 steps
    assert summary["imitation"]["rounds"][0]["teacher_share"] == 1.0
    trained = read_meta(tmp_path / "policy.zip")["train"]
    assert (trained["algo"], trained["bc"]) == ("lean", "greedy")


def test_the_lean_update_is_sb3_ppo_train_on_the_same_rollout(tmp_path: Path):
    from stable_baselines3.common.logger import configure

    config = TrainConfig(**{**TINY, "n_epochs": 1, "batch_size": 48})  # one minibatch
    model, venv, _, _ = build(config)
    model.set_logger(configure(str(tmp_path), []))  # SB3's default logs into TMPDIR
    lean = LeanPPO(model, venv, config.precision, config.seed)
    lean._last_obs = venv.reset()
    lean._collect(None)
    buf = model.rollout_buffer
    buf.reset()
    buf.observations[:] = lean.obs.numpy()
    buf.actions[:] = lean.actions.numpy()[..., None]
    for name in ("log_probs", "values", "advantages", "returns"):
        getattr(buf, name)[:] = getattr(lean, name).numpy()
    buf.full = True
    start = copy.deepcopy(model.policy.state_dict())
    plain_adam = dict(lr=config.learning_rate, eps=1e-5)
    model.policy.optimizer = torch.optim.Adam(model.policy.parameters(), **plain_adam)
    model._current_progress_remaining = 1.0
    model.train()
    sb3 = copy.deepcopy(model.policy.state_dict())
    model.policy.load_state_dict(start)
    lean.policy.optimizer = torch.optim.Adam(model.policy.parameters(), **plain_adam)
    model.num_timesteps, lean._total = 0, 10**9  # the learning rate at its start value
    lean._update()
    for name, value in model.policy.state_dict().items():
        assert not torch.equal(value, start[name])  # both moved ...
        torch.testing.assert_close(value, sb3[name], rtol=1e-5, atol=1e-6)  # ... alike


@pytest.mark.parametrize(("bad", "match"), [
    ({"algo": "jax"}, "algo must be one of sb3, lean"),
    ({"precision": "fp16", "algo": "lean"}, "precision must be one of fp32, bf16"),
    ({"precision": "bf16"}, "needs algo 'lean'"),
])
def test_lean_options_are_checked(bad: dict, match: str, tmp_path: Path):
    with pytest.raises(ConfigError, match=match):
        train(TrainConfig(out=str(tmp_path), **bad), progress=False)


def test_cli_refuses_bf16_without_the_lean_loop(tmp_path: Path, capsys: pytest.CaptureFixture):
    argv = ["train", "--steps", "100", "--out", str(tmp_path / "x"), "--quiet"]
    assert main([*argv, "--precision", "bf16"]) == 2
    assert "--algo lean" in capsys.readouterr().err
    assert main([*argv, "--algo", "jax"]) == 2  # argparse: not among the choices

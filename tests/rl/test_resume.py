"""Resuming a run (weights, Adam state, step count) and the TensorBoard option."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")

from ocplus_plan.errors import ConfigError, DependencyNotInstalled  # noqa: E402
from ocplus_plan.rl.train import TrainConfig, build, train  # noqa: E402
from ocplus_plan.rl.train import _resume  # noqa: E402

TINY = dict(preset="easy", n_kitchens=2, n_steps=64, batch_size=64, n_epochs=1, hidden=(16,))


def test_resume_restores_weights_optimiser_state_and_step_count(tmp_path: Path, monkeypatch):
    import torch

    from ocplus_plan.rl.weights import TRUST_ENV

    first = tmp_path / "a"
    train(TrainConfig(steps=256, out=str(first), **TINY), command="t", progress=False)
    saved = first / "policy.zip"
    with pytest.raises(ConfigError, match="trust-pickled-checkpoint"):  # the zip pickles
        TrainConfig(steps=512, out=str(tmp_path / "b"), resume=str(saved), **TINY).validate()
    monkeypatch.setenv(TRUST_ENV, "1")
    config = TrainConfig(steps=512, out=str(tmp_path / "b"), resume=str(saved), **TINY)
    model, venv, _, _ = build(config)
    _resume(model, venv, config)
    reference, _, _, _ = build(TrainConfig(steps=512, out=str(tmp_path / "c"), **TINY))
    reference.set_parameters(str(saved))
    assert model.num_timesteps == 256
    for a, b in zip(model.policy.optimizer.state_dict()["state"].values(),
                    reference.policy.optimizer.state_dict()["state"].values()):
        assert torch.equal(a["exp_avg"], b["exp_avg"]) and a["exp_avg"].abs().sum() > 0
    import ocplus_plan.rl.train as train_module

    speeds = []
    monkeypatch.setattr(train_module, "own_speed",
                        lambda *a: speeds.append(a[:2]) or 1.0)
    summary = train(config, command="t", progress=False)
    assert summary["timesteps"] == 512  # 256 more, not 512 from 0
    assert summary["resumed_from_timesteps"] == 256
    # the speed counts the 256 steps this run made, not the 512 the model has
    assert speeds == [(512, 256)] and summary["steps_per_s"] == 1.0
    steps = [int(p.stem.split("_")[1]) for p in (tmp_path / "b" / "checkpoints").glob("step_*")]
    assert steps and min(steps) > 256  # the checkpoints go on from the resumed step
    with pytest.raises(ConfigError, match="raise --timesteps"):
        _resume(model, venv, TrainConfig(steps=100, out=str(tmp_path / "d"),
                                         resume=str(saved), **TINY))
    with pytest.raises(ConfigError, match="plain sb3 run"):
        TrainConfig(resume=str(saved), bc="greedy").validate()


@pytest.mark.skipif(importlib.util.find_spec("tensorboard") is not None,
                    reason="tensorboard is installed")
def test_tensorboard_without_the_extra_is_refused_naming_it(tmp_path: Path):
    with pytest.raises(DependencyNotInstalled, match=r"ocplus-plan\[tensorboard\]"):
        build(TrainConfig(tensorboard=str(tmp_path / "tb"), out=str(tmp_path), **TINY))


@pytest.mark.skipif(importlib.util.find_spec("tensorboard") is None,
                    reason="the tensorboard extra is not installed")
def test_tensorboard_writes_event_files(tmp_path: Path):
    train(TrainConfig(steps=256, out=str(tmp_path / "r"), tensorboard=str(tmp_path / "tb"),
                      **TINY), command="t", progress=False)
    assert list((tmp_path / "tb").glob("events.out.tfevents.*"))
    assert json.loads((tmp_path / "r" / "train.json").read_text())["timesteps"] >= 256


def test_a_resumed_runs_speed_counts_its_own_steps_and_time():
    from ocplus_plan.rl.train import own_speed

    assert own_speed(512, 256, 2.0, None) == 128.0  # 256 steps of its own in 2 s
    assert own_speed(512, 0, 2.0, None) == 256.0
    assert own_speed(512, 0, 3.0, {"wall_time_s": 1.0}) == 256.0  # less the clone's time

"""The behaviour-cloning warm start (rl/imitation.py, ``ocplus train --bc``); tiny budgets."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip(
    "stable_baselines3", reason="the rl extra is not installed: pip install -e '.[rl]'"
)

from ocplus_plan.agents import make_controller
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.imitation import Imitation, collect, discounted, fit
from ocplus_plan.rl.obs import make_encoder
from ocplus_plan.rl.policy import read_meta
from ocplus_plan.rl.train import TrainConfig, build, train
from ocplus_plan.sim import make_rules, new_state


def greedy(seed: int):
    return make_controller("greedy", seed)


def rules(preset: str = "easy", n_agents: int = 1):
    return make_rules(preset, n_agents=n_agents, reward_mode="individual")


def test_discounted_returns_sum_later_rewards_with_gamma():
    r = np.array([[1.0], [0.0], [2.0]], np.float32)
    assert discounted(r, 0.5).ravel().tolist() == [1.5, 1.0, 2.0]


def test_collect_records_every_cook_at_every_step_of_whole_episodes():
    data, dishes = collect(rules("easy", 2), "features", 0, greedy, steps=150, seed=3)
    obs, actions, returns = data.arrays()
    assert len(dishes) == 1  # whole episodes: one 200-step episode covers 150 steps
    assert obs.shape == (200 * 2, make_encoder("features", rules("easy", 2)).size)
    assert actions.shape == returns.shape == (400,)
    assert set(actions.tolist()) <= set(range(5))


def test_the_labels_are_the_teachers_actions():
    data, _ = collect(rules(), "features", 0, greedy, steps=1, seed=5)
    state = new_state(rules(), 5 * 1_000_003)
    teacher = greedy(5)
    teacher.reset(state)
    assert data.actions[0][0] == teacher.act(state)[0]


def test_fitting_lowers_the_cross_entropy_on_the_teachers_actions(tmp_path: Path):
    model, _, _, _ = build(TrainConfig(preset="easy", n_kitchens=1, n_steps=16, batch_size=16,
                                       hidden=(32,), out=str(tmp_path)))
    data, _ = collect(rules(), "features", 0, greedy, steps=200, seed=1)
    cfg = Imitation(steps=200, epochs=1, batch_size=64, learning_rate=3e-3)
    first = fit(model.policy, data, cfg, seed=0)["cross_entropy"]
    later = fit(model.policy, data, Imitation(steps=200, epochs=10, batch_size=64,
                                              learning_rate=3e-3), seed=1)
    assert later["cross_entropy"] < first
    assert 0.0 <= later["accuracy"] <= 1.0


def test_training_with_bc_keeps_the_clone_and_reports_each_round(tmp_path: Path):
    config = TrainConfig(preset="easy", steps=64, seed=2, out=str(tmp_path), n_kitchens=1,
                         n_steps=64, batch_size=64, n_epochs=1, hidden=(32,), bc="greedy",
                         bc_steps=100, bc_rounds=2, bc_epochs=1)
    summary = train(config, command="test", progress=False, teacher=greedy)
    rounds = summary["imitation"]["rounds"]
    assert [r["teacher_share"] for r in rounds] == [1.0, 0.5]
    assert rounds[1]["samples"] > rounds[0]["samples"]
    assert read_meta(tmp_path / "bc_policy.zip")["train"]["bc"] == "greedy"
    assert json.loads((tmp_path / "train.json").read_text())["imitation"]["teacher"] == "greedy"


def test_bc_without_a_teacher_factory_is_refused(tmp_path: Path):
    with pytest.raises(ConfigError, match="teacher"):
        train(TrainConfig(preset="easy", steps=64, out=str(tmp_path), bc="greedy"),
              progress=False)


def test_bc_steps_must_be_positive():
    with pytest.raises(ConfigError, match="bc steps"):
        TrainConfig(bc="greedy", bc_steps=0).validate()


def test_cli_refuses_an_unknown_teacher_before_training(tmp_path: Path, capsys):
    code = main(["train", "--preset", "easy", "--steps", "64", "--bc", "nosuchcook",
                 "--out", str(tmp_path / "run")])
    assert code == 2
    assert "nosuchcook" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


def test_collect_judges_the_learner_on_every_sample_it_labels(tmp_path: Path):
    """With ``judge``, each sample says whether the learner's argmax missed the label."""
    from ocplus_plan.rl.policy import LoadedPolicy

    model, _, _, _ = build(TrainConfig(preset="easy", n_agents=2, n_kitchens=1, n_steps=16,
                                       batch_size=16, hidden=(32,), out=str(tmp_path)))
    learner = LoadedPolicy(tmp_path, {}, model)
    data, _ = collect(rules("easy", 2), "features", 0, greedy, steps=30, seed=4,
                      learner=learner, beta=1.0, judge=True)
    obs, actions, _ = data.arrays()
    missed = np.concatenate(data.missed)
    np.testing.assert_array_equal(missed, learner.probs(obs).argmax(axis=1) != actions)
    assert missed.any() and not missed.all()  # an untrained learner misses some, not all
    weights = data.weights(4.0)
    assert set(weights[missed]) == {4.0} and set(weights[~missed]) == {1.0}
    plain, _ = collect(rules("easy", 2), "features", 0, greedy, steps=30, seed=4)
    assert not np.concatenate(plain.missed).any()  # no learner: nothing judged


def test_focus_weighs_the_missed_samples_in_the_fit(tmp_path: Path):
    """A focused fit moves the actor more on the missed samples than a plain one."""
    import torch

    data, _ = collect(rules(), "features", 0, greedy, steps=200, seed=1)
    n = sum(len(a) for a in data.actions)
    data.missed = [np.arange(n) % 7 == 0]  # mark one sample in seven as missed
    obs, actions, _ = data.arrays()
    hit = {}
    for focus in (1.0, 20.0):
        model, _, _, _ = build(TrainConfig(preset="easy", n_kitchens=1, n_steps=16,
                                           batch_size=16, hidden=(32,), seed=0,
                                           out=str(tmp_path / str(focus))))
        fit(model.policy, data, Imitation(steps=200, epochs=3, batch_size=64,
                                          learning_rate=3e-3, focus=focus), seed=0)
        with torch.no_grad():
            _, log_prob, _ = model.policy.evaluate_actions(
                torch.as_tensor(obs[data.missed[0]]).float(),
                torch.as_tensor(actions[data.missed[0]]))
        hit[focus] = float(log_prob.mean())
    assert hit[20.0] > hit[1.0]


def test_bc_focus_is_bounded():
    with pytest.raises(ConfigError, match="bc focus"):
        TrainConfig(bc="greedy", bc_focus=0.5).imitation().validate()

"""The generalist: which checkpoint a bare ``ppo`` plays, and the weights-only export."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.agents.ppo import shipped_checkpoint
from ocplus_plan.errors import ConfigError


def _shelf(tmp_path: Path, *names: str) -> Path:
    for name in names:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_bytes(b"x")
    return tmp_path


def test_a_bare_ppo_never_plays_a_checkpoint_of_another_cook_count(tmp_path: Path):
    shelf = _shelf(tmp_path, "hard_1agent.npz", "hard_2agent.npz")
    assert shipped_checkpoint("hard", 2, shelf).name == "hard_2agent.npz"
    with pytest.raises(ConfigError, match="another number of cooks is never played"):
        shipped_checkpoint("hard", 3, shelf)


def test_a_kitchen_without_its_own_checkpoint_gets_the_generalist_for_its_cooks(tmp_path):
    shelf = _shelf(tmp_path, "medium_2agent.npz", "generalist_2agent/policy.npz")
    own = shipped_checkpoint("medium", 2, shelf, map_name="medium_kitchen")
    assert own.name == "medium_2agent.npz"
    other = shipped_checkpoint("medium", 2, shelf, map_name="gen:open:test:3:medium")
    assert other.parent.name == "generalist_2agent" and other.name == "policy.npz"
    with pytest.raises(ConfigError, match="no shipped PPO checkpoint for 1 cook"):
        shipped_checkpoint("medium", 1, shelf, map_name="gen:open:test:3:medium")


pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")


def test_the_weights_only_export_plays_the_same_probabilities(tmp_path: Path):
    from ocplus_plan.agents.ppo import PPOAgent
    from ocplus_plan.agents.base import run_episode
    from ocplus_plan.rl.npz_export import export_npz
    from ocplus_plan.rl.npz_policy import NpzPolicy
    from ocplus_plan.rl.policy import load_policy
    from ocplus_plan.rl.train import TrainConfig, train
    from ocplus_plan.sim import make_rules, new_state

    out = tmp_path / "run"
    train(TrainConfig(preset="easy", n_agents=2, maps="gen:open:train:0-1", steps=256,
                      n_kitchens=1, n_steps=128, batch_size=128, n_epochs=1, hidden=(16, 16),
                      out=str(out)), command="test", progress=False)
    npz = export_npz(out / "policy.zip", tmp_path / "generalist_2agent")
    with np.load(npz, allow_pickle=False) as data:  # weights only: nothing to unpickle
        assert sorted(data.files) == ["b0", "b1", "b2", "w0", "w1", "w2"]
    sb3, light = load_policy(out / "policy.zip"), NpzPolicy(npz)
    assert light.meta["obs"] == "window" and light.meta["obs_radius"] == 2
    x = np.random.default_rng(0).normal(size=(7, sb3.meta["obs_size"])).astype(np.float32)
    np.testing.assert_allclose(light.probs(x), sb3.probs(x), rtol=1e-4, atol=1e-6)
    rules = make_rules("easy", map="gen:split:test:0:easy", n_agents=2, horizon=20)
    stats = run_episode(new_state(rules, 0), PPOAgent(str(npz), seed=0))
    assert stats["t"] == 20


def test_a_bare_ppo_plays_the_shipped_generalist_on_a_generated_kitchen_and_says_so(capsys):
    from ocplus_plan.agents import ppo
    from ocplus_plan.agents.base import run_episode
    from ocplus_plan.sim import make_rules, new_state

    ppo._ANNOUNCED.clear()
    agent = ppo.PPOAgent(None, seed=0)
    rules = make_rules("medium", map="gen:open:test:0:medium", n_agents=2, horizon=5)
    run_episode(new_state(rules, 0), agent)
    assert agent.info()["checkpoint"].endswith("generalist_2agent/policy.npz")
    assert "generalist_2agent" in capsys.readouterr().err

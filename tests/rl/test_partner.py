"""Training beside a scripted partner (``ocplus train --partner greedy:0.5``): the partner's
actions are the greedy cook's, its cook gives no samples, bad values and combinations are
refused (skipped without the ``rl`` extra)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.train import TrainConfig, parse_partner

torch = pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")

from ocplus_plan.agents.greedy import GreedyAgent  # noqa: E402
from ocplus_plan.cli import main  # noqa: E402
from ocplus_plan.rl.obs import make_encoder  # noqa: E402
from ocplus_plan.rl.vec_env import KitchenVecEnv  # noqa: E402
from ocplus_plan.sim import new_state  # noqa: E402
from ocplus_plan.sim.rules import make_rules  # noqa: E402
from ocplus_plan.sim.step import transition  # noqa: E402

MAPS = "gen:open:train:0-1,gen:split:train:0"


def test_a_partner_spec_is_an_agent_and_a_share():
    assert parse_partner("greedy:0.5") == ("greedy", 0.5)
    assert parse_partner("stay:1") == ("stay", 1.0)
    assert TrainConfig(partner="greedy:0.5", n_kitchens=32).partner_kitchens() == 16


@pytest.mark.parametrize("text", ["greedy", "greedy:0", "greedy:1.5", "greedy:x", "greedy:nan",
                                  "planner:0.5", ":0.5"])
def test_a_bad_partner_spec_is_refused_naming_the_form(text):
    with pytest.raises(ConfigError, match="AGENT:SHARE"):
        parse_partner(text)


@pytest.mark.parametrize("extra, why", [
    (["--partner", "greedy:2"], "share must be in"),
    (["--partner", "ppo:0.5"], "AGENT:SHARE"),
    (["--partner", "greedy:0.1", "--n-kitchens", "2"], "gives the partner no kitchen"),
    (["--partner", "greedy:0.5", "--n-agents", "1"], "--n-agents 2 or more"),
    (["--partner", "greedy:0.5", "--engine", "batch"], "--engine loop"),
    (["--partner", "greedy:0.5", "--engine", "jax"], "not --engine jax"),
    (["--partner", "greedy:0.5", "--bc", "greedy"], "does not go with --bc"),
    (["--partner", "greedy:0.5", "--algo", "lean"], "does not go with --algo lean"),
    (["--partner", "greedy:0.5", "--resume-from", "x.zip", "--trust-pickled-checkpoint"],
     "does not go with --resume-from"),
])
def test_the_cli_refuses_a_bad_partner_in_one_line(tmp_path: Path, capsys, monkeypatch, extra,
                                                   why):
    from ocplus_plan.rl.weights import TRUST_ENV

    monkeypatch.setenv(TRUST_ENV, "0")  # --trust-pickled-checkpoint sets it: undone after
    code = main(["train", "--preset", "easy", "--timesteps", "100", "--out",
                 str(tmp_path / "x"), *extra])
    err = capsys.readouterr().err.strip()
    assert code == 2 and why in err and len(err.splitlines()) == 1 and "Traceback" not in err


def test_the_partner_plays_the_last_cook_as_the_greedy_cook_would():
    rules = make_rules("easy", n_agents=2, reward_mode="individual", horizon=60)
    venv = KitchenVecEnv(rules, 2, seed=3, obs="features", engine="loop",
                         partner=GreedyAgent, partner_kitchens=1)
    assert venv.num_envs == 3  # kitchen 0: cook 0 only; kitchen 1: both cooks
    obs = venv.reset()
    ref = new_state(rules, venv.states[0].seed)
    greedy = GreedyAgent(3)
    greedy.reset(ref, [1])
    enc = make_encoder("features", rules, 0)
    np.testing.assert_allclose(obs[0], enc.encode_all(ref)[0])
    rng = np.random.default_rng(0)
    moved = 0
    for _ in range(50):
        acts = rng.integers(0, 5, size=3)
        partner_act = greedy.act(ref)
        moved += partner_act[0] != 0
        transition(ref, [int(acts[0]), *partner_act])
        venv.step_async(acts)
        obs, rewards, dones, _ = venv.step_wait()
        assert obs.shape == (3, venv.obs_size) and rewards.shape == (3,)
        assert venv.states[0].agent_pos == ref.agent_pos
        assert venv.states[0].agent_hand == ref.agent_hand
        np.testing.assert_allclose(obs[0], enc.encode_all(ref)[0])
    assert moved > 10  # the greedy cook worked, it did not stand still


def test_ppo_trains_beside_a_greedy_partner_on_the_learners_samples_only(tmp_path: Path):
    out = tmp_path / "partner"
    # 2 kitchens, one with the partner: 3 slots x 64 steps = 192 samples a rollout;
    # 4 rollouts end one 200-step episode in each kitchen (were the partner's cook a slot,
    # 768 samples would be 3 rollouts of 4 x 64, 192 kitchen steps: no episode would end)
    code = main(["train", "--preset", "easy", "--n-agents", "2", "--maps", MAPS,
                 "--obs", "features", "--timesteps", "768", "--n-kitchens", "2",
                 "--n-steps", "64", "--batch-size", "96", "--n-epochs", "1", "--hidden", "16",
                 "--partner", "greedy:0.5", "--quiet", "--out", str(out)])
    assert code == 0
    summary = json.loads((out / "train.json").read_text())
    assert summary["timesteps"] == 768 and summary["config"]["engine"] == "loop"
    assert summary["config"]["partner"] == "greedy:0.5"
    with open(out / "episodes.csv") as f:
        episodes = list(csv.DictReader(f))
    assert {(e["kitchen"], e["partner"]) for e in episodes} == {("0", "greedy"), ("1", "")}
    from ocplus_plan.rl.weights import WeightsPolicy

    assert WeightsPolicy(str(out / "policy.npz")).meta["partner"] == "greedy:0.5"

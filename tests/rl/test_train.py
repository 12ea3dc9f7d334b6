"""Training, checkpoints and the ppo controller (skipped without the ``rl`` extra)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip(
    "stable_baselines3", reason="the rl extra is not installed: pip install -e '.[rl]'"
)

from ocplus_plan.agents import make_controller
from ocplus_plan.agents.ppo import PPOAgent, parse_spec, shipped_checkpoint
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.policy import load_policy, read_meta
from ocplus_plan.rl.train import TrainConfig, train
from ocplus_plan.rl.vec_env import KitchenVecEnv
from ocplus_plan.rl.weights import FORMAT, WeightsPolicy
from ocplus_plan.sim import make_rules, new_state, transition

SHIPPED = Path(__file__).resolve().parents[2] / "experiments" / "checkpoints"
EXPECTED = {"easy_1agent.npz": ("easy", 1), "medium_1agent.npz": ("medium", 1),
            "easy_2agent.npz": ("easy", 2), "medium_2agent.npz": ("medium", 2),
            "hard_1agent.npz": ("hard", 1), "hard_2agent.npz": ("hard", 2)}


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("ppo")
    train(TrainConfig(preset="easy", n_agents=2, steps=3000, seed=1, out=str(out),
                      n_kitchens=4, n_steps=64, batch_size=128, n_epochs=2, hidden=(32,),
                      checkpoint_every=1000),
          command="test", progress=False)
    return out


def test_short_training_writes_policy_logs_and_checkpoints(tiny_run: Path):
    assert (tiny_run / "policy.zip").is_file() and (tiny_run / "policy.npz").is_file()
    assert len(list((tiny_run / "checkpoints").glob("step_*.npz"))) >= 2
    summary = json.loads((tiny_run / "train.json").read_text())
    assert summary["timesteps"] >= 3000 and summary["wall_time_s"] > 0
    rows = list(csv.DictReader((tiny_run / "episodes.csv").open()))
    # 4 kitchens x 2 agents = 8 slots: 3072 agent-steps = 384 kitchen steps, 200-step episodes
    assert len(rows) == 4
    assert {r["steps"] for r in rows} == {"200"}
    assert all(float(r["dishes"]) >= 0 and r["preset"] == "easy" for r in rows)
    meta = WeightsPolicy(tiny_run / "policy.npz").meta
    assert meta == {**read_meta(tiny_run / "policy.zip"), "format": FORMAT, "activation": "tanh"}
    assert meta["n_agents"] == 2 and meta["obs"] == "features"
    assert meta["train"]["command"] == "test"


def test_saved_policy_loads_and_drives_every_agent(tiny_run: Path):
    policy = load_policy(tiny_run / "policy.zip")
    obs = np.zeros((3, policy.meta["obs_size"]), np.float32)
    p = policy.probs(obs)
    assert p.shape == (3, 5) and np.allclose(p.sum(axis=1), 1.0, atol=1e-5)
    agent = make_controller(f"ppo:{tiny_run / 'policy.npz'}", seed=0)
    rules = make_rules("hard")  # features work on any map and agent count
    state = new_state(rules, 0)
    agent.reset(state)
    for _ in range(20):
        actions = agent.act(state)
        assert len(actions) == 2 and all(0 <= a <= 4 for a in actions)
        transition(state, actions)


def test_sampling_is_reproducible_and_greedy_is_deterministic(tiny_run: Path):
    path = str(tiny_run / "policy.npz")

    def run(spec: str, seed: int) -> list[list[int]]:
        agent = make_controller(spec, seed)
        state = new_state(make_rules("easy"), 4)
        agent.reset(state)
        out = []
        for _ in range(15):
            a = agent.act(state)
            out.append(a)
            transition(state, a)
        return out

    assert run(f"ppo:{path}", 3) == run(f"ppo:{path}", 3)
    assert run(f"ppo:{path}@greedy", 1) == run(f"ppo:{path}@greedy", 2)


def test_cli_train_runs_and_prints_a_summary(tmp_path: Path, capsys: pytest.CaptureFixture):
    out = tmp_path / "run"
    code = main(["train", "--preset", "easy", "--steps", "600", "--seed", "0", "--out", str(out),
                 "--n-kitchens", "2", "--n-steps", "32", "--batch-size", "64", "--hidden", "16",
                 "--no-progress", "--json"])
    assert code == 0
    printed = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert printed["policy"].endswith("policy.npz") and printed["timesteps"] >= 600
    assert "ocplus train --preset easy" in read_meta(out / "policy.zip")["train"]["command"]


def test_bad_input_is_a_clear_error(tmp_path: Path):
    assert main(["train", "--preset", "nope", "--steps", "10", "--out", str(tmp_path)]) == 2
    assert main(["train", "--steps", "0", "--out", str(tmp_path / "x")]) == 2
    with pytest.raises(ConfigError, match="cannot be read"):
        make_controller(f"ppo:{tmp_path / 'missing.npz'}")
    (tmp_path / "junk.npz").write_text("not a zip")
    with pytest.raises(ConfigError, match="not a readable .npz"):
        make_controller(f"ppo:{tmp_path / 'junk.npz'}")
    with pytest.raises(ConfigError, match="trust-pickled-checkpoint"):
        make_controller(f"ppo:{tmp_path / 'junk.zip'}")
    assert parse_spec("a/b.zip@greedy") == ("a/b.zip", "greedy")
    assert parse_spec(None) == (None, None)
    with pytest.raises(ConfigError, match="no shipped PPO checkpoint"):
        shipped_checkpoint("hard", 2, tmp_path)


def test_vec_env_has_one_slot_per_agent_and_resets_kitchens():
    rules = make_rules("easy", n_agents=2, horizon=5, reward_mode="individual")
    venv = KitchenVecEnv(rules, n_kitchens=3, seed=0)
    assert venv.num_envs == 6
    obs = venv.reset()
    assert obs.shape == (6, venv.obs_size)
    for t in range(5):
        venv.step_async(np.full(6, 4))
        obs, rew, dones, infos = venv.step_wait()
        assert dones.all() == (t == 4)
    assert len(venv.finished) == 3 and all("terminal_observation" in i for i in infos)
    assert np.allclose(rew, 2 * -0.1 * venv.reward_scale)  # team step penalty, no shaping
    with pytest.raises(ConfigError, match="individual"):
        KitchenVecEnv(make_rules("easy", reward_mode="shared"))


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_shipped_checkpoints_are_small_load_and_serve(name: str):
    path = SHIPPED / name
    if not path.is_file():
        pytest.fail(f"missing shipped checkpoint {path}")
    assert path.stat().st_size < 5 * 1024 * 1024
    preset, n_agents = EXPECTED[name]
    meta = WeightsPolicy(path).meta
    assert (meta["preset"], meta["n_agents"]) == (preset, n_agents)
    agent = PPOAgent(str(path), seed=0)
    rules = make_rules(preset, n_agents=n_agents)
    state = new_state(rules, 0)
    agent.reset(state)
    while not state.done:
        transition(state, agent.act(state))
    if preset == "easy":  # a trained easy policy serves within one episode
        assert state.stats["dishes_served"] >= 1
    assert make_controller("ppo").info()["checkpoint"] is None  # resolved at reset


def test_grid_observations_and_curriculum_switch():
    easy = make_rules("easy", reward_mode="individual")
    venv = KitchenVecEnv(easy, n_kitchens=2, seed=0, obs="grid")
    obs = venv.reset()
    assert obs.shape == (2, venv.obs_size) and 0.0 <= obs.min() and obs.max() <= 1.0
    # a features env can switch presets mid-training (same size on every map) ...
    feats = KitchenVecEnv([easy, make_rules("medium", reward_mode="individual")], n_kitchens=2)
    feats.reset()
    assert {s.rules.preset for s in feats.states} == {"easy", "medium"}
    feats.set_rules(make_rules("hard", n_agents=1, reward_mode="individual"))
    # ... a grid env cannot: the map size changes the observation
    with pytest.raises(ConfigError, match="curriculum rule set"):
        venv.set_rules(make_rules("hard", n_agents=1, reward_mode="individual"))


def test_batch_engine_vec_env_matches_its_kitchens_and_trains(tmp_path: Path):
    from stable_baselines3 import PPO
    from stable_baselines3.common.logger import configure

    from ocplus_plan.rl.obs import GridEncoder
    from ocplus_plan.rl.shaping import Shaping

    rules = make_rules("easy", n_agents=2, horizon=5, reward_mode="individual")
    only_subtasks = Shaping(stage=0, useful_plate=0, carry_fresh=0, carry_ready=0, carry_dish=0)
    venv = KitchenVecEnv(rules, n_kitchens=3, seed=0, obs="grid", shaping=only_subtasks,
                         engine="batch")
    obs = venv.reset()
    enc = GridEncoder(rules)
    for j in range(3):
        state = venv.batch.engine(rules)[1].state(j)
        np.testing.assert_array_equal(obs[2 * j : 2 * j + 2], enc.encode_all(state))
    for t in range(5):
        venv.step_async(np.full(6, 4))
        obs, rew, dones, infos = venv.step_wait()
        assert dones.all() == (t == 4)
    assert len(venv.finished) == 3 and all("terminal_observation" in i for i in infos)
    assert np.allclose(rew, 2 * -0.1 * venv.reward_scale)
    model = PPO("MlpPolicy", venv, n_steps=8, batch_size=24, n_epochs=1, seed=0, device="cpu")
    model.set_logger(configure(str(tmp_path), []))  # SB3's default logs into TMPDIR
    model.learn(48)
    assert model.num_timesteps >= 48


def test_an_unknown_engine_is_refused():
    rules = make_rules("easy", n_agents=2, reward_mode="individual")
    with pytest.raises(ConfigError, match="engine must be"):
        KitchenVecEnv(rules, engine="fast")


def test_batch_engine_trains_on_grid_observations(tmp_path: Path):
    summary = train(TrainConfig(preset="easy", steps=600, out=str(tmp_path), obs="grid",
                                engine="batch", n_kitchens=4, n_steps=32, batch_size=64,
                                n_epochs=1, hidden=(16,)),
                    command="test", progress=False)
    assert summary["timesteps"] >= 600 and summary["config"]["engine"] == "batch"
    assert read_meta(tmp_path / "policy.zip")["obs"] == "grid"


def test_wall_budget_stops_training_and_still_saves(tmp_path: Path):
    summary = train(TrainConfig(preset="easy", steps=10_000_000, out=str(tmp_path),
                                n_kitchens=2, n_steps=16, batch_size=32, n_epochs=1,
                                hidden=(16,), max_wall_s=0.5),
                    command="test", progress=False)
    assert summary["stopped_by_wall_budget"] is True
    assert summary["timesteps"] < 10_000_000
    assert (tmp_path / "policy.zip").is_file()


@pytest.mark.parametrize("bad", [{"engine": "fast"}, {"torch_threads": 0},
                                 {"max_wall_s": 0.0}])
def test_speed_options_are_checked(bad: dict, tmp_path: Path):
    with pytest.raises(ConfigError, match=next(iter(bad))):
        train(TrainConfig(out=str(tmp_path), **bad), progress=False)


def test_bare_ppo_without_a_checkpoint_for_the_kitchen_is_a_skipped_row(tmp_path: Path,
                                                                        monkeypatch):
    from ocplus_plan.agents import ppo
    from ocplus_plan.eval.results import read_results
    from ocplus_plan.eval.runner import EvalConfig, run_eval

    def nothing_shipped(preset: str, n_agents: int, **kw):
        raise ConfigError(f"no shipped PPO checkpoint for preset {preset!r}")

    monkeypatch.setattr(ppo, "shipped_checkpoint", nothing_shipped)
    run_eval(EvalConfig(presets=["easy"], agents=["greedy", "ppo"], seeds=[0], out=tmp_path / "e",
                        horizon=10, n_agents=1, jobs=1, quiet=True), echo=lambda _: None)
    rows = {r["agent"]: r for r in read_results(tmp_path / "e")}
    assert rows["ppo"]["status"] == "skipped" and "no shipped" in rows["ppo"]["reason"]
    assert rows["greedy"]["status"] == "ok"


@pytest.mark.parametrize("bad, words", [({"device": "tpu"}, "device must be"),
                                        ({"device": "cuda", "algo": "lean"}, "lean loop")])
def test_device_choices_are_checked(bad: dict, words: str, tmp_path: Path):
    with pytest.raises(ConfigError, match=words):
        train(TrainConfig(out=str(tmp_path), **bad), progress=False)


def test_the_trainer_builds_on_the_device_asked_for(tmp_path: Path):
    import torch

    from ocplus_plan.rl.train import build

    model, venv, _, _ = build(TrainConfig(out=str(tmp_path), n_kitchens=1, device="cpu"))
    venv.close()
    assert model.device.type == "cpu"
    if not torch.cuda.is_available():
        with pytest.raises(ConfigError, match="no CUDA device"):
            build(TrainConfig(out=str(tmp_path), n_kitchens=1, device="cuda"))

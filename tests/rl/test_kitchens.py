"""Training on a kitchen distribution: ``--maps`` parsing, a kitchen drawn per episode, the
``window`` observation, imitation and PPO over the list (skipped without the ``rl`` extra)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.kitchens import curriculum_stages, distribution_rules, parse_maps
from ocplus_plan.rl.obs import make_encoder
from ocplus_plan.sim import new_state


def test_a_range_expands_to_one_kitchen_per_index_with_the_presets_stations():
    names = parse_maps("gen:open:train:0-2, gen:split:test:5,mapA", "medium")
    assert names == ["gen:open:train:0:medium", "gen:open:train:1:medium",
                     "gen:open:train:2:medium", "gen:split:test:5:medium", "mapA"]


@pytest.mark.parametrize("text, why", [("", "names no kitchen"), ("gen:open:train:5-2", "ends"),
                                       ("gen:nope:train:0-3", "unknown family"),
                                       ("gen:open:train:0-5000", "at most")])
def test_a_bad_kitchen_list_is_refused_naming_the_form(text, why):
    with pytest.raises(ConfigError, match=why):
        parse_maps(text, "medium")


def test_layout_switches_only_where_the_kitchen_has_a_switch_layout():
    rules = distribution_rules(["gen:open:train:0:hard", "gen:switching:train:0:hard"], "hard")
    assert [r.dynamic for r in rules] == [False, True]


def test_window_observations_have_one_size_on_every_kitchen_and_cook_count():
    sizes = {make_encoder("window", r, 2).encode_all(new_state(r, 0)).shape[1]
             for n in (1, 2, 3)
             for r in distribution_rules(parse_maps("gen:open:train:0-1,gen:corridor:train:0",
                                                    "medium"), "medium", n_agents=n)}
    assert len(sizes) == 1
    with pytest.raises(ConfigError, match="obs_radius >= 1"):
        make_encoder("window", distribution_rules(["mapA"], "easy")[0], 0)


def test_the_curriculum_grows_from_the_smallest_kitchens_to_all():
    rules = distribution_rules(parse_maps("gen:open:train:0-3", "easy"), "easy")
    pools = curriculum_stages(rules, 2)
    assert len(pools[0]) == 2 and len(pools[1]) == 4
    assert max(r.layout.grid.size for r in pools[0]) <= min(
        r.layout.grid.size for r in pools[1] if r not in pools[0])


torch = pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")

from ocplus_plan.rl.vec_env import KitchenVecEnv  # noqa: E402


def test_each_episode_draws_a_kitchen_and_both_engines_agree():
    pool = distribution_rules(parse_maps("gen:open:train:0-2,gen:corridor:train:0", "easy"),
                              "easy", n_agents=2, reward_mode="individual", horizon=6)
    envs = {e: KitchenVecEnv(pool, 2, seed=3, obs="window", obs_radius=2, engine=e, draw=True)
            for e in ("loop", "batch")}
    obs = {e: v.reset() for e, v in envs.items()}
    np.testing.assert_allclose(obs["loop"], obs["batch"], atol=1e-6)
    rng = np.random.default_rng(0)
    for _ in range(30):  # 5 episodes per kitchen
        acts = rng.integers(0, 5, size=4)
        out = {}
        for e, v in envs.items():
            v.step_async(acts)
            out[e] = v.step_wait()
        np.testing.assert_allclose(out["loop"][0], out["batch"][0], atol=1e-6)
        np.testing.assert_allclose(out["loop"][1], out["batch"][1], atol=1e-6)
    maps = [f["map"] for f in envs["batch"].finished]
    assert len(maps) == 10 and len(set(maps)) >= 3


def test_training_on_a_kitchen_list_clones_greedy_then_runs_ppo(tmp_path: Path):
    from ocplus_plan.cli import main

    out = tmp_path / "gen"
    code = main(["train", "--preset", "easy", "--n-agents", "2", "--maps",
                 "gen:open:train:0-1,gen:split:train:0", "--timesteps", "1024",
                 "--n-kitchens", "2", "--n-steps", "64", "--batch-size", "128",
                 "--n-epochs", "1", "--hidden", "16", "--bc", "greedy", "--bc-steps", "200",
                 "--bc-rounds", "2", "--bc-epochs", "1", "--quiet", "--out", str(out)])
    assert code == 0
    summary = json.loads((out / "train.json").read_text())
    assert summary["config"]["obs"] == "window" and summary["config"]["obs_radius"] == 2
    assert summary["timesteps"] >= 1024
    rounds = summary["imitation"]["rounds"]
    assert [r["round"] for r in rounds] == [0, 1] and rounds[1]["samples"] > rounds[0]["samples"]
    from ocplus_plan.rl.policy import read_meta

    meta = read_meta(out / "policy.zip")
    assert meta["maps"] == "gen:open:train:0-1,gen:split:train:0" and meta["kitchens"] == 3

"""Training a policy that chooses subtasks (``ocplus train --obs choice``): its actions are
slots of the task-choice controller, the vec env moves the cooks with the greedy cook's
skills, the checkpoint plays with ``ppo:PATH`` (skipped without the ``rl`` extra)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.train import TrainConfig

pytest.importorskip("torch", reason="the rl extra is not installed: pip install -e '.[rl]'")
pytest.importorskip("stable_baselines3", reason="the rl extra is not installed")

from ocplus_plan.agents.ppo import PPOAgent  # noqa: E402
from ocplus_plan.agents.task_choice import SLOTS, TaskChoice  # noqa: E402
from ocplus_plan.cli import main  # noqa: E402
from ocplus_plan.rl.kitchens import kitchen_rules  # noqa: E402
from ocplus_plan.rl.vec_env import KitchenVecEnv  # noqa: E402
from ocplus_plan.sim import new_state  # noqa: E402
from ocplus_plan.sim.step import transition  # noqa: E402

MAPS = "gen:open:train:0-1,gen:corridor:train:0"


def _rules(name: str = "gen:open:train:0"):
    return kitchen_rules("medium", name, n_agents=2, reward_mode="individual", horizon=60)


def test_the_vec_env_steps_the_kitchen_as_the_task_choice_controller_would():
    rules = _rules()
    venv = KitchenVecEnv(rules, 1, seed=2, obs="choice", engine="loop", chooser=TaskChoice)
    assert venv.action_space.n == SLOTS + 1 and venv.obs_size == TaskChoice.obs_size(rules)
    obs = venv.reset()
    ref = new_state(rules, venv.states[0].seed)
    chooser = TaskChoice(2)
    chooser.reset(ref)
    rng = np.random.default_rng(0)
    for _ in range(40):
        np.testing.assert_allclose(obs, chooser.prepare(ref))
        picks = rng.integers(0, SLOTS + 1, size=2)
        transition(ref, chooser.drive(ref, picks.tolist()))
        venv.step_async(picks)
        obs, rewards, dones, _ = venv.step_wait()
        assert venv.states[0].agent_pos == ref.agent_pos
        assert venv.states[0].agent_hand == ref.agent_hand


@pytest.mark.parametrize("kw, why", [
    ({"obs": "choice", "engine": "batch"}, "--engine loop"),
    ({"obs": "choice", "bc": "greedy"}, "drop --bc"),
    ({"obs": "choice", "algo": "lean"}, "drop --bc and --algo lean"),
])
def test_bad_combinations_with_choice_are_refused_by_name(kw, why):
    with pytest.raises(ConfigError, match=why):
        TrainConfig(maps=MAPS, preset="medium", n_agents=2, **kw).validate()


def test_a_vec_env_with_choice_needs_the_chooser_and_the_loop_engine():
    with pytest.raises(ConfigError, match="chooser"):
        KitchenVecEnv(_rules(), 1, obs="choice", engine="loop")
    with pytest.raises(ConfigError, match="loop engine"):
        KitchenVecEnv(_rules(), 1, obs="choice", engine="batch", chooser=TaskChoice)


def test_ppo_trains_choices_on_a_kitchen_list_and_the_checkpoint_plays(tmp_path: Path):
    out = tmp_path / "choice"
    # 2 kitchens x 2 cooks x 100 steps: 400 samples a rollout, two updates, one episode each
    code = main(["train", "--preset", "medium", "--n-agents", "2", "--maps", MAPS,
                 "--obs", "choice", "--timesteps", "800", "--n-kitchens", "2",
                 "--n-steps", "100", "--batch-size", "200", "--n-epochs", "1", "--hidden", "16",
                 "--quiet", "--out", str(out)])
    assert code == 0
    summary = json.loads((out / "train.json").read_text())
    assert summary["timesteps"] == 800 and summary["config"]["engine"] == "loop"
    assert summary["config"]["obs"] == "choice"
    agent = PPOAgent(str(out / "policy.npz"), seed=0)
    state = new_state(kitchen_rules("medium", "gen:open:test:0", n_agents=2), 0)
    agent.reset(state)
    for _ in range(30):
        joint = agent.act(state)
        assert len(joint) == 2 and all(0 <= a <= 4 for a in joint)  # moves, not slots
        transition(state, joint)

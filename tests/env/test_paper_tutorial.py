"""The paper's drop-in, exactly as good as the docs claim (docs/paper.md).

``gymnasium.make("Overcooked-Plus", **kw)`` builds what ``create_env(**kw)`` builds on each
of the paper's five valid maps (mapE moves a station when it switches and is refused), and
every cell of the paper's ``tutorial.ipynb`` (545659928/Overcooked-Plus) runs here with the
replacements of the attribute table in docs/paper.md: Gymnasium's reset/step, the state
instead of the managers, and ``one_cook(env)`` where the tutorial's SB3 cell calls
``_patch_env(env)``.
"""

from __future__ import annotations

import numpy as np
import pytest

import gymnasium as gym
import ocplus_plan  # noqa: F401  (registers the ids)
from ocplus_plan.env.paper import create_env, one_cook
from ocplus_plan.errors import ConfigError, MapFormatError
from ocplus_plan.render.replay import rules_to_dict
from ocplus_plan.render.rgb import render_frame
from tests.paper_maps import write_paper_maps

VALID = ("mapA", "mapB", "mapC", "mapD", "mapF")


@pytest.mark.parametrize("name", VALID)
def test_make_builds_what_create_env_builds_on_every_valid_paper_map(tmp_path, name):
    path = str(write_paper_maps(tmp_path)[name])
    made = gym.make("Overcooked-Plus", map_name=path, n_agent=1).unwrapped
    created = create_env(map_name=path, n_agent=1).unwrapped
    assert rules_to_dict(made.rules) == rules_to_dict(created.rules)
    assert made.config.obs_radius == created.config.obs_radius == 2  # the paper's default
    obs_made, _ = made.reset(seed=3)
    obs_created, _ = created.reset(seed=3)
    assert np.array_equal(obs_made[0], obs_created[0])
    _, reward, *_ = made.step([4])
    assert np.shape(reward) == (1,)  # one reward per cook, as the paper's loop reads it


def test_make_refuses_the_paper_map_whose_switch_moves_a_station(tmp_path):
    with pytest.raises((ConfigError, MapFormatError), match="mapE|moves|station|cell"):
        gym.make("Overcooked-Plus", map_name=str(write_paper_maps(tmp_path)["mapE"]))


def test_the_tutorials_analysis_cells_run_with_the_documented_replacements():
    env = create_env(preset="medium", n_agent=1)  # cell 3
    obs, info = env.reset(seed=0)  # cell 5: a list entry per cook
    assert obs[0].shape == env.observation_space[0].shape
    state = env.unwrapped.state
    rewards, positions, created, completed = [[]], [[]], {}, []
    done = False
    cook = ocplus_plan.agents.make_controller("greedy", 0)
    cook.reset(state)
    while not done:  # cells 7 and 16: step with one action per cook until done
        obs, reward, terminated, truncated, info = env.step(cook.act(state))
        cook.observe(state, info["events"])
        rewards[0].append(float(reward[0]))  # env.agent[0].reward
        positions[0].append(state.geo.rc(state.agent_pos[0]))  # env.agent[0].loc_log
        for event in info["events"]:  # env.task_Manager.completed_tasks
            if event.kind == "order_new":
                created[event.value] = state.t
            elif event.kind == "delivery":
                completed.append({"task_start_time": created.get(event.value, 0),
                                  "task_end_time": state.t,
                                  "ingredients": state.geo.item_names[event.item]})
        done = terminated or truncated
    assert state.t == env.unwrapped.rules.horizon  # env.env_step
    assert completed and all(c["task_end_time"] > c["task_start_time"] for c in completed)
    assert rewards[0].count(200 - 0.1) + rewards[0].count(200 + 10 - 0.1) >= 1
    rows, cols = env.unwrapped.rules.layout.rows, env.unwrapped.rules.layout.cols
    heatmap = np.zeros((rows, cols))  # env.map_Manager.dimensions
    for cell in positions[0]:
        heatmap[cell] += 1
    screenshot = render_frame(state)  # env.preception_Manager._get_image_state()[0]
    assert heatmap.sum() == len(positions[0]) and screenshot.ndim == 3
    frame = create_env(preset="medium", n_agent=1, render_mode="rgb_array")
    frame.reset(seed=0)
    assert frame.render().shape == screenshot.shape  # cell 14: rgb_array=env.render()


def test_the_tutorials_sb3_cell_runs(tmp_path):
    sb3 = pytest.importorskip("stable_baselines3", reason="the rl extra (stable-baselines3)")
    from stable_baselines3.common.callbacks import CheckpointCallback, EvalCallback
    from stable_baselines3.common.evaluation import evaluate_policy
    from stable_baselines3.common.logger import configure
    from stable_baselines3.common.monitor import Monitor

    env = create_env(preset="easy", n_agent=1, GUI_enable=False, obs_mode="vector",
                     fixed_task=True, max_ing=1, horizon=40)
    env = Monitor(one_cook(env), filename=str(tmp_path / "logs"))  # was _patch_env(env)
    model = sb3.PPO("MlpPolicy", env, n_steps=64, batch_size=32, n_epochs=1, verbose=0,
                    device="cpu")
    model.set_logger(configure(str(tmp_path / "log"), ["csv"]))  # not in the temp root
    checkpoint = CheckpointCallback(save_freq=64, save_path=str(tmp_path / "models"),
                                    name_prefix="ppo_model")
    evaluate = EvalCallback(env, best_model_save_path=str(tmp_path / "best"),
                            log_path=str(tmp_path / "results"), eval_freq=64,
                            n_eval_episodes=1, deterministic=True, render=False)
    model.learn(total_timesteps=128, callback=[checkpoint, evaluate])
    model.save(tmp_path / "ppo_overcooked_model")
    model = sb3.PPO.load(tmp_path / "ppo_overcooked_model", device="cpu")
    obs, _ = env.reset(seed=0)
    action, _ = model.predict(obs, deterministic=True)
    assert env.action_space.contains(int(action))
    mean_reward, _ = evaluate_policy(model, env, n_eval_episodes=1)
    assert np.isfinite(mean_reward)
    assert list((tmp_path / "models").glob("ppo_model_*.zip"))


def test_one_cook_refuses_two_cooks():
    with pytest.raises(ConfigError, match="exactly one cook"):
        one_cook(create_env(preset="hard"))

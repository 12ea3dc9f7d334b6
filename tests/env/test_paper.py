"""The paper's constructor: its keywords with their meaning, its presets through
``create_env``, per-cook rewards, and its tutorial's code path run against this package.

The tutorial path below is written for this test after reading the paper's
``tutorial.ipynb`` and ``humanplayer_example.py`` (545659928/Overcooked-Plus): build the
env with ``create_env(preset="medium", n_agent=1, GUI_enable=True)``, reset, step with a
list of actions, read each cook's reward as ``reward[i]``, render, loop until done. The
only changes are Gymnasium's: ``reset`` returns ``(obs, info)`` and ``step`` five values.
"""

from __future__ import annotations

import os

import gymnasium as gym
import numpy as np
import pytest

import ocplus_plan
from ocplus_plan.agents import make_controller
from ocplus_plan.env.gym_env import OvercookedPlusEnv
from ocplus_plan.env.paper import PAPER_PRESETS, PAPER_TASKS, create_env
from ocplus_plan.errors import ConfigError
from ocplus_plan.render.replay import rules_to_dict
from ocplus_plan.render.window import HUMAN_MARK, WASD
from ocplus_plan.sim import Item
from ocplus_plan.sim.rules import parse_recipe
from tests.paper_maps import write_paper_maps

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # GUI_enable=True opens the window off-screen

PAPER_REWARDS = {"subtask finished": 10, "correct delivery": 200, "wrong delivery": -5,
                 "step penalty": -0.1, "burned penalty": -2}


def test_every_keyword_of_the_papers_constructor_is_accepted_with_its_meaning():
    env = gym.make("Overcooked-Plus", rewardList={**PAPER_REWARDS, "correct delivery": 150},
                   n_agent=2, n_task=3, map_name="mapC", obs_radius=2, obs_mode="image",
                   debug=True, dynamic_map=True, fixed_task=False, task_idx=None,
                   agent_communication=False, GUI_enable=False, human_player=True,
                   min_ing=3, max_ing=4).unwrapped
    rules = env.rules
    assert rules.layout.name == "mapC" and rules.dynamic and rules.n_agents == 2
    assert rules.n_orders == 3 and {len(r) for r in rules.recipes} <= {3, 4}
    assert rules.rewards.correct_delivery == 150 and rules.rewards.step_penalty == -0.1
    assert env.config.mode == "rgb" and env.config.obs_radius == 2
    assert env.render_mode is None and env.config.human_cooks == (0,)
    assert OvercookedPlusEnv("hard", GUI_enable=True).render_mode == "human"
    assert OvercookedPlusEnv("hard", human_player=[1]).config.human_cooks == (1,)
    # debug has no meaning here: accepted, and changes nothing
    plain, debug = OvercookedPlusEnv("hard"), OvercookedPlusEnv("hard", debug=True)
    assert rules_to_dict(plain.rules) == rules_to_dict(debug.rules)
    assert plain.config == debug.config


def test_fixed_task_keeps_the_same_orders_and_task_idx_picks_them_from_the_papers_list():
    env = OvercookedPlusEnv("medium", map="mapB", fixed_task=True, task_idx=[9, 8])
    want = [parse_recipe(PAPER_TASKS[9]), parse_recipe(PAPER_TASKS[8])]
    assert want == [(Item.TOMATO, Item.STEAK), (Item.LETTUCE, Item.STEAK)]
    for seed in (0, 5):
        env.reset(seed=seed)
        assert [o.recipe for o in env.state.orders] == want
    drawn = OvercookedPlusEnv("easy", fixed_task=True, n_task=2)
    orders = set()
    for seed in range(4):
        drawn.reset(seed=seed)
        orders.add(tuple(o.recipe for o in drawn.state.orders))
    assert len(orders) == 1 and len(orders.pop()) == 2


@pytest.mark.parametrize("kw, words", [
    ({"task_idx": [0]}, "only valid with fixed_task=True"),
    ({"fixed_task": True, "task_idx": [15]}, "not an index"),
    ({"fixed_task": True, "task_idx": [7]}, "cannot be made"),  # steak: easy_open has none
    ({"min_ing": 3, "max_ing": 2}, "min_ing=3 is above max_ing=2"),
    ({"n_task": 2, "n_orders": 3}, "disagree"),
    ({"obs_mode": "vector", "mode": "rgb"}, "disagree"),
    ({"human_player": "me"}, "human_player"),
    ({"human_player": 2}, "human_player"),
])
def test_bad_paper_keywords_name_the_problem(kw, words):
    with pytest.raises(ConfigError, match=words):
        OvercookedPlusEnv("easy", **kw)


def test_create_env_builds_the_papers_presets_on_its_maps():
    expected = {"easy": ("mapA", 1, False), "medium": ("mapB", 1, False), "hard": ("mapC", 2, True)}
    for preset, (map_name, n, dynamic) in expected.items():
        env = create_env(preset=preset)
        rules = env.unwrapped.rules
        assert (rules.preset, rules.layout.name, rules.n_agents, rules.dynamic) == (
            preset, map_name, n, dynamic)
        assert env.unwrapped.config.obs_radius == PAPER_PRESETS[preset]["obs_radius"] == 2
        env.close()
    override = create_env(preset="easy", n_agent=2, obs_radius=0).unwrapped
    assert override.rules.n_agents == 2 and override.config.obs_radius == 0
    with pytest.raises(ConfigError, match="paper's presets"):
        create_env(preset="expert")


def test_create_env_without_a_preset_runs_any_paper_map_as_the_paper_does(tmp_path):
    paths = write_paper_maps(tmp_path)
    # the tutorial's "settings equivalent to preset='medium'"
    env = create_env(map_name="mapB", rewardList=PAPER_REWARDS, n_agent=1, obs_mode="vector",
                     obs_radius=2, dynamic_map=False, agent_communication=False).unwrapped
    assert (env.rules.preset, env.rules.layout.name, env.rules.dynamic) == ("medium", "mapB", False)
    f = create_env(map_name=str(paths["mapF"]), n_agent=2).unwrapped  # sink, pan; static
    assert (f.rules.preset, f.rules.dynamic, f.rules.n_agents) == ("hard", False, 2)
    d = create_env(map_name=str(paths["mapD"]), n_agent=1).unwrapped  # one board, one tomato
    assert d.rules.preset == "easy"
    c = create_env(n_agent=2).unwrapped  # the paper constructor's default map is mapC
    assert c.rules.layout.name == "mapC" and c.rules.dynamic


def test_per_agent_rewards_are_one_float_per_cook_and_the_team_scope_sums_them():
    env = create_env(preset="hard")
    env.reset(seed=0)
    _, reward, _, _, info = env.step([4, 4])
    assert isinstance(reward, np.ndarray) and reward.shape == (2,)
    assert reward.tolist() == info["rewards"] == pytest.approx([-0.1, -0.1])
    team = create_env(preset="hard", reward_scope="team")
    team.reset(seed=0)
    assert team.step([4, 4])[1] == pytest.approx(-0.2)
    with pytest.raises(ConfigError, match="reward_scope"):
        OvercookedPlusEnv("hard", reward_scope="mine")


def test_the_papers_tutorial_code_path_runs_against_this_package():
    env = ocplus_plan.create_env(preset="medium", n_agent=1, GUI_enable=True,
                                 human_player=True)
    obs, info = env.reset(seed=0)
    assert len(obs) == 1 and obs[0].shape == env.observation_space[0].shape
    obs, reward, terminated, truncated, info = env.step([0])  # "right"
    assert reward[0] == pytest.approx(-0.1) and not (terminated or truncated)
    assert env.render() is None  # GUI_enable: the window was drawn (off-screen here)
    window = env.unwrapped._window
    assert (window.pixels() == HUMAN_MARK).all(axis=2).any()  # the player's cook is marked

    # the human loop: keys -> actions -> step([action]), until the episode is done; a
    # scripted cook stands in for the keyboard so that a dish gets served
    key_of = {int(action): key for key, action in WASD.items()}
    cook = make_controller("greedy", 0)
    cook.reset(env.unwrapped.state)
    history = [[float(reward[0])]]  # the tutorial plots each cook's reward over the steps
    done = False
    while not done:
        action = WASD[key_of[cook.act(env.unwrapped.state)[0]]]
        obs, reward, terminated, truncated, info = env.step([int(action)])
        cook.observe(env.unwrapped.state, info["events"])
        history[0].append(float(reward[0]))
        done = terminated or truncated
    env.close()
    assert len(history[0]) == env.unwrapped.rules.horizon
    served = env.unwrapped.state.stats["dishes_served"]
    assert served >= 1 and history[0].count(200 - 0.1) == served

"""The Gymnasium envs: conformance on every registered id and mode, keywords, spaces,
determinism, errors and rendering."""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.error import ResetNeeded
from gymnasium.utils.env_checker import check_env

import ocplus_plan.env as ocenv
from ocplus_plan.env.gym_env import OvercookedPlusEnv, OvercookedPlusSingleEnv, StateSpace
from ocplus_plan.errors import ConfigError, DependencyNotInstalled, InvalidActionError
from ocplus_plan.render import TILE_SIZE
from ocplus_plan.sim import State

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")  # check_env also tries render_mode="human"
IDS = list(ocenv.REGISTRY)
MODES = ["vector", "rgb", "symbolic"]


@pytest.mark.parametrize("env_id", IDS)
@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("comm", [False, True], ids=["nocomm", "comm"])
def test_check_env_passes_without_warnings(env_id, mode, comm):
    extra = {"agent_communication": True, "comm_failure_rate": 0.2, "comm_range": 3,
             "obs_radius": 2} if comm else {}
    if env_id == "Overcooked-Plus":  # the paper's id gives one reward per cook by default;
        extra["reward_scope"] = "team"  # Gymnasium's checker wants the scalar one
    env = gym.make(env_id, mode=mode, **extra)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped)
    ours = [str(w.message) for w in caught if "pygame" not in str(w.message).lower()]
    assert ours == []
    env.close()


def test_paper_keyword_names_map_onto_the_rules():
    env = gym.make("Overcooked-Plus", map_name="hard_switch", dynamic_map=False, n_agent=2,
                   rewardList={"subtask finished": 7, "correct delivery": 100,
                               "step penalty": 0.0},
                   agent_communication=True, obs_radius=1, mode="image", horizon=50).unwrapped
    rules = env.rules
    assert rules.layout.name == "hard_switch" and not rules.dynamic and rules.n_agents == 2
    assert rules.rewards.subtask_finished == 7 and rules.rewards.correct_delivery == 100
    assert rules.rewards.step_penalty == 0.0 and rules.horizon == 50
    assert env.config.mode == "rgb" and env.core.comm is not None
    assert env.observation_space[0]["obs"].shape == (3 * TILE_SIZE, 3 * TILE_SIZE, 3)
    assert env.observation_space[0]["messages"].nvec.tolist() == [9]
    assert env.action_space.nvec.tolist() == [5, 8, 5, 8]


def test_our_keyword_names_work_too_and_conflicts_are_refused():
    env = OvercookedPlusEnv("medium", map="medium_kitchen", n_agents=2, rewards={"wrong_delivery": -1})
    assert env.rules.n_agents == 2 and env.rules.rewards.wrong_delivery == -1
    with pytest.raises(ConfigError, match="disagree"):
        OvercookedPlusEnv("hard", n_agent=2, n_agents=3)
    with pytest.raises(ConfigError, match="mode"):
        OvercookedPlusEnv("hard", mode="pixels")
    with pytest.raises(ConfigError, match="agent_communication"):
        OvercookedPlusEnv("hard", comm_range=2)
    with pytest.raises(ConfigError, match="unknown rule parameter"):
        OvercookedPlusEnv("hard", horizn=10)
    with pytest.raises(ConfigError, match="render_mode"):
        OvercookedPlusEnv("hard", render_mode="window")
    with pytest.raises(ConfigError, match="reward"):
        OvercookedPlusEnv("hard", rewardList={"tip": 3})


@pytest.mark.parametrize("n_agents,radius", [(1, 0), (2, 0), (2, 3), (3, 1)])
def test_observation_space_states_the_exact_shape(n_agents, radius):
    for mode in ("vector", "rgb"):
        env = OvercookedPlusEnv("hard", n_agents=n_agents, mode=mode, obs_radius=radius)
        obs, _ = env.reset(seed=1)
        assert isinstance(env.observation_space, gym.spaces.Tuple)
        assert len(obs) == len(env.observation_space) == n_agents
        for o, space in zip(obs, env.observation_space):
            assert o.shape == space.shape and o.dtype == space.dtype and o in space
        if mode == "rgb":
            side = (2 * radius + 1) * TILE_SIZE if radius else None
            shape = (side, side, 3) if side else (9 * TILE_SIZE, 9 * TILE_SIZE, 3)
            assert env.observation_space[0].shape == shape
    env = OvercookedPlusEnv("hard", mode="symbolic")
    obs, _ = env.reset(seed=1)
    assert isinstance(env.observation_space[0], StateSpace) and isinstance(obs[0], State)


def _trajectory(env, seed: int, steps: int) -> list:
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    env.action_space.seed(seed)
    out = [obs]
    for _ in range(steps):
        obs, reward, term, trunc, info = env.step(env.action_space.sample())
        out.append((obs, reward, info["rewards"], [e.kind for e in info["events"]]))
        if term or trunc:
            obs, _ = env.reset(seed=int(rng.integers(1000)))
            out.append(obs)
    return out


@pytest.mark.parametrize("mode", MODES)
def test_two_envs_with_the_same_seed_give_identical_trajectories(mode):
    kw = {"mode": mode, "agent_communication": True, "comm_failure_rate": 0.3, "horizon": 60}
    a = _trajectory(OvercookedPlusEnv("hard", **kw), 11, 150)
    b = _trajectory(OvercookedPlusEnv("hard", **kw), 11, 150)
    assert gym.utils.env_checker.data_equivalence(a, b, exact=True)
    c = _trajectory(OvercookedPlusEnv("hard", **kw), 12, 150)
    assert not gym.utils.env_checker.data_equivalence(a, c, exact=True)


def test_unseeded_resets_follow_the_first_seed():
    env1, env2 = OvercookedPlusEnv("hard"), OvercookedPlusEnv("hard")
    env1.reset(seed=3)
    env2.reset(seed=3)
    seeds1 = [env1.reset()[1]["episode_seed"] for _ in range(3)]
    seeds2 = [env2.reset()[1]["episode_seed"] for _ in range(3)]
    assert seeds1 == seeds2 and len(set(seeds1)) == 3
    assert env1.reset(seed=42)[1]["episode_seed"] == 42


def test_rewards_team_sum_and_per_agent_info():
    env = OvercookedPlusEnv("hard", n_agents=2)
    env.reset(seed=0)
    _, reward, _, _, info = env.step([4, 4])
    assert info["rewards"] == [-0.1, -0.1] and reward == pytest.approx(-0.2)
    shared = OvercookedPlusEnv("hard", n_agents=2, reward_mode="shared")
    shared.reset(seed=0)
    _, reward, _, _, info = shared.step([4, 4])
    assert info["rewards"] == [pytest.approx(-0.2)] * 2 and reward == pytest.approx(-0.2)


def test_episode_truncates_at_the_horizon_then_needs_a_reset():
    env = OvercookedPlusEnv("easy", horizon=5)
    env.reset(seed=0)
    flags = [env.step([4])[3] for _ in range(5)]
    assert flags == [False] * 4 + [True]
    with pytest.raises(ResetNeeded):
        env.step([4])
    env.reset()
    env.step([4])


def test_bad_actions_are_invalid_action_errors():
    env = OvercookedPlusEnv("hard", n_agents=2)
    env.reset(seed=0)
    with pytest.raises(InvalidActionError, match="expected 2 moves"):
        env.step([0])
    with pytest.raises(InvalidActionError, match="0 right"):
        env.step([7, 0])
    comm = OvercookedPlusEnv("hard", n_agents=2, agent_communication=True, comm_vocab=4)
    comm.reset(seed=0)
    with pytest.raises(InvalidActionError, match="move, token"):
        comm.step([0, 0])
    with pytest.raises(InvalidActionError, match="vocabulary"):
        comm.step([0, 9, 0, 0])


def test_render_modes():
    assert OvercookedPlusEnv("hard").render() is None
    env = OvercookedPlusEnv("hard", render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (9 * TILE_SIZE, 9 * TILE_SIZE, 3) and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 10


def test_human_mode_without_the_window_module_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "ocplus_plan.render.window", None)  # import fails
    env = OvercookedPlusEnv("hard", GUI=True)
    assert env.render_mode == "human"
    with pytest.raises(DependencyNotInstalled, match=r"ocplus-plan\[gui\]"):
        env.reset(seed=0)


def test_single_agent_view_with_default_and_supplied_partners():
    env = gym.make("OvercookedPlusSingle-v0", n_agent=2).unwrapped
    assert env.action_space == gym.spaces.Discrete(5)
    obs, _ = env.reset(seed=0)
    start = list(env.state.agent_pos)
    for _ in range(3):
        obs, reward, *_ , info = env.step(2)
    assert env.state.agent_pos[1] == start[1]  # the default partner stays
    assert obs.shape == env.observation_space.shape and len(info["rewards"]) == 2

    calls = []

    class Mover:
        def reset(self, state, agent_ids):
            calls.append(tuple(agent_ids))

        def act(self, state):
            return [3]  # up

    env = OvercookedPlusSingleEnv("hard", partner=Mover(), reward_scope="own")
    env.reset(seed=0)
    before = env.state.agent_rc(1)
    _, reward, *_ = env.step(4)
    assert calls == [(1,)] and env.state.agent_rc(1) == (before[0] - 1, before[1])
    assert reward == pytest.approx(-0.1)
    with pytest.raises(ConfigError, match="partner"):
        OvercookedPlusSingleEnv("hard", partner=3)
    with pytest.raises(ConfigError, match="agent_id"):
        OvercookedPlusSingleEnv("hard", agent_id=5)


def test_single_agent_view_passes_stable_baselines3_check():
    sb3 = pytest.importorskip("stable_baselines3", reason="stable-baselines3 not installed "
                              "(pip install 'ocplus-plan[rl]')")
    from stable_baselines3.common.env_checker import check_env as sb3_check

    sb3_check(OvercookedPlusSingleEnv("hard", n_agents=2), warn=True)
    sb3_check(OvercookedPlusSingleEnv("hard", n_agents=2, agent_communication=True), warn=True)
    assert sb3


def test_importing_the_env_loads_no_heavy_package():
    code = ("import sys, gymnasium as gym, ocplus_plan.env; "
            "e = gym.make('OvercookedPlus-v0', mode='rgb'); e.reset(seed=0); "
            "e.step(e.action_space.sample()); print(' '.join(sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = {m.split(".")[0] for m in out.stdout.split()}
    assert not loaded & {"unified_planning", "pygame", "torch", "matplotlib", "pettingzoo"}


@pytest.mark.parametrize("code", [
    # gymnasium imports the package named before the colon: no import of ours first
    "import gymnasium as gym; e = gym.make('ocplus_plan:OvercookedPlus-v0')",
    # the package import alone registers every id, whatever the import order
    ("import ocplus_plan, gymnasium as gym; e = gym.make('OvercookedPlus-v0'); "
     "gym.make('Overcooked-Plus'); gym.make('OvercookedPlusSingle-v0')"),
    "import gymnasium as gym, ocplus_plan; e = gym.make('OvercookedPlus-v0')",
])
def test_the_ids_are_registered_in_a_fresh_interpreter(code, tmp_path):
    code += "; obs, info = e.reset(seed=0); print(e.unwrapped.rules.preset, len(obs))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split() == ["hard", "2"]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="display variables are X11/Wayland")
def test_check_env_without_a_display_draws_off_screen_and_prints_no_sdl_errors(tmp_path):
    code = ("import gymnasium as gym, ocplus_plan; "
            "from gymnasium.utils.env_checker import check_env; "
            "check_env(gym.make('OvercookedPlus-v0').unwrapped); print('checked')")
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, env=env, timeout=120, check=False)
    assert out.returncode == 0 and out.stdout.split() == ["checked"], out.stderr[-2000:]
    assert "XDG_RUNTIME_DIR" not in out.stderr and "error:" not in out.stderr, out.stderr
    assert out.stderr.count("drawn off-screen") == 1  # one clear warning instead


@pytest.mark.parametrize("comm", [False, True], ids=["nocomm", "comm"])
def test_check_env_passes_in_text_mode(comm):
    env = OvercookedPlusEnv("hard", mode="text", agent_communication=comm)
    check_env(env)
    obs, _ = env.reset(seed=0)
    first = obs[0]["obs"] if comm else obs[0]
    assert first.startswith("You are cook 0")


def test_text_mode_with_a_window_radius_is_refused():
    with pytest.raises(ConfigError, match="obs_radius must be 0"):
        OvercookedPlusEnv("hard", mode="text", obs_radius=2)

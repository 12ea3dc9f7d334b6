"""The paper's constructor: its keywords, its task list, its presets and ``create_env``.

Scripts written for the published Overcooked-Plus code (545659928/Overcooked-Plus) build the
env with ``create_env(preset="medium", n_agent=1, GUI_enable=True)`` or
``gym.make("Overcooked-Plus", rewardList=..., n_agent=..., ...)``. Every keyword of that
constructor is accepted here, with its meaning:

==================  =====================================================================
paper keyword       meaning here
==================  =====================================================================
``rewardList``      ``rewards``; keys as the paper spells them (``"correct delivery"``)
``n_agent``         ``n_agents``
``map_name``        ``map`` (a registered name, a YAML path, or a dict)
``dynamic_map``     ``dynamic`` (``None``: the preset's; ``create_env``: the map's)
``obs_mode``        ``mode``: ``"vector"`` or ``"image"`` (= ``"rgb"``)
``obs_radius``      ``obs_radius`` (0 = the whole map)
``GUI_enable``      ``render_mode="human"`` (the pygame window, extra ``gui``)
``human_player``    the cooks a person plays (``True`` = cook 0, or indices): the window
                    marks them "YOU"; the keyboard loop is the caller's, as in the paper
``agent_communication``  as here (one token per cook and step)
``n_task``          ``n_orders``: orders open at once
``fixed_task``      ``fixed_orders=True``: the same orders every episode; a served order
                    comes back (the paper keeps it open)
``task_idx``        with ``fixed_task``: the orders are these entries of the paper's task
                    list (:data:`PAPER_TASKS`)
``min_ing``, ``max_ing``  ``recipe_sizes = range(min_ing, max_ing + 1)`` (the preset's steak
                    rule still applies; sizes the map cannot make are simply absent)
``debug``           accepted and ignored: it switches development output in the paper's
                    code and has no counterpart here
==================  =====================================================================

What differs is Gymnasium's API: ``reset()`` returns ``(obs, info)`` and ``step()`` returns
``(obs, reward, terminated, truncated, info)`` (the paper's gym returns ``obs`` and a 4-tuple
with ``done``). ``create_env`` returns per-cook rewards (``reward[i]``) as the paper's loop
reads them; pass ``reward_scope="team"`` for the team's float.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium
import numpy as np

from ..errors import ConfigError
from ..sim import PRESETS, load_kitchen
from ..sim.codes import Cell
from ..sim.maps import Layout

#: The paper's task list in its order (``task_idx`` indexes it), as recipes.
PAPER_TASKS: tuple[str, ...] = (
    "tomato", "lettuce", "onion", "lettuce+tomato", "onion+tomato", "lettuce+onion",
    "lettuce+onion+tomato", "steak", "steak+lettuce", "steak+tomato", "steak+onion",
    "steak+lettuce+tomato", "steak+lettuce+onion", "steak+tomato+onion",
    "steak+lettuce+tomato+onion",
)

#: The paper's ``create_env`` presets (its ``env_creater.presets``), keyword for keyword.
PAPER_PRESETS: dict[str, dict[str, Any]] = {
    "easy": {"map_name": "mapA", "dynamic_map": False, "n_agent": 1,
             "agent_communication": False, "obs_radius": 2, "obs_mode": "vector",
             "GUI_enable": False},
    "medium": {"map_name": "mapB", "dynamic_map": False, "n_agent": 1,
               "agent_communication": False, "obs_radius": 2, "obs_mode": "vector",
               "GUI_enable": False},
    "hard": {"map_name": "mapC", "dynamic_map": True, "n_agent": 2,
             "agent_communication": False, "obs_radius": 2, "obs_mode": "vector",
             "GUI_enable": False},
}

#: The paper constructor's defaults where they differ from the registered env's.
PAPER_DEFAULTS: dict[str, Any] = {"map_name": "mapC", "obs_radius": 2}

#: Paper keywords translated by :func:`translate_paper_keywords` (the others,
#: ``rewardList``, ``n_agent``, ``map_name``, ``dynamic_map``, ``obs_mode`` and
#: ``GUI_enable``, are aliases handled by ``parse_env_kwargs``).
PAPER_ONLY_KEYWORDS = ("debug", "n_task", "fixed_task", "task_idx", "min_ing", "max_ing",
                       "human_player")


def _pop_int(kw: dict[str, Any], name: str, default: int) -> int:
    value = kw.pop(name, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ConfigError(f"{name} must be a positive integer, got {value!r}")
    return value


def _fixed_orders(kw: dict[str, Any]) -> Any:
    """``fixed_task`` / ``task_idx`` -> the value of ``fixed_orders`` (None: not fixed)."""
    fixed_task = kw.pop("fixed_task", False)
    task_idx = kw.pop("task_idx", None)
    if task_idx is not None and not fixed_task:
        raise ConfigError("task_idx is only valid with fixed_task=True (as in the paper's code)")
    if not fixed_task:
        return None
    if task_idx is None:
        return True
    if isinstance(task_idx, (str, bytes)) or not isinstance(task_idx, Sequence) or not task_idx:
        raise ConfigError(f"task_idx must be a non-empty list of task indices, got {task_idx!r}")
    bad = [i for i in task_idx if isinstance(i, bool) or not isinstance(i, int)
           or not 0 <= i < len(PAPER_TASKS)]
    if bad:
        listing = ", ".join(f"{i}: {t}" for i, t in enumerate(PAPER_TASKS))
        raise ConfigError(f"task_idx {bad}: not an index of the paper's task list ({listing})")
    return [PAPER_TASKS[i] for i in task_idx]


def human_cooks(value: Any) -> tuple[int, ...]:
    """``human_player``: ``False``/``None`` -> (), ``True`` -> (0,), ``1`` -> (1,),
    ``[0, 1]`` -> (0, 1)."""
    if value is None or value is False:
        return ()
    if value is True:
        return (0,)
    cooks = [value] if isinstance(value, int) else value
    if (isinstance(cooks, (str, bytes)) or not isinstance(cooks, Sequence)
            or any(isinstance(c, bool) or not isinstance(c, int) or c < 0 for c in cooks)
            or len(set(cooks)) != len(cooks)):
        raise ConfigError(f"human_player must be True/False, a cook index or a list of distinct "
                          f"indices, got {value!r}")
    return tuple(cooks)


def translate_paper_keywords(kw: dict[str, Any]) -> tuple[dict[str, Any], tuple[int, ...]]:
    """Replace the paper-only keywords in ``kw`` by ours; return it and the human cooks."""
    kw = dict(kw)
    kw.pop("debug", None)
    humans = human_cooks(kw.pop("human_player", None))
    if "n_task" in kw:
        n_task = kw.pop("n_task")
        if "n_orders" in kw and kw["n_orders"] != n_task:
            raise ConfigError(f"n_orders={kw['n_orders']!r} and n_task={n_task!r} disagree; "
                              "pass only one of them")
        kw["n_orders"] = n_task
    fixed = _fixed_orders(kw)
    if fixed is not None:
        if "fixed_orders" in kw:
            raise ConfigError("fixed_orders and fixed_task / task_idx both given; pass one")
        kw["fixed_orders"] = fixed
    if "min_ing" in kw or "max_ing" in kw:
        lo, hi = _pop_int(kw, "min_ing", 1), _pop_int(kw, "max_ing", 4)
        if lo > hi:
            raise ConfigError(f"min_ing={lo} is above max_ing={hi}")
        if "recipe_sizes" in kw:
            raise ConfigError("recipe_sizes and min_ing / max_ing both given; pass one")
        kw["recipe_sizes"] = tuple(range(lo, hi + 1))
    return kw, humans


def preset_for_map(layout: Layout) -> str:
    """The hardest of our presets whose stations ``layout`` has (the paper's env has no
    preset: every kitchen it can run is one of ours)."""
    for name in reversed(list(PRESETS)):
        preset = PRESETS[name]
        needs = set(preset.stations) | ({Cell.SINK} if preset.dirty_plates else set())
        if all(layout.cells_of(c) for c in needs):
            return name
    raise ConfigError(f"map {layout.name!r} has none of the stations a preset needs "
                      "(cutting boards at least)")


def paper_config(kwargs: dict[str, Any], preset: str | None = None) -> dict[str, Any]:
    """The keywords the paper's constructor means by ``kwargs`` (and its ``create_env``
    preset, if any), as this package's env keywords.

    With a paper preset: that preset's keywords (``easy`` mapA, ``medium`` mapB, ``hard``
    mapC), updated with ``kwargs``, on our preset of the same name. Without one: the paper
    constructor's defaults (``map_name="mapC"``, ``obs_radius=2``), the hardest of our
    presets whose stations the map has (unless ``preset`` is among ``kwargs``), and the
    map's own switching (unless ``dynamic_map`` says otherwise). Rewards are per cook
    (``reward_scope="per_agent"``) unless ``reward_scope`` is given.
    """
    if preset is not None and preset not in PAPER_PRESETS:
        raise ConfigError(f"unknown preset {preset!r}; the paper's presets are "
                          f"{', '.join(PAPER_PRESETS)}")
    config = {**(PAPER_PRESETS[preset] if preset else PAPER_DEFAULTS), **kwargs}
    if preset is not None:
        config.setdefault("preset", preset)
    elif "preset" not in config:
        layout = load_kitchen(config.get("map_name", config.get("map")))
        config["preset"] = preset_for_map(layout)
        if config.get("dynamic_map", config.get("dynamic")) is None:
            config["dynamic_map"] = layout.is_dynamic
    config.setdefault("reward_scope", "per_agent")
    return config


def create_env(preset: str | None = None, **kwargs: Any) -> Any:
    """The paper's ``create_env``: a preset of its own (``easy`` mapA, ``medium`` mapB,
    ``hard`` mapC, as in its ``env_creater``) updated with ``kwargs``, or ``kwargs`` alone
    (then what ``gymnasium.make("Overcooked-Plus", **kwargs)`` builds: see
    :func:`paper_config` and :func:`ocplus_plan.env.gym_env.make_paper_env`).

    Returns a Gymnasium env whose ``step`` gives one reward per cook
    (``reward_scope="per_agent"``, the paper's loop reads ``reward[i]``); pass
    ``reward_scope="team"`` for the team's sum as a float.
    """
    return gymnasium.make("Overcooked-Plus", **paper_config(kwargs, preset))


class OneCook(gymnasium.Wrapper):
    """A one-cook paper env as a plain single-agent Gymnasium env: the cook's own ``Box``
    observation, a ``Discrete`` action and a float reward instead of one-entry tuples, which
    is what stable-baselines3's ``PPO("MlpPolicy", ...)`` takes (the part of the paper
    tutorial's ``_patch_env(env)`` that is still needed). Two or more cooks are refused: use
    ``OvercookedPlusSingle-v0`` (one learner, the others driven by a partner) or
    ``ocplus train``."""

    def __init__(self, env: Any) -> None:
        space = env.observation_space
        n = len(space) if isinstance(space, gymnasium.spaces.Tuple) else 0
        if n != 1:
            raise ConfigError(
                f"one_cook needs an env with exactly one cook (n_agent=1), got "
                f"{n or 'a non-tuple observation space'}; for more cooks use "
                "gymnasium.make('OvercookedPlusSingle-v0', ...) or ocplus train")
        super().__init__(env)
        self.observation_space = space[0]
        self.action_space = gymnasium.spaces.Discrete(int(env.action_space.nvec[0]))

    def reset(self, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        return obs[0], info

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = self.env.step([int(action)])
        return obs[0], float(np.sum(reward)), terminated, truncated, info


def one_cook(env: Any) -> OneCook:
    """``env`` (one cook, from ``create_env`` or ``gymnasium.make("Overcooked-Plus", ...)``)
    as a single-agent env for stable-baselines3 and the like (see :class:`OneCook`)."""
    return OneCook(env)


__all__ = ["PAPER_PRESETS", "PAPER_TASKS", "OneCook", "create_env", "human_cooks",
           "one_cook", "paper_config", "preset_for_map",
           "translate_paper_keywords"]

"""What the Gymnasium and PettingZoo envs share: keyword parsing and the kitchen core.

:func:`parse_env_kwargs` maps the paper's keyword names (``map_name``, ``dynamic_map``,
``rewardList``, ``n_agent``, ``agent_communication``, ``GUI`` / ``GUI_enable``, ``obs_mode``
and the others of :mod:`.paper`) and ours onto :func:`ocplus_plan.sim.make_rules` plus an
:class:`EnvConfig`. :class:`KitchenCore` owns
one episode: the simulator state, the encoder of the chosen mode and the message
channel, and turns ``(moves, tokens)`` into observations. No gymnasium import here.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ConfigError, InvalidActionError
from ..sim import Rules, State, StepResult, make_rules, new_state, transition
from ..sim.observe import VectorEncoder, snapshot
from ..sim.fast.observe_incremental import IncrementalEncoder
from ..sim.maps import MAX_GRID_SIDE

#: the largest ``obs_radius``: a window of radius 64 already covers the largest map
MAX_OBS_RADIUS = MAX_GRID_SIDE
#: actions are whole numbers; anything this large is no action of any kind
_ACTION_BOUND = 2**31
from ..sim.observe_text import text_observations
from .comm import CommChannel, CommConfig
from .paper import PAPER_ONLY_KEYWORDS, translate_paper_keywords

MODES = ("vector", "rgb", "symbolic", "text")
#: accepted spellings of a mode (gym-macro-overcooked calls the picture mode "image")
MODE_ALIASES = {"vector": "vector", "rgb": "rgb", "image": "rgb", "symbolic": "symbolic",
                "text": "text"}
RENDER_MODES = ("human", "rgb_array")
#: keywords the env itself understands (everything else goes to ``make_rules``)
ENV_KEYWORDS = (
    "preset", "map_name", "map", "dynamic_map", "dynamic", "rewardList", "rewards", "n_agent",
    "n_agents", "agent_communication", "comm_vocab", "comm_range", "comm_failure_rate",
    "comm_delay", "obs_radius", "mode", "obs_mode", "GUI", "GUI_enable", "render_mode",
    *PAPER_ONLY_KEYWORDS,
)


@dataclass(frozen=True)
class EnvConfig:
    """Learner-side options (the rules themselves live in :class:`Rules`)."""

    mode: str = "vector"
    obs_radius: int = 0
    comm: CommConfig | None = None
    render_mode: str | None = None
    #: cooks a person plays (the paper's ``human_player``): the window marks them
    human_cooks: tuple[int, ...] = ()


def _alias(kwargs: dict[str, Any], ours: str, paper: str, default: Any) -> Any:
    """The value given under either name; an error when both are given and differ."""
    a, b = kwargs.pop(ours, None), kwargs.pop(paper, None)
    if a is not None and b is not None and a != b:
        raise ConfigError(f"{ours}={a!r} and {paper}={b!r} disagree; pass only one of them")
    return default if a is None and b is None else (a if a is not None else b)


def parse_env_kwargs(preset: str = "hard", **kwargs: Any) -> tuple[Rules, EnvConfig]:
    """Rules and env options from the env's keyword arguments (see the env docstring).

    Every keyword that is not an env option is passed to ``make_rules`` (so any rule
    parameter, e.g. ``horizon`` or ``order_time_limit``, can be overridden); unknown
    names fail there with the list of known ones.
    """
    kw, humans = translate_paper_keywords(kwargs)
    map_ = _alias(kw, "map", "map_name", None)
    dynamic = _alias(kw, "dynamic", "dynamic_map", None)
    rewards = _alias(kw, "rewards", "rewardList", None)  # the paper's keys: Rewards reads them
    n_agents = _alias(kw, "n_agents", "n_agent", None)
    comm_on = bool(kw.pop("agent_communication", False))
    comm_kw = {k: kw.pop(f"comm_{k}") for k in ("vocab", "range", "failure_rate", "delay")
               if f"comm_{k}" in kw}
    if comm_kw and not comm_on:
        raise ConfigError(
            f"{', '.join('comm_' + k for k in comm_kw)} given without agent_communication=True"
        )
    gui = bool(_alias(kw, "GUI", "GUI_enable", False))
    render_mode = kw.pop("render_mode", None)
    if gui:
        if render_mode not in (None, "human"):
            raise ConfigError(f"GUI=True asks for render_mode='human' but render_mode={render_mode!r}")
        render_mode = "human"
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise ConfigError(f"render_mode must be None, 'human' or 'rgb_array', got {render_mode!r}")
    mode = _alias(kw, "mode", "obs_mode", "vector")
    if mode not in MODE_ALIASES:
        raise ConfigError(f"mode must be one of {', '.join(MODES)} ('image' = 'rgb'), got {mode!r}")
    obs_radius = kw.pop("obs_radius", 0)
    if isinstance(obs_radius, bool) or not isinstance(obs_radius, int) \
            or not 0 <= obs_radius <= MAX_OBS_RADIUS:
        raise ConfigError(f"obs_radius must be an integer from 0 (whole map) to "
                          f"{MAX_OBS_RADIUS} (a map's largest side), got {obs_radius!r}")
    if MODE_ALIASES[mode] == "text" and obs_radius:
        raise ConfigError(f"mode='text' describes the whole kitchen; obs_radius must be 0, "
                          f"got {obs_radius}")

    overrides = dict(kw)
    if map_ is not None:
        overrides["map"] = map_
    if dynamic is not None:
        overrides["dynamic"] = bool(dynamic)
    if rewards is not None:
        overrides["rewards"] = rewards
    if n_agents is not None:
        overrides["n_agents"] = n_agents
    try:
        rules = make_rules(preset, **overrides)
    except ConfigError as exc:
        if "unknown rule parameter" in str(exc):
            raise ConfigError(f"{exc}; env keywords: {', '.join(ENV_KEYWORDS)}") from None
        raise
    comm = CommConfig(**comm_kw) if comm_on else None
    if comm is not None and rules.n_agents < 2:
        raise ConfigError("agent_communication needs at least two agents (n_agents >= 2)")
    if any(h >= rules.n_agents for h in humans):
        raise ConfigError(f"human_player {list(humans)}: the kitchen has {rules.n_agents} "
                          f"cooks (0..{rules.n_agents - 1})")
    return rules, EnvConfig(MODE_ALIASES[mode], obs_radius, comm, render_mode, humans)


class KitchenCore:
    """One kitchen episode plus its encoder and message channel."""

    def __init__(self, rules: Rules, config: EnvConfig) -> None:
        self.rules = rules
        self.config = config
        self.n_agents = n = rules.n_agents
        self.comm = CommChannel(config.comm, n, rules.layout.cols) if config.comm else None
        vocab = config.comm.vocab if config.comm else 0
        self.vector = VectorEncoder(rules, config.obs_radius, vocab) if config.mode == "vector" \
            else None
        # the env's stream of states is encoded incrementally (same values as
        # self.vector.encode, which stays the from-scratch reference)
        self._live = IncrementalEncoder(self.vector) if self.vector is not None else None
        # the rows of an (n, size) array as n arrays (itemgetter: no Python-level loop)
        self._rows = operator.itemgetter(*range(n)) if n > 1 else lambda obs: (obs[0],)
        self.rgb: Any = None
        if config.mode == "rgb":
            from ..render.rgb import RgbEncoder  # numpy only; kept local for import speed

            self.rgb = RgbEncoder(rules, config.obs_radius)
        self.state: State = new_state(rules, 0)
        self.received = np.full((n, max(0, n - 1)), -1, np.int64)
        self.episode_seed = 0

    def reset(self, episode_seed: int) -> None:
        self.episode_seed = int(episode_seed)
        self.state = new_state(self.rules, self.episode_seed)
        if self.comm is not None:
            self.received = self.comm.reset(self.episode_seed)

    def step(self, moves: Sequence[int], tokens: Sequence[int] | None) -> StepResult:
        result = transition(self.state, moves)
        if self.comm is not None and tokens is not None:
            self.received = self.comm.exchange(tokens, self.state.agent_pos)
        return result

    def observe(self) -> Sequence[Any]:
        """One observation per agent (a tuple or a list). ``vector``: rows of an ``(n,
        size)`` float32 array (received tokens are among the features), encoded
        incrementally; ``rgb``: ``(H, W, 3)`` uint8 images; ``symbolic``: one shared
        :class:`~ocplus_plan.sim.observe.StateSnapshot`; ``text``: one string per cook
        (:func:`~ocplus_plan.sim.observe_text.text_observation`). With
        communication, rgb, symbolic and text observations become ``{"obs": ..., "messages":
        tokens}`` with one token per other agent (``comm_vocab`` = nothing received)."""
        if self._live is not None:
            obs = self._live.encode(self.state, self.received if self.comm else None)
            return self._rows(obs)
        if self.rgb is not None:
            obs = list(self.rgb.encode(self.state))
        elif self.config.mode == "text":
            obs = text_observations(self.state)
        else:
            obs = [snapshot(self.state)] * self.n_agents
        if self.comm is None:
            return obs
        msgs = np.where(self.received < 0, self.comm.config.vocab, self.received)
        return [{"obs": o, "messages": m} for o, m in zip(obs, msgs)]

    def split_action(self, action: Any) -> tuple[list[int], list[int] | None]:
        """A joint action -> (moves, tokens). Accepts ``n`` moves, or with communication
        ``2n`` values interleaved ``[move0, token0, move1, token1, ...]`` (or ``(n, 2)``)."""
        n = self.n_agents
        if self.comm is None and type(action) is list and len(action) == n \
                and all(type(a) is int for a in action):
            return action, None  # fast path; transition checks each move
        if type(action) is np.ndarray and action.ndim == 1 and action.dtype.kind in "iu":
            flat = action
        else:
            flat = whole_numbers(action)
        if self.comm is None:
            if flat.size != n:
                raise InvalidActionError(
                    f"expected {n} moves (one per agent, each 0..4), got {flat.size} values"
                )
            return flat.tolist(), None
        if flat.size != 2 * n:
            raise InvalidActionError(
                f"with agent_communication the action is [move, token] per agent: {2 * n} "
                f"values, got {flat.size}"
            )
        pairs = flat.reshape(n, 2)
        return pairs[:, 0].tolist(), pairs[:, 1].tolist()


def whole_numbers(action: Any) -> np.ndarray:
    """``action`` as a flat int64 array. Integers pass; a float that is a whole number
    (2.0) passes; 1.7, NaN, infinity, booleans, text and anything past 2**31 are an
    :class:`InvalidActionError` naming the value (never silently rounded or wrapped)."""
    try:
        arr = np.asarray(action)
    except (TypeError, ValueError):
        arr = np.asarray(None)
    kind = arr.dtype.kind
    if kind == "O":  # a ragged or mixed sequence: try the plain int conversion
        try:
            arr = np.asarray(action, dtype=np.int64)
            kind = "i"
        except (TypeError, ValueError, OverflowError):
            pass
    if kind not in "iuf":
        raise InvalidActionError(f"action {action!r} is not a sequence of whole numbers "
                                 "(moves are 0..4)")
    flat = arr.reshape(-1)
    if kind == "f":
        bad = ~np.isfinite(flat) | (flat != np.round(flat))
        if bad.any():
            raise InvalidActionError(f"action value {flat[bad][0].item()!r} is not a whole number "
                                     "(moves are 0..4)")
    big = np.abs(flat.astype(np.float64)) >= _ACTION_BOUND
    if big.any():
        raise InvalidActionError(f"action value {flat[big][0].item()!r} is out of range (moves are "
                                 "0..4)")
    return flat.astype(np.int64)


__all__ = ["MAX_OBS_RADIUS", "MODES", "EnvConfig", "KitchenCore", "parse_env_kwargs",
           "whole_numbers"]

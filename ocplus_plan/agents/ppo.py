"""``ppo:PATH``: a controller that acts with a PPO checkpoint written by ``ocplus train``.

Every driven agent is encoded from the symbolic state with the checkpoint's observation
kind (the ``features`` encoder works on any map and agent count; ``grid`` needs the
map it was trained on) and acts with the one shared policy. Actions are sampled from
the policy with this controller's own generator (seeded from the controller seed and
the episode seed), or taken greedily with ``ppo:PATH@greedy``. torch and
stable-baselines3 are imported when the first controller is built; without them the
error names the ``rl`` extra.

A checkpoint is a weights-only ``.npz`` (:mod:`ocplus_plan.rl.weights`: arrays and a JSON
description, read with sizes checked and nothing unpickled), played with numpy alone;
``ppo:OUT/policy.npz`` of ``ocplus train`` likewise (:mod:`ocplus_plan.rl.npz_policy`). An
SB3 ``.zip`` runs code when loaded (pickle) and is refused unless
``--trust-pickled-checkpoint`` is given. ``ppo`` without a path picks a shipped checkpoint
(package data built from ``experiments/checkpoints/``) by the kitchen and its cook count:
``{preset}_{n}agent.npz`` on the preset's own map, else the generalist trained on the
generator's kitchens for ``n`` cooks (``generalist_{n}agent/policy.npz``). It says on stderr
which one it loaded, and never plays a checkpoint trained for another number of cooks:
without one for ``n`` cooks it is refused, naming the cook counts that have one.
"""

from __future__ import annotations

import sys
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ConfigError
from ..sim.state import State
from .base import Controller

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

_MODES = ("sample", "greedy")
#: shipped checkpoints this process has said it plays
_ANNOUNCED: set[str] = set()


def parse_spec(arg: str | None) -> tuple[str | None, str | None]:
    """``PATH``, ``PATH@greedy`` / ``PATH@sample``, ``@greedy`` or None -> (path or None
    for a shipped checkpoint, mode or None for the checkpoint's default)."""
    if not arg:
        return None, None
    path, sep, mode = arg.rpartition("@")
    if sep and mode in _MODES:
        return path or None, mode
    return arg, None


def shipped_checkpoint(preset: str, n_agents: int, directory: Traversable | None = None,
                       map_name: str | None = None) -> Traversable:
    """The shipped checkpoint for a kitchen with ``n_agents`` cooks: the preset's own on its
    map (``map_name`` None or the preset's), else the generalist for ``n_agents`` cooks
    (``ConfigError`` if neither: never one trained for another cook count); ``directory``
    defaults to the package data ``checkpoints``."""
    from ..sim.rules import PRESETS

    if directory is None:
        from ..data import data_files

        directory = data_files("checkpoints")
    names = [f"generalist_{n_agents}agent/policy.npz"]
    if preset in PRESETS and map_name in (None, PRESETS[preset].map):
        names.insert(0, f"{preset}_{n_agents}agent.npz")
    for name in names:
        if (directory.joinpath(*name.split("/"))).is_file():
            return directory.joinpath(*name.split("/"))
    have = sorted(p.name for p in directory.iterdir()
                  if p.name.endswith(".npz") or p.name.startswith("generalist_")) \
        if directory.is_dir() else []
    raise ConfigError(
        f"no shipped PPO checkpoint for {n_agents} cook(s) on preset {preset!r}"
        f"{'' if map_name is None else f' map {map_name!r}'} in {directory} (have: "
        f"{', '.join(have) or 'none'}; a checkpoint for another number of cooks is never "
        "played in its place); pass one explicitly as ppo:PATH"
    )


def missing_checkpoint(arg: str | None, preset: str, n_agents: int,
                       map_name: str | None = None) -> str | None:
    """Why ``ppo[:arg]`` cannot play ``preset`` with ``n_agents`` cooks (a bare ``ppo`` with
    no shipped checkpoint for that kitchen), or None. Needs no torch: the evaluation
    runner asks before any episode, so such kitchens become skipped rows, not errors."""
    path, _ = parse_spec(arg)
    if path is not None:
        return None
    try:
        shipped_checkpoint(preset, n_agents, map_name=map_name)
    except ConfigError as exc:
        return str(exc)
    return None


class PPOAgent(Controller):
    """Drives its agents with a trained PPO policy (parameter sharing across agents)."""

    name = "ppo"

    def __init__(self, path: str | None, seed: int = 0, mode: str | None = None) -> None:
        self.path = path
        self.seed = seed
        self._mode = mode
        if mode is not None and mode not in _MODES:
            raise ConfigError(f"ppo mode {mode!r}: choose one of {', '.join(_MODES)}")
        self.policy: Any = None
        self._loaded: dict[str, Any] = {}
        if path is not None:
            self.policy = self._load(path)
        self.rng: np.random.Generator | None = None
        self._encoders: dict[int, Any] = {}
        self._encoder: Any = None
        self._chooser: Any = None

    def _load(self, path: str) -> Any:
        if path not in self._loaded:
            self._loaded[path] = load_checkpoint(path)
        return self._loaded[path]

    @property
    def mode(self) -> str:
        if self._mode is not None:
            return self._mode
        return self.policy.meta.get("act", "sample") if self.policy is not None else "sample"

    def _reset(self, state: State) -> None:
        from ..rl.obs import make_encoder

        if self.path is None:  # a shipped checkpoint, chosen per kitchen
            shipped = shipped_checkpoint(state.rules.preset, state.n_agents,
                                         map_name=state.rules.layout.name)
            with resources.as_file(shipped) as file:  # a real file, sizes checked by stat
                chosen = str(file)
                if self.policy is None or self.policy.path != Path(chosen):
                    if chosen not in _ANNOUNCED:  # once per process and file
                        _ANNOUNCED.add(chosen)
                        print(f"ppo: kitchen {state.rules.layout.name!r} with {state.n_agents} "
                              f"cook(s) plays the shipped checkpoint {chosen}", file=sys.stderr)
                    self.policy = self._load(chosen)
                    self._encoders = {}
        meta = self.policy.meta
        sample = self.mode == "sample"
        self.rng = np.random.default_rng([self.seed, state.seed or 0]) if sample else None
        self._chooser = None
        if meta["obs"] == "choice":  # the policy picks subtasks, the greedy cook's skills move
            self._encoder = self._chooser = self._choice(state, meta)
            return
        key = id(state.rules)
        enc = self._encoders.get(key)
        if enc is None and meta.get("engine") == "jax":
            from ..rl.npz_policy import NpzInputs

            enc = NpzInputs(state.rules, meta)
            self._encoders = {key: enc}
        if enc is None:
            enc = make_encoder(meta["obs"], state.rules, meta.get("obs_radius", 0))
            if enc.size != meta["obs_size"]:
                raise ConfigError(
                    f"checkpoint {str(self.policy.path)!r} expects observations of size "
                    f"{meta['obs_size']} "
                    f"({meta['obs']}, trained on map {meta['map']!r}) but this kitchen "
                    f"({state.rules.layout.name!r}) gives {enc.size}; use a features checkpoint "
                    "or the map it was trained on"
                )
            self._encoders = {key: enc}  # keeps the rules alive, so the id stays unique
        self._encoder = enc

    def _choice(self, state: State, meta: dict[str, Any]) -> Any:
        """A checkpoint trained with ``--obs choice``: a task-choice controller whose free
        cooks take the subtasks the policy picks (:mod:`.task_choice`)."""
        from .task_choice import TaskChoice

        size = TaskChoice.obs_size(state.rules)
        if size != meta["obs_size"]:
            raise ConfigError(f"checkpoint {str(self.policy.path)!r} expects observations of "
                              f"size {meta['obs_size']} (choice) but this package's task-choice "
                              f"controller gives {size}: retrain it with this version")
        chooser = TaskChoice(self.seed, lambda rows: self.policy.act(rows, self.rng))
        chooser.reset(state, self.agent_ids)
        return chooser

    def act(self, state: State) -> list[int]:
        if self._encoder is None:
            raise ConfigError("PPOAgent.act called before reset(state)")
        if not self.agent_ids:
            return []
        if self._chooser is not None:
            return self._chooser.act(state)
        obs = self._encoder.encode_all(state, self.agent_ids)
        return self.policy.act(obs, self.rng)

    def info(self) -> dict[str, object]:
        checkpoint = str(self.policy.path) if self.policy is not None else self.path
        return {"checkpoint": checkpoint, "mode": self.mode}


def load_checkpoint(path: str) -> Any:
    """A weights-only ``.npz`` (``ocplus train``'s or a JAX ``policy.npz``); anything else is
    an SB3 zip, loaded with stable-baselines3 (which unpickles, so runs code) only when the
    user trusts pickled checkpoints."""
    from ..rl import weights

    if str(path).endswith(".npz"):
        arrays = weights.read_arrays(path)  # sizes checked, nothing unpickled
        if weights.META in arrays:
            return weights.WeightsPolicy(path, arrays)
        from ..rl.npz_policy import NpzPolicy

        return NpzPolicy(path, arrays)
    if not weights.pickled_trusted():
        raise weights.refuse_pickled(path)
    from ..rl.policy import load_policy, require_rl

    require_rl()  # names the extra
    return load_policy(path)


def make_ppo_agent(arg: str | None, seed: int = 0) -> PPOAgent:
    """The ``FACTORIES['ppo']`` entry: ``ppo[:PATH][@greedy|@sample]``."""
    path, mode = parse_spec(arg)
    return PPOAgent(path, seed, mode)


__all__ = ["PPOAgent", "make_ppo_agent", "missing_checkpoint", "parse_spec"]

"""Policies written by ``ocplus train --engine jax`` (``policy.npz`` beside ``train.json``),
played on the CPU with numpy alone: no jax, torch or stable-baselines3 needed.

The network is :func:`ocplus_plan.rl.fast.jax_ppo.forward`'s: two tanh layers, then the
action logits and the value; its input is a cook's vector observation (the values of
:class:`~ocplus_plan.sim.observe.VectorEncoder`, which the JAX kitchen mirrors) followed by
a one-hot of the cook's index. ``train.json`` gives the observation radius and the cooks.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..sim.rules import Rules
from ..sim.state import State
from .weights import read_arrays

MAX_RECORD_BYTES = 1 << 20


class NpzPolicy:
    """A loaded ``policy.npz``: :meth:`probs` and :meth:`act` on input batches."""

    def __init__(self, path: str | Path,
                 arrays: Mapping[str, np.ndarray] | None = None) -> None:
        """``arrays``: the file's arrays when the caller has read them already."""
        self.path = Path(path)
        record = self.path.with_name("train.json")
        if not self.path.is_file() or not record.is_file():
            raise ConfigError(f"{str(self.path)!r}: a JAX policy is a policy.npz with the "
                              "train.json that ocplus train --engine jax writes beside it")
        if arrays is None:
            arrays = read_arrays(self.path, "JAX policy")  # sizes checked, nothing unpickled
        self.weights = {k: np.asarray(v, np.float32) for k, v in arrays.items()}
        try:
            if record.stat().st_size > MAX_RECORD_BYTES:
                raise ValueError(f"{record.name} is over {MAX_RECORD_BYTES} bytes")
            info = json.loads(record.read_text())
            if not isinstance(info, dict):
                raise ValueError(f"{record.name} is not a JSON object")
        except (OSError, ValueError, RecursionError) as exc:
            raise ConfigError(f"{str(self.path)!r}: not a readable JAX policy ({exc})") from None
        if {f"{p}{i}" for p in "wb" for i in range(3)} - set(self.weights):
            raise ConfigError(f"{str(self.path)!r}: expected weights w0-w2 and b0-b2")
        obs = info.get("obs", "vector")  # features/window: a policy exported from the trainer
        try:
            self.meta: dict[str, Any] = {
                "obs": obs, "obs_radius": int(info.get("obs_radius", 0)),
                "obs_size": int(info["obs_size"]), "n_agents": int(info["n_agents"]),
                "map": info.get("map"), "act": info.get("act") or "sample",
                "engine": "jax" if obs == "vector" else "sb3"}
        except (KeyError, TypeError, ValueError) as exc:
            raise ConfigError(f"{str(self.path)!r}: train.json lacks a valid {exc}") from None

    def probs(self, x: np.ndarray) -> np.ndarray:
        w = self.weights
        h = np.tanh(x @ w["w0"] + w["b0"])
        h = np.tanh(h @ w["w1"] + w["b1"])
        logits = (h @ w["w2"] + w["b2"])[:, :-1]
        e = np.exp(logits - logits.max(axis=1, keepdims=True))
        return e / e.sum(axis=1, keepdims=True)

    def act(self, x: np.ndarray, rng: np.random.Generator | None = None) -> list[int]:
        """Greedy actions when ``rng`` is None, else sampled with ``rng``."""
        p = self.probs(np.asarray(x, np.float32))
        if rng is None:
            return [int(a) for a in p.argmax(axis=1)]
        u = rng.random(len(p))
        return [int(min(np.searchsorted(np.cumsum(row), v, side="right"), len(row) - 1))
                for row, v in zip(p, u)]


class NpzInputs:
    """A JAX policy's inputs for the cooks of one rule set: vector observation + cook one-hot."""

    def __init__(self, rules: Rules, meta: dict[str, Any]) -> None:
        from ..sim.observe import VectorEncoder

        if rules.n_agents != meta["n_agents"]:
            raise ConfigError(f"this JAX policy drives {meta['n_agents']} cooks (its cook "
                              f"index is an input); the kitchen has {rules.n_agents}")
        self._enc = VectorEncoder(rules, obs_radius=meta["obs_radius"])
        if self._enc.size != meta["obs_size"]:
            raise ConfigError(f"this JAX policy expects observations of size {meta['obs_size']}"
                              f" (map {meta['map']!r}); this kitchen ({rules.layout.name!r}) "
                              f"gives {self._enc.size}")
        self._eye = np.eye(rules.n_agents, dtype=np.float32)
        self.size = self._enc.size

    def encode_all(self, state: State, agents: Sequence[int] | None = None) -> np.ndarray:
        rows = list(range(state.n_agents)) if agents is None else list(agents)
        obs = np.asarray(self._enc.encode(state), np.float32)[rows]
        return np.concatenate([obs, self._eye[rows]], axis=1)


__all__ = ["NpzInputs", "NpzPolicy"]

"""Which observation a policy sees: ``features`` (this package's egocentric encoder, the
default), ``grid`` (the SPEC section 8 ``vector`` encoding of :mod:`ocplus_plan.sim.observe`)
or ``window`` (both: the features, then the grid encoding of an ``obs_radius`` window around
the cook, whose size is the same on every map: the default for a kitchen distribution)
or ``tasks`` (the features, then what a task-allocating cook decides on: what the orders
still lack, the nearest such ingredient, free boards and pans; :mod:`.task_features`)
or ``choice`` (the ``tasks`` vector and the subtasks a free cook may choose, whose actions
pick one of them: encoded by :mod:`ocplus_plan.agents.task_choice`, not here).

Both are wrapped to one small interface, :class:`ObsEncoder`: ``size`` and
``encode_all(state, agents)`` -> ``(len(agents), size)`` float32.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np

from ..errors import ConfigError
from ..sim.rules import Rules
from ..sim.state import State
from .features import FeatureEncoder
from .task_features import TaskEncoder

OBS_KINDS: tuple[str, ...] = ("features", "grid", "window", "tasks", "choice")
#: the window radius of ``window`` observations when none is given
DEFAULT_WINDOW = 2


class ObsEncoder(Protocol):
    size: int

    def encode_all(self, state: State, agents: Sequence[int] | None = None) -> np.ndarray: ...


class GridEncoder:
    """Adapter over :class:`ocplus_plan.sim.observe.VectorEncoder` (whole map or a window)."""

    def __init__(self, rules: Rules, obs_radius: int = 0) -> None:
        from ..sim.observe import VectorEncoder

        self._enc = VectorEncoder(rules, obs_radius=obs_radius)
        self.size = int(self._enc.size)
        # the grid channels hold counts; scale them to about [0, 1] for the network
        self._scale = (1.0 / np.maximum(np.asarray(self._enc.high, np.float32), 1.0)).astype(
            np.float32
        )

    def encode_all(self, state: State, agents: Sequence[int] | None = None) -> np.ndarray:
        obs = self._enc.encode(state) * self._scale
        return obs if agents is None else obs[list(agents)]


class WindowEncoder:
    """The path features followed by the scaled grid encoding of a radius-``obs_radius``
    window (the same size on every map and cook count)."""

    def __init__(self, rules: Rules, obs_radius: int) -> None:
        if obs_radius < 1:
            raise ConfigError(f"window observations need obs_radius >= 1 (0 is the whole map, "
                              f"whose size differs between maps), got {obs_radius}")
        self._features = FeatureEncoder(rules)
        self._grid = GridEncoder(rules, obs_radius)
        self.size = self._features.size + self._grid.size

    def encode_all(self, state: State, agents: Sequence[int] | None = None) -> np.ndarray:
        return np.concatenate([self._features.encode_all(state, agents),
                               self._grid.encode_all(state, agents)], axis=1)


def make_encoder(kind: str, rules: Rules, obs_radius: int = 0) -> ObsEncoder:
    """The encoder named ``kind`` for ``rules`` (``ConfigError`` for an unknown kind)."""
    if kind == "features":
        return FeatureEncoder(rules)
    if kind == "grid":
        return GridEncoder(rules, obs_radius)
    if kind == "window":
        return WindowEncoder(rules, obs_radius)
    if kind == "tasks":
        return TaskEncoder(rules)
    if kind == "choice":
        raise ConfigError("obs 'choice' is encoded by the task-choice controller that chooses "
                          "the subtasks (ocplus_plan.agents.task_choice), not by an encoder")
    raise ConfigError(f"unknown observation kind {kind!r}; choose one of {', '.join(OBS_KINDS)}")


__all__ = ["DEFAULT_WINDOW", "OBS_KINDS", "GridEncoder", "ObsEncoder", "WindowEncoder",
           "make_encoder"]

"""The one controller interface that the executive, the evaluation and the GUI share.

A controller drives some of the agents (``agent_ids``; all of them by default):
``reset(state, agent_ids)`` at the start of an episode, then ``act(state)`` each
step, returning one action per driven agent, in ``agent_ids`` order. A
:class:`Team` combines controllers that drive disjoint subsets into a joint action.
Controllers may read the full symbolic state; learned policies encode their own
observations from it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ConfigError
from ..sim.codes import Action
from ..sim.state import State


class Controller:
    """Base class: subclasses implement :meth:`act` (and :meth:`_reset` if stateful)."""

    name = "controller"
    agent_ids: tuple[int, ...] = ()

    def reset(self, state: State, agent_ids: Sequence[int] | None = None) -> None:
        self.agent_ids = tuple(range(state.n_agents)) if agent_ids is None else tuple(agent_ids)
        self._reset(state)

    def _reset(self, state: State) -> None:  # noqa: B027 - optional hook
        pass

    def act(self, state: State) -> list[int]:
        raise NotImplementedError

    def observe(self, state: State, events: Sequence[object]) -> None:  # noqa: B027
        """Called after each step with that step's events (for monitoring controllers)."""

    def info(self) -> dict[str, object]:
        """Per-episode statistics for the evaluation (replans, planning time, ...)."""
        return {}


class RandomAgent(Controller):
    """Uniformly random actions from its own seeded generator."""

    name = "random"

    def __init__(self, seed: int = 0) -> None:
        self.seed = seed
        self.rng = np.random.default_rng(seed)

    def _reset(self, state: State) -> None:
        self.rng = np.random.default_rng([self.seed, state.seed or 0])

    def act(self, state: State) -> list[int]:
        return [int(a) for a in self.rng.integers(0, 5, size=len(self.agent_ids))]


class StayAgent(Controller):
    """Always stays (the default partner of the single-agent env view)."""

    name = "stay"

    def act(self, state: State) -> list[int]:
        return [int(Action.STAY)] * len(self.agent_ids)


class Team:
    """Several controllers driving disjoint agent subsets of one kitchen."""

    def __init__(self, controllers: Sequence[Controller], assignment: Sequence[Sequence[int]]):
        if len(controllers) != len(assignment):
            raise ConfigError("Team: one agent-id list per controller is needed")
        flat = [a for ids in assignment for a in ids]
        if len(set(flat)) != len(flat):
            raise ConfigError(f"Team: an agent is driven by two controllers: {assignment}")
        self.controllers = list(controllers)
        self.assignment = [tuple(ids) for ids in assignment]

    def reset(self, state: State) -> None:
        covered = sorted(a for ids in self.assignment for a in ids)
        if covered != list(range(state.n_agents)):
            raise ConfigError(
                f"Team drives agents {covered} but the kitchen has {state.n_agents} agents"
            )
        for c, ids in zip(self.controllers, self.assignment):
            c.reset(state, ids)

    def act(self, state: State) -> list[int]:
        joint = [int(Action.STAY)] * state.n_agents
        for c, ids in zip(self.controllers, self.assignment):
            acts = c.act(state)
            for a, act in zip(ids, acts):
                joint[a] = int(act)
        return joint

    def observe(self, state: State, events: Sequence[object]) -> None:
        for c in self.controllers:
            c.observe(state, events)

    def info(self) -> dict[str, object]:
        """Each controller's statistics, keyed ``"<index>:<name>"``."""
        return {f"{i}:{c.name}": c.info() for i, c in enumerate(self.controllers)}

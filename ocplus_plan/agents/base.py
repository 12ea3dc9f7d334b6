"""The one controller interface that the executive, the evaluation and the GUI share,
and the one episode loop that drives it.

A controller drives some of the agents (``agent_ids``; all of them by default):
``reset(state, agent_ids)`` at the start of an episode, then ``act(state)`` each
step, returning one action per driven agent, in ``agent_ids`` order. A
:class:`Team` combines controllers that drive disjoint subsets into a joint action.
Controllers may read the full symbolic state; learned policies encode their own
observations from it. :class:`Episode` steps a kitchen with a team (``ocplus rollout``,
the evaluation runner, the fault experiments and ``ocplus play`` all use it);
:func:`run_episode` plays one to its end.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any, Protocol

import numpy as np

from ..errors import ConfigError
from ..sim.codes import Action
from ..sim.state import Event, State
from ..sim.step import StepResult, transition


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


class Faults(Protocol):
    """Something that changes the world before each step (``execution.faults.FaultSchedule``)."""

    def before_step(self, state: State) -> list[Event]: ...


#: a team, one controller for every agent, or (controller, agent ids) pairs (agents that
#: no pair names stay where they are)
Drivers = Team | Controller | Sequence[tuple[Any, Sequence[int]]]


def as_team(drivers: Drivers, n_agents: int) -> Team:
    """The :class:`Team` that ``drivers`` describe (see :data:`Drivers`)."""
    if isinstance(drivers, Team):
        return drivers
    if hasattr(drivers, "act"):
        return Team([drivers], [range(n_agents)])  # type: ignore[list-item]
    controllers = [c for c, _ in drivers]  # type: ignore[union-attr]
    assignment = [tuple(ids) for _, ids in drivers]  # type: ignore[union-attr]
    driven = {a for ids in assignment for a in ids}
    idle = tuple(a for a in range(n_agents) if a not in driven)
    if idle:
        controllers.append(StayAgent())
        assignment.append(idle)
    return Team(controllers, assignment)


class Episode:
    """One episode: a kitchen, the team that drives it, and what has happened so far.

    :meth:`step` asks the team for a joint action (timing it), applies it, and tells the
    team what happened (with the events of ``faults``, which act first); :meth:`run`
    steps until the episode ends or ``steps`` steps have passed.
    """

    def __init__(self, state: State, drivers: Drivers, faults: Faults | None = None) -> None:
        self.state = state
        self.team = as_team(drivers, state.n_agents)
        self.faults = faults
        self.rewards = [0.0] * state.n_agents
        self.blocked_moves = 0
        self.max_agents_per_cell = 1  # more would be a collision bug
        self.joint: list[int] = []  # the last joint action
        self.decision_time = 0.0  # seconds the team took to choose it
        self.finished = False
        self.team.reset(state)

    def step(self) -> StepResult:
        state = self.state
        fault_events = self.faults.before_step(state) if self.faults is not None else []
        t0 = time.perf_counter()
        self.joint = self.team.act(state)
        self.decision_time = time.perf_counter() - t0
        result = transition(state, self.joint)
        self.team.observe(state, fault_events + result.events)
        self.rewards = [total + r for total, r in zip(self.rewards, result.rewards)]
        self.blocked_moves += sum(1 for e in result.events if e.kind == "move_blocked")
        crowd = max(state.agent_pos.count(p) for p in state.agent_pos)
        self.max_agents_per_cell = max(self.max_agents_per_cell, crowd)
        self.finished = result.terminated or result.truncated
        return result

    def run(self, steps: int | None = None,
            on_step: Callable[[Episode, StepResult], None] | None = None) -> Episode:
        """Step to the end of the episode (or until step ``steps``), calling ``on_step``
        after each step."""
        limit = self.state.rules.horizon if steps is None else steps
        while not self.state.done and self.state.t < limit:
            result = self.step()
            if on_step is not None:
                on_step(self, result)
        return self

    def summary(self) -> dict[str, Any]:
        """The state's statistics plus the steps taken, the team's reward and collisions."""
        return {**self.state.stats, "t": self.state.t, "reward": round(sum(self.rewards), 6),
                "blocked_moves": self.blocked_moves,
                "max_agents_per_cell": self.max_agents_per_cell}


#: names a partner may be given by beside the agent registry's (``idle`` is ``stay``)
PARTNER_ALIASES = {"idle": "stay"}


def run_episode(state: State, drivers: Drivers, faults: Faults | None = None,
                steps: int | None = None) -> dict[str, Any]:
    """Play ``state`` to its end (or until step ``steps``) and return :meth:`Episode.summary`."""
    return Episode(state, drivers, faults).run(steps).summary()

"""Fault injection for tests and experiments: the world changing under a plan.

- :func:`force_burn`: a pan's steak jumps ahead so that it burns in the next step.
- :func:`force_switch`: an extra layout switch now (through ``sim.dynamics.maybe_switch``).
- :class:`BlockingAgent`: a controller for an agent the planner does not drive, which
  walks to a cell in everybody's way and stands there for a while (a human in the way).
- :class:`MessageLoss`: an executive hook that drops an agent's new task list.
- :class:`FaultSchedule`: faults at given steps of an episode (pass it to
  ``agents.run_episode`` / ``agents.Episode``, which apply it before each step).

These mutate the state on purpose (that is the fault); every other layer treats the
simulator as the only source of truth.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError
from ..sim.codes import Action, Item
from ..sim.dynamics import maybe_switch
from ..sim.state import Event, State
from .paths import PathRequest, plan_paths


def force_burn(state: State, pan: int | None = None) -> list[Event]:
    """Advance the steak on ``pan`` (default: the first pan holding one) to the last tick
    before burning, so that the next step burns it. Returns a ``fault_burn`` event, or
    nothing when no pan holds a steak."""
    geo = state.geo
    pans = geo.pans if pan is None else (pan,)
    for p in pans:
        if p not in geo.pans:
            raise ConfigError(f"cell {geo.rc(p)} is not a pan; pans are at {[geo.rc(c) for c in geo.pans]}")
        steak = state.cell_item[p]
        if steak >= 0 and geo.item_kind[steak] == Item.STEAK:
            state.item_progress[steak] = max(state.item_progress[steak], state.rules.burn_time)
            return [Event("fault_burn", -1, geo.rc(p), steak, state.item_progress[steak])]
    return []


def force_switch(state: State) -> list[Event]:
    """Switch the layout now if the map has a switch layout and nothing blocks it."""
    events: list[Event] = []
    maybe_switch(state, events, force=True)
    return events


class MessageLoss:
    """Drops each agent's copy of a new plan with probability ``rate`` (seeded)."""

    def __init__(self, rate: float, seed: int = 0) -> None:
        if not 0.0 <= rate <= 1.0:
            raise ConfigError(f"message loss rate must be in [0, 1], got {rate}")
        self.rate = rate
        self.rng = np.random.default_rng(seed)
        self.dropped = 0

    def __call__(self, agent: int) -> bool:
        lost = bool(self.rng.random() < self.rate)
        self.dropped += lost
        return not lost


class BlockingAgent:
    """Drives one agent: from ``start`` it walks to ``cell`` and stands there for
    ``duration`` steps, then stays where it is (a cook or a human in the way)."""

    name = "blocker"

    def __init__(self, cell: tuple[int, int], start: int = 0, duration: int = 30) -> None:
        self.cell, self.start, self.duration = cell, start, duration
        self.agent_ids: tuple[int, ...] = ()

    def reset(self, state: State, agent_ids: Sequence[int] | None = None) -> None:
        self.agent_ids = tuple(agent_ids) if agent_ids is not None else (state.n_agents - 1,)
        r, c = self.cell
        if not (0 <= r < state.geo.rows and 0 <= c < state.geo.cols) or \
                not state.geo.walkables[state.layout_index][state.geo.flat(r, c)]:
            raise ConfigError(f"blocking cell {self.cell} is not a floor cell of this map")

    def act(self, state: State) -> list[int]:
        out = []
        goal = state.geo.flat(*self.cell)
        for a in self.agent_ids:
            if not self.start <= state.t < self.start + self.duration:
                out.append(int(Action.STAY))
                continue
            others = {b: state.agent_pos[b] for b in range(state.n_agents) if b != a}
            res = plan_paths(state.geo, [PathRequest(a, state.agent_pos[a], frozenset({goal}))],
                             others, horizon=30, layout_index=state.layout_index)
            out.append(res[a].next_action(state.geo))
        return out

    def observe(self, state: State, events: Sequence[object]) -> None:
        pass

    def info(self) -> dict[str, object]:
        return {}


@dataclass
class FaultSchedule:
    """Faults by step: ``burns`` (steps at which a cooking steak is made to burn, retried each
    step until a steak is on a pan), ``switches`` (steps of extra layout switches)."""

    burns: list[int] = field(default_factory=list)
    switches: list[int] = field(default_factory=list)
    applied: list[tuple[int, str]] = field(default_factory=list)

    def before_step(self, state: State) -> list[Event]:
        events: list[Event] = []
        for t in list(self.burns):
            if state.t >= t:
                ev = force_burn(state)
                if ev:
                    self.burns.remove(t)
                    self.applied.append((state.t, "burn"))
                    events += ev
        for t in list(self.switches):
            if state.t >= t:
                ev = force_switch(state)
                if any(e.kind == "layout_switch" for e in ev):
                    self.switches.remove(t)
                    self.applied.append((state.t, "switch"))
                events += ev
        return events


__all__ = [
    "BlockingAgent",
    "FaultSchedule",
    "MessageLoss",
    "force_burn",
    "force_switch",
]

"""Livelock: cooks that keep blocking each other while no step of the plan gets done.

In a one-lane corridor two cooks sent past each other walk right and left, each ``blocked``
replan gives them the same kind of plan, and nothing is served. :class:`LivelockWatch`
sees it: ``blocked`` triggers keep coming and no plan step has finished for ``patience``
steps. The executive then changes strategy (see :meth:`~.executive.Executive._replan`):
one cook gives way (it is left out of the next plans for a while and steps aside), the
work goes to the others, and a cook that keeps livelocking is swapped for the next one.

The watch also records the stretches the benchmark checks (``stretch`` steps or more with
a ``blocked`` trigger and no plan step finished).

:class:`Contests` handles the smallest livelock, a cell two cooks step into at once: both
stay where they are (docs/spec.md, section 5), and a partner that presses on holds our cook
in place for good (a learned partner stepping right into the free cell our cook stepped up
into held it 17 steps on ``gen:corridor:test:0``, seed 2). After ``patience`` such steps
in a row our cook stays one step and the partner gets the cell. Not beside a partner the
executive predicts by its own policy (greedy): it steps aside itself.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..sim.codes import Action
from ..sim.state import State

#: steps of a stretch with blocked replans and nothing done that counts as a livelock
LIVELOCK_STRETCH = 30


class LivelockWatch:
    """Counts ``blocked`` triggers since the last finished plan step."""

    def __init__(self, patience: int, stretch: int = LIVELOCK_STRETCH) -> None:
        self.patience = patience
        self.stretch = stretch
        self.since = 0  # the step of the last progress
        self.blocked = 0  # blocked triggers since then
        self.fired = 0  # livelocks declared since then
        #: (first, last) step of each stretch of ``stretch`` steps or more with blocked
        #: triggers and no finished plan step
        self.stretches: list[tuple[int, int]] = []
        self.detected = 0

    def progress(self, t: int) -> None:
        """A plan step finished (or nobody has work): the stretch, if any, ends here."""
        self.close(t)
        self.since, self.blocked, self.fired = t, 0, 0

    def on_blocked(self) -> None:
        self.blocked += 1

    def check(self, t: int) -> bool:
        """Is this a (new) livelock: two blocked triggers or more and no progress for
        ``patience`` steps, declared again every ``patience`` steps while it lasts?"""
        if self.blocked < 2 or t - self.since < self.patience * (self.fired + 1):
            return False
        self.fired += 1
        self.detected += 1
        return True

    def close(self, t: int) -> None:
        """Record the stretch that ends at ``t`` if it is long enough."""
        if self.blocked and t - self.since >= self.stretch:
            self.stretches.append((self.since, t))
            self.blocked = 0

    def info(self) -> dict[str, object]:
        return {"livelocks_detected": self.detected,
                "livelock_stretches": list(self.stretches)}


class Contests:
    """Moves of our cooks into a free cell that another cook stepped into at the same time
    (see the module docstring)."""

    def __init__(self, patience: int = 2) -> None:
        self.patience = patience
        self.tried: dict[int, tuple[int, int]] = {}  # cook -> (its cell, the cell it moved to)
        self.count: dict[int, int] = {}  # cook -> contested moves in a row

    def settle(self, state: State, actions: Mapping[int, int]) -> dict[int, int]:
        """``actions`` (cook -> action), with STAY for a cook whose last ``patience`` moves
        were contested; the moves are remembered for the next step's check."""
        out = dict(actions)
        walkable = state.geo.walkables[state.layout_index]
        for a, action in actions.items():
            pos, last = state.agent_pos[a], self.tried.pop(a, None)
            contested = last is not None and last[0] == pos and last[1] not in \
                state.agent_pos and any(n >= 0 and n != pos and n in state.agent_pos
                                        for n in state.geo.neighbors[last[1]])
            self.count[a] = self.count.get(a, 0) + 1 if contested else 0
            if self.count[a] >= self.patience:
                self.count[a] = 0
                out[a] = int(Action.STAY)
                continue
            cell = state.geo.neighbors[pos][action] if action < len(state.geo.neighbors[pos]) \
                else -1
            if cell >= 0 and walkable[cell]:
                self.tried[a] = (pos, cell)
        return out


__all__ = ["LIVELOCK_STRETCH", "Contests", "LivelockWatch"]

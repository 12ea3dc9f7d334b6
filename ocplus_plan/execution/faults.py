"""Fault injection for tests and experiments: the world changing under a plan.

- :func:`force_burn`: a pan's steak jumps ahead so that it burns in the next step.
- :func:`force_switch`: an extra layout switch now (through ``sim.dynamics.maybe_switch``).
- :class:`BlockingAgent`: a controller for an agent the planner does not drive, which
  wanders (or stands) in everybody's way, a human in the way, but only ever stands on
  :func:`safe_cells`, so it never seals the kitchen.
- :class:`MessageLoss`: an executive hook that drops an agent's new task list.
- :class:`FaultSchedule`: faults at given steps of an episode (pass it to
  ``agents.run_episode`` / ``agents.Episode``, which apply it before each step).
- :class:`FaultSpec` / :func:`parse_faults`: the text of ``ocplus eval --faults``
  (``burns:3,switches:40,message-loss:0.3,blocker:moving``).

These mutate the state on purpose (that is the fault); every other layer treats the
simulator as the only source of truth.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..errors import ConfigError
from ..sim.codes import Action, Cell, Item
from ..sim.dynamics import maybe_switch
from ..sim.queries import distances, interaction_spots
from ..sim.state import Event, Geometry, State
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
    """Drives one agent that gets in the cooks' way without ever sealing the kitchen.

    It only ever stands on :func:`safe_cells` (cells whose loss keeps the floor in one
    piece and leaves every station and the serving window an access spot); it walks
    between them along safe cells too. With ``cell`` it walks there and stands for
    ``duration`` steps from ``start`` (``cell`` must be safe); without, it wanders: a
    random safe target, a dwell of a few steps there, the next target (``seed``).
    Outside its active window, and after a layout switch leaves it on an unsafe cell,
    it walks to the nearest safe cell and stays.
    """

    name = "blocker"

    def __init__(self, cell: tuple[int, int] | None = None, start: int = 0,
                 duration: int | None = None, seed: int = 0, dwell: tuple[int, int] = (3, 8)):
        self.cell, self.start, self.duration = cell, start, duration
        self.rng = np.random.default_rng(seed)
        self.dwell = dwell
        self.agent_ids: tuple[int, ...] = ()
        self.target: dict[int, int] = {}
        self.wait: dict[int, int] = {}
        self.moves = 0
        self.unsafe_steps = 0

    def reset(self, state: State, agent_ids: Sequence[int] | None = None) -> None:
        self.agent_ids = tuple(agent_ids) if agent_ids is not None else (state.n_agents - 1,)
        self.target, self.wait = {}, {}
        self.moves = self.unsafe_steps = 0
        if not safe_cells(state.geo, state.layout_index):
            raise ConfigError("this map has no floor cell where a blocking agent seals nothing "
                              "(every cell splits the floor or is a station's only access)")
        if self.cell is None:
            return
        r, c = self.cell
        geo = state.geo
        if not (0 <= r < geo.rows and 0 <= c < geo.cols) or \
                not geo.walkables[state.layout_index][geo.flat(r, c)]:
            raise ConfigError(f"blocking cell {self.cell} is not a floor cell of this map")
        if geo.flat(r, c) not in safe_cells(geo, state.layout_index):
            raise ConfigError(
                f"blocking cell {self.cell} would seal the kitchen (it splits the floor, or it "
                "is the only access to a station, or it stops a layout switch); choose one of "
                f"{sorted(geo.rc(f) for f in safe_cells(geo, state.layout_index))}")

    def _active(self, t: int) -> bool:
        return t >= self.start and (self.duration is None or t < self.start + self.duration)

    def act(self, state: State) -> list[int]:
        geo, li = state.geo, state.layout_index
        safe = safe_cells(geo, li)
        out = []
        for a in self.agent_ids:
            pos = state.agent_pos[a]
            self.unsafe_steps += pos not in safe
            others = {b: state.agent_pos[b] for b in range(state.n_agents) if b != a}
            if pos not in safe:  # on the way, or left unsafe by a switch: to safety at once
                goals = safe - set(others.values())
                action = _step_towards(geo, li, a, pos, goals, others, None)
            elif not self._active(state.t):
                action = int(Action.STAY)
            else:
                action = self._wander(geo, li, a, pos, safe, others)
            self.moves += action != int(Action.STAY)
            out.append(action)
        return out

    def _wander(self, geo: Geometry, li: int, a: int, pos: int, safe: frozenset[int],
                others: dict[int, int]) -> int:
        goal = self.target.get(a)
        if self.cell is not None:
            goal = geo.flat(*self.cell)
        elif goal is None or goal not in safe or (pos == goal and self.wait.get(a, 0) <= 0):
            reach = distances(geo.neighbors, _mask(geo, safe), [pos])
            choices = sorted(c for c in safe if reach[c] > 0 and c not in others.values())
            if not choices:
                return int(Action.STAY)
            goal = int(self.rng.choice(choices))
            self.target[a] = goal
            self.wait[a] = int(self.rng.integers(self.dwell[0], self.dwell[1] + 1))
        if pos == goal:
            self.wait[a] = self.wait.get(a, 0) - 1
            return int(Action.STAY)
        return _step_towards(geo, li, a, pos, frozenset({goal}), others, _mask(geo, safe))

    def observe(self, state: State, events: Sequence[object]) -> None:
        pass

    def info(self) -> dict[str, object]:
        return {"blocker_moves": self.moves, "blocker_unsafe_steps": self.unsafe_steps}


def _mask(geo: Geometry, cells: frozenset[int]) -> tuple[bool, ...]:
    return tuple(f in cells for f in range(geo.rows * geo.cols))


def _step_towards(geo: Geometry, li: int, a: int, pos: int, goals: Iterable[int],
                  others: dict[int, int], walk: Sequence[bool] | None) -> int:
    goals = frozenset(goals)
    if not goals:
        return int(Action.STAY)
    res = plan_paths(geo, [PathRequest(a, pos, goals)], others, horizon=30, layout_index=li,
                     walk_at=None if walk is None else (lambda t: walk))
    return res[a].next_action(geo)


@lru_cache(maxsize=64)
def safe_cells(geo: Geometry, layout_index: int) -> frozenset[int]:
    """Floor cells of a layout where an agent may stand without sealing the kitchen:
    removing the cell keeps its floor neighbours connected to each other (it cuts no part
    of the floor off), leaves every interactive cell (stations, counters, the window) an
    access spot in each floor region that had one, and is no switch cell (an agent there
    would hold back a layout switch)."""
    walk, terrain = geo.walkables[layout_index], geo.terrains[layout_index]
    n = geo.rows * geo.cols
    region = [-1] * n
    for f in range(n):
        if walk[f] and region[f] < 0:
            for g, d in enumerate(distances(geo.neighbors, walk, [f])):
                if d >= 0:
                    region[g] = f
    spots: dict[tuple[int, int], set[int]] = {}
    for f in range(n):
        if not walk[f] and terrain[f] != Cell.BLOCK:
            for s in interaction_spots(geo.neighbors, walk, f):
                spots.setdefault((f, region[s]), set()).add(s)
    safe = set()
    for f in range(n):
        if not walk[f] or f in geo.switch_cells:
            continue
        if any(len(cells) == 1 and f in cells for cells in spots.values()):
            continue
        nbs = [g for g in geo.neighbors[f] if g >= 0 and walk[g]]
        if len(nbs) > 1:
            without = list(walk)
            without[f] = False
            d = distances(geo.neighbors, without, [nbs[0]])
            if any(d[g] < 0 for g in nbs[1:]):
                continue
        safe.add(f)
    return frozenset(safe)


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


#: the keys of ``--faults`` and what each takes
FAULT_KEYS: dict[str, str] = {
    "burns": "N: make N cooking steaks burn, spread evenly over the episode (N >= 1)",
    "switches": "K: an extra layout switch every K steps (K >= 1; maps with a switch layout)",
    "message-loss": "P: each cook misses each new plan with probability P (0 <= P <= 1; "
                    "planner agents)",
    "blocker": "moving: one more agent wanders among the cells where it seals nothing",
}
BLOCKER_MODES = ("moving",)


@dataclass(frozen=True)
class FaultSpec:
    """The faults of ``ocplus eval --faults``: see :data:`FAULT_KEYS` and :func:`parse_faults`."""

    burns: int = 0
    switch_every: int = 0
    message_loss: float = 0.0
    blocker: str | None = None

    def __bool__(self) -> bool:
        return bool(self.burns or self.switch_every or self.message_loss or self.blocker)

    def __str__(self) -> str:
        parts = [f"burns:{self.burns}" if self.burns else "",
                 f"switches:{self.switch_every}" if self.switch_every else "",
                 f"message-loss:{self.message_loss:g}" if self.message_loss else "",
                 f"blocker:{self.blocker}" if self.blocker else ""]
        return ",".join(p for p in parts if p)

    def schedule(self, horizon: int) -> FaultSchedule:
        """The burns and switches of an episode of ``horizon`` steps."""
        burns = [round((i + 1) * horizon / (self.burns + 1)) for i in range(self.burns)]
        every = self.switch_every
        switches = list(range(every, horizon, every)) if every else []
        return FaultSchedule(burns=burns, switches=switches)


def _fault_error(text: str, problem: str) -> ConfigError:
    allowed = "; ".join(f"{k}:{v}" for k, v in FAULT_KEYS.items())
    return ConfigError(f"--faults {text!r}: {problem}. Give KEY:VALUE pairs joined by commas, "
                       f"e.g. burns:3,switches:40,message-loss:0.3,blocker:moving; keys: {allowed}")


def parse_faults(text: str | None) -> FaultSpec:
    """``"burns:3,switches:40,message-loss:0.3,blocker:moving"`` -> :class:`FaultSpec`
    (empty text: no faults). A bad key or value is a :class:`ConfigError` listing the keys."""
    values: dict[str, object] = {}
    for part in filter(None, (p.strip() for p in (text or "").split(","))):
        key, sep, value = (x.strip() for x in part.partition(":"))
        if key not in FAULT_KEYS or not sep:
            raise _fault_error(text or "", f"{part!r} is not KEY:VALUE with a known key")
        if key in values:
            raise _fault_error(text or "", f"{key!r} is given twice")
        values[key] = _fault_value(text or "", key, value)
    return FaultSpec(burns=int(values.get("burns", 0)),  # type: ignore[call-overload]
                     switch_every=int(values.get("switches", 0)),  # type: ignore[call-overload]
                     message_loss=float(values.get("message-loss", 0.0)),  # type: ignore[arg-type]
                     blocker=values.get("blocker"))  # type: ignore[arg-type]


def _fault_value(text: str, key: str, value: str) -> object:
    if key == "blocker":
        if value not in BLOCKER_MODES:
            raise _fault_error(text, f"blocker:{value} is unknown; blocker takes "
                                     f"{' or '.join(BLOCKER_MODES)}")
        return value
    if key == "message-loss":
        try:
            rate = float(value) if value.isascii() else math.nan
        except ValueError:
            rate = math.nan
        if not 0.0 <= rate <= 1.0:  # nan fails too
            raise _fault_error(text, f"message-loss:{value} is not a probability in [0, 1]")
        return rate
    if not (value.isascii() and value.isdigit()) or int(value) < 1 or int(value) > 100_000:
        raise _fault_error(text, f"{key}:{value} is not a whole number from 1 to 100000")
    return int(value)


__all__ = [
    "BLOCKER_MODES",
    "FAULT_KEYS",
    "BlockingAgent",
    "FaultSchedule",
    "FaultSpec",
    "MessageLoss",
    "force_burn",
    "force_switch",
    "parse_faults",
    "safe_cells",
]

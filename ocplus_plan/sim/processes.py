"""One record per process station, compiled to lookup tables: the rules' single source.

A process station changes the state of the item lying on it. Its :class:`Process` record
says what it takes (item kinds in one state), what it makes (the state they reach),
whether the cook's bumps (``"bump"``: the board's chops, the sink's washes) or the clock
(``"time"``: the pan's ticks, one per step) drive it, how long it takes, an optional
overrun (the state reached, and after how many ticks: the pan's burn) and its hand effect
(whether a plate may be filled from, or onto, what lies there).

:func:`process_tables` compiles the records of a rule set into :class:`ProcessTables`:
per cell code the process of that station, per process its durations, and boolean arrays
indexed ``[process, item kind, item state]`` (``accepts``: a cook may put it down there;
``works``: an empty-handed bump works on it). The reference step (``step.py``,
``queries.bump_effect``), the array kernels (``fast/kernels.py``) and the JAX kitchen
(``fast/jax_kitchen.py``) index these tables instead of branching per station; the
planning model (``planning/model.py``) writes one schema per bump-driven record.

Adding a station that processes an item (the oven that bakes) is one record in
:data:`ADDED` plus its cell code and kind (``codes.py``, ``stations.py``); a kitchen
file then lists it under ``processes:`` (see docs/architecture.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from ..errors import ConfigError
from .codes import Cell, Item, ItemState

#: how a process advances
DRIVES = ("bump", "time")
#: item kind codes and state codes the tables span
N_KINDS = 16
N_STATES = len({int(s) for s in ItemState})


@dataclass(frozen=True)
class Process:
    """The rules of one process station."""

    #: the verb of one unit of work: event names are ``<verb>`` and ``<verb>_done``
    verb: str
    #: its past participle ("chopped"): names the planning model's ``pick_<past>``
    past: str
    station: Cell
    #: the item kinds it takes, and the state they must be in
    takes: tuple[Item, ...]
    takes_state: ItemState
    #: the state the item reaches
    makes_state: ItemState
    #: ``"bump"``: each bump by an empty-handed cook is one unit of work; ``"time"``: one
    #: unit per step while the item lies there (with nobody needed)
    drive: str
    #: units of work to finish; a :class:`Rules` field named by ``duration_param``
    #: overrides it
    duration: int
    duration_param: str = ""
    #: the state reached when the item stays ``overrun`` ticks (and one more) on a
    #: time-driven station (the pan's burn); None: it never overruns
    overrun_state: ItemState | None = None
    overrun: int = 0
    overrun_param: str = ""
    #: the stats counter of finished work, and of overruns
    stat: str = ""
    overrun_stat: str = "burns"
    #: hand effect: a cook holding a clean plate may take a plateable item from here, and
    #: a cook holding a plateable item may put it onto a clean plate lying here
    plates: bool = True

    @property
    def timed(self) -> bool:
        return self.drive == "time"


#: the shipped process stations (the presets' rules)
PROCESSES: tuple[Process, ...] = (
    Process("chop", "chopped", Cell.BOARD, (Item.TOMATO, Item.LETTUCE, Item.ONION), ItemState.FRESH,
            ItemState.CHOPPED, "bump", 3, "chop_steps", stat="chops"),
    Process("cook", "cooked", Cell.PAN, (Item.STEAK,), ItemState.FRESH, ItemState.COOKED, "time", 10,
            "cook_time", ItemState.BURNT, 20, "burn_time", stat="cooks"),
    Process("wash", "washed", Cell.SINK, (Item.PLATE,), ItemState.DIRTY, ItemState.CLEAN, "bump", 3,
            "wash_steps", stat="washes", plates=False),
)


#: process stations a kitchen file may add (``processes:``, ``sim/process_yaml.py``) with
#: their default records; each takes its item kinds over from the shipped record that had
#: them. The oven roasts steak in the clock's time and burns it when left (its cells are
#: cell kind ``oven`` in ``stations.py``)
ADDED: tuple[Process, ...] = (
    Process("bake", "baked", Cell.OVEN, (Item.STEAK,), ItemState.FRESH, ItemState.COOKED,
            "time", 8, "", ItemState.BURNT, 16, "", stat="cooks"),
)


#: the counters a record may count into (the stats every engine keeps)
COUNTERS = ("chops", "cooks", "washes", "burns")


def check_processes(processes: tuple[Process, ...], durations: dict[str, int] | None = None,
                    ) -> None:
    """Raise :class:`ConfigError` naming the record and the fix for a rule set of process
    records that no engine could run (``durations``: the rule parameters a record names)."""
    seen: dict[Cell, str] = {}
    for p in processes:
        what = f"process {p.verb!r}"
        if not isinstance(p, Process):
            raise ConfigError(f"processes must be Process records, got {p!r}")
        if p.station in seen:
            raise ConfigError(f"{what}: station {p.station.name.lower()} already runs "
                              f"{seen[p.station]!r}; give each station one process")
        seen[p.station] = p.verb
        if p.drive not in DRIVES:
            raise ConfigError(f"{what}: drive {p.drive!r} is not one of {', '.join(DRIVES)}")
        if not p.takes or p.takes_state == p.makes_state:
            raise ConfigError(f"{what} must take at least one item kind and change its state")
        for name in (p.stat, p.overrun_stat):
            if name not in COUNTERS:
                raise ConfigError(f"{what}: counter {name!r} is not one of {', '.join(COUNTERS)}")
        duration = (durations or {}).get(p.duration_param, p.duration)
        if isinstance(duration, bool) or not isinstance(duration, int) or duration < 1:
            raise ConfigError(f"{what}: duration must be a positive integer, got {duration!r}")
        if p.overrun_state is not None:
            overrun = (durations or {}).get(p.overrun_param, p.overrun)
            if not p.timed:
                raise ConfigError(f"{what}: only a time-driven station overruns; drop the "
                                  "overrun or make the drive time")
            if overrun < duration:
                raise ConfigError(f"{what}: its overrun time ({overrun}) comes before its "
                                  f"duration ({duration}); make it at least the duration")
    kinds = [k for p in processes for k in p.takes]
    dup = sorted({k.name.lower() for k in kinds if kinds.count(k) > 1})
    if dup:
        raise ConfigError(f"item kind(s) {dup} are taken by two processes; one each")


def ingredient_process(processes: tuple[Process, ...] = PROCESSES) -> dict[Item, Process]:
    """The process each ingredient needs before it goes on a plate (plates excluded)."""
    return {k: p for p in processes for k in p.takes if k != Item.PLATE}


def ready_state(processes: tuple[Process, ...] = PROCESSES) -> dict[Item, ItemState]:
    """The state each ingredient must reach before it goes on a plate."""
    return {k: p.makes_state for k, p in ingredient_process(processes).items()}


#: The processed state an ingredient must reach before it goes on a plate.
READY_STATE: dict[Item, ItemState] = ready_state()
#: The station an ingredient needs to be processed.
PROCESS_STATION: dict[Item, Cell] = {k: p.station for k, p in ingredient_process().items()}


@dataclass(frozen=True)
class ProcessTables:
    """The records of one rule set as lookup tables (shared, never mutated)."""

    processes: tuple[Process, ...]
    #: cell code -> process index
    by_code: dict[int, int]
    #: per process: units of work to finish, overrun tick (-1: none), done / overrun state
    duration: tuple[int, ...]
    overrun: tuple[int, ...]
    done_state: tuple[int, ...]
    overrun_state: tuple[int, ...]
    timed: tuple[bool, ...]
    plates: tuple[bool, ...]
    #: [process, kind, state]: may be put down there / an empty-handed bump works on it
    accepts: np.ndarray
    works: np.ndarray
    #: [kind, state]: goes on a plate
    plateable: np.ndarray
    #: the same three as nested lists (faster to index one element from Python)
    accepts_list: list
    works_list: list
    plateable_list: list

    def process_at(self, code: int) -> Process | None:
        i = self.by_code.get(code, -1)
        return self.processes[i] if i >= 0 else None

    def index_of(self, kind: int) -> int:
        """The process that takes item kind ``kind`` (-1: none)."""
        return next((j for j, p in enumerate(self.processes) if kind in p.takes), -1)

    def work(self, kind: int) -> int:
        """Units of work (bumps or ticks) that finish item kind ``kind``'s process (0: none)."""
        j = self.index_of(kind)
        return self.duration[j] if j >= 0 else 0

    def progress_scale(self, kind: int) -> int:
        """What an item's progress is divided by to lie in [0, 1]: its overrun tick + 1 on a
        station that overruns (the pan's ``burn_time + 1``), else its duration (1: none)."""
        j = self.index_of(kind)
        if j < 0:
            return 1
        return self.overrun[j] + 1 if self.overrun_state[j] >= 0 else self.duration[j]

    def ready_of(self, kind: int) -> int:
        """The state item kind ``kind`` must reach before it goes on a plate: the state its
        process makes (-1: no process takes it)."""
        j = self.index_of(kind)
        return self.done_state[j] if j >= 0 and kind != Item.PLATE else -1

    def station_of(self, kind: int) -> int:
        """The station code of the process that takes item kind ``kind`` (steak: the pan,
        or an oven where a kitchen's records give it the steak; -1: none)."""
        j = self.index_of(kind)
        return int(self.processes[j].station) if j >= 0 else -1

    def duration_at(self, code: int) -> int:
        """The duration of station ``code``'s process."""
        return self.duration[self.by_code[code]]

    def overrun_at(self, code: int) -> int:
        """The overrun tick of station ``code``'s process (-1: it never overruns)."""
        return self.overrun[self.by_code[code]]


def _param(rules: Any, name: str, default: int) -> int:
    return int(getattr(rules, name)) if rules is not None and name else default


def process_tables(rules: Any = None) -> ProcessTables:
    """The tables of a :class:`~.rules.Rules`' processes (durations from its parameters),
    cached; None: the shipped records with their default durations. (``rules`` is not
    annotated with the class: this module sits below ``rules.py``, which imports it.)"""
    procs = PROCESSES if rules is None else rules.processes
    durations = tuple((_param(rules, p.duration_param, p.duration),
                       _param(rules, p.overrun_param, p.overrun) if p.overrun_state is not None
                       else -1) for p in procs)
    return _compile(procs, durations)


@lru_cache(maxsize=64)
def _compile(procs: tuple[Process, ...], durations: tuple[tuple[int, int], ...]) -> ProcessTables:
    n = len(procs)
    accepts = np.zeros((n, N_KINDS, N_STATES), bool)
    works = np.zeros((n, N_KINDS, N_STATES), bool)
    plateable = np.zeros((N_KINDS, N_STATES), bool)
    for i, p in enumerate(procs):
        for k in p.takes:
            accepts[i, int(k), int(p.takes_state)] = True
            if p.timed and p.overrun_state is not None:  # it keeps heating what it made
                accepts[i, int(k), int(p.makes_state)] = True
            if not p.timed:
                works[i, int(k), int(p.takes_state)] = True
            if k != Item.PLATE:
                plateable[int(k), int(p.makes_state)] = True
    return ProcessTables(
        procs, {int(p.station): i for i, p in enumerate(procs)},
        tuple(d for d, _ in durations), tuple(o for _, o in durations),
        tuple(int(p.makes_state) for p in procs),
        tuple(-1 if p.overrun_state is None else int(p.overrun_state) for p in procs),
        tuple(p.timed for p in procs), tuple(p.plates for p in procs),
        accepts, works, plateable, accepts.tolist(), works.tolist(), plateable.tolist())


__all__ = ["ADDED", "COUNTERS", "DRIVES", "check_processes", "N_KINDS", "N_STATES", "PROCESSES", "PROCESS_STATION", "READY_STATE", "Process", "ProcessTables",
           "ingredient_process", "process_tables", "ready_state"]

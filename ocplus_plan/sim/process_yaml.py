"""A kitchen file's ``processes``: its own process-station records (SPEC section 2).

Each entry replaces the shipped record of one process station (board, pan, sink) for that
kitchen, or adds a station of :data:`.processes.ADDED` (the oven), which takes the item
kinds it lists over from the shipped records (one left with none is dropped); the
stations it does not list keep theirs. Entries are checked like the rest of
the map: a bounded list of mappings with known keys, each value of the right kind and
range, and the resulting records together as :func:`.processes.check_processes` requires;
every error is a :class:`MapFormatError` naming the file, the entry and the fix.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from ..errors import ConfigError, MapFormatError
from .codes import ITEM_NAMES, ItemState
from .processes import ADDED, COUNTERS, DRIVES, PROCESSES, Process, check_processes

#: at most this many entries (one per process station)
MAX_PROCESSES = 8
#: the longest duration or overrun a record may give, in bumps or steps
MAX_DURATION = 1000
KEYS = ("station", "verb", "past", "takes", "from", "to", "drive", "duration", "overrun",
        "plates", "counter")
STATIONS = {p.station.name.lower(): p.station for p in PROCESSES + ADDED}
STATES = {**{s.name.lower(): s for s in ItemState}, "raw": ItemState.RAW}
_SHIPPED = {p.station: p for p in PROCESSES + ADDED}


def parse_processes(value: Any, src: str) -> tuple[Process, ...]:
    """The kitchen's records: the shipped ones, with each listed station's replaced."""
    if not isinstance(value, list) or not value or len(value) > MAX_PROCESSES:
        raise MapFormatError(f"{src}: 'processes' must be a list of 1 to {MAX_PROCESSES} "
                             "station records (mappings with station, verb, takes, ...)")
    given = {}
    for n, entry in enumerate(value):
        record = _record(entry, f"{src}: processes[{n}]")
        if record.station in given:
            raise MapFormatError(f"{src}: processes[{n}] gives station "
                                 f"{record.station.name.lower()} a second record; keep one")
        given[record.station] = record
    out = tuple(given.pop(p.station, p) for p in PROCESSES)
    if given:  # added stations: each takes its kinds over from the shipped records
        taken = {k for p in given.values() for k in p.takes}
        kept = (replace(p, takes=tuple(k for k in p.takes if k not in taken)) for p in out)
        out = tuple(p for p in kept if p.takes) + tuple(given.values())
    try:
        check_processes(out)
    except ConfigError as exc:
        raise MapFormatError(f"{src}: processes: {exc}") from None
    return out


def process_to_dict(p: Process) -> dict[str, Any]:
    """A record as a kitchen file's entry (what :func:`parse_processes` reads back into the
    same record, durations included)."""
    out: dict[str, Any] = {
        "station": p.station.name.lower(), "verb": p.verb, "past": p.past,
        "takes": [k.name.lower() for k in p.takes], "from": p.takes_state.name.lower(),
        "to": p.makes_state.name.lower(), "drive": p.drive, "duration": p.duration}
    if p.overrun_state is not None:
        out["overrun"] = {"state": p.overrun_state.name.lower(), "after": p.overrun}
    out["plates"], out["counter"] = p.plates, p.stat
    return out


def own_processes(processes: tuple[Process, ...] | None) -> list[dict[str, Any]]:
    """The entries of a kitchen's records that are not the shipped ones (its ``processes``)."""
    return [process_to_dict(p) for p in processes or () if p not in PROCESSES]


def check_entry(entry: Any, where: str, example: str, keys: tuple[str, ...]) -> None:
    """Refuse a kitchen-file record that is not a mapping of ``keys`` (``example``: one)."""
    if not isinstance(entry, dict):
        raise MapFormatError(f"{where} must be a mapping such as {example}")
    unknown = [k for k in entry if k not in keys]
    if unknown:
        raise MapFormatError(f"{where}: unknown key {str(unknown[0])[:40]!r}; allowed keys: "
                             f"{', '.join(keys)}")


def _record(entry: Any, where: str) -> Process:
    check_entry(entry, where, "{station: pan, verb: roast, takes: [steak], from: raw, "
                "to: cooked, drive: time, duration: 8}", KEYS)
    missing = [k for k in ("station", "verb", "takes", "from", "to", "drive", "duration")
               if k not in entry]
    if missing:
        raise MapFormatError(f"{where}: missing {', '.join(missing)}")
    station = _choice(entry["station"], STATIONS, where, "station")
    verb = _word(entry["verb"], where, "verb")
    takes = entry["takes"]
    if not isinstance(takes, list) or not takes or len(takes) > len(ITEM_NAMES):
        raise MapFormatError(f"{where}: 'takes' must be a list of item kinds such as [steak]")
    kinds = tuple(_choice(k, ITEM_NAMES, where, "takes") for k in takes)
    overrun_state, overrun = None, 0
    if entry.get("overrun") is not None:
        spec = entry["overrun"]
        if not isinstance(spec, dict) or set(spec) != {"state", "after"}:
            raise MapFormatError(f"{where}: 'overrun' must be a mapping "
                                 "{state: burnt, after: 20} (the state, and after how many steps)")
        overrun_state = _choice(spec["state"], STATES, where, "overrun state")
        overrun = _count(spec["after"], where, "overrun after")
    plates = entry.get("plates", _SHIPPED[station].plates)
    if not isinstance(plates, bool):
        raise MapFormatError(f"{where}: 'plates' must be true or false, got {plates!r:.40}")
    past = entry.get("past", verb + ("d" if verb.endswith("e") else "ed"))
    return Process(
        verb, _word(past, where, "past"), station, kinds,
        _choice(entry["from"], STATES, where, "from"), _choice(entry["to"], STATES, where, "to"),
        _choice(entry["drive"], {d: d for d in DRIVES}, where, "drive"),
        _count(entry["duration"], where, "duration"), "", overrun_state, overrun, "",
        stat=_choice(entry.get("counter", _SHIPPED[station].stat), {c: c for c in COUNTERS},
                     where, "counter"),
        plates=plates)


def _choice(value: Any, options: dict[str, Any], where: str, key: str) -> Any:
    if not isinstance(value, str) or value.strip().lower() not in options:
        raise MapFormatError(f"{where}: {key} {str(value)[:40]!r} is not one of "
                             f"{', '.join(options)}")
    return options[value.strip().lower()]


def _word(value: Any, where: str, key: str) -> str:
    if not isinstance(value, str) or not value.isidentifier() or not value.islower() \
            or len(value) > 24:
        raise MapFormatError(f"{where}: '{key}' must be one lower-case word (letters, digits, "
                             f"underscores; at most 24), got {str(value)[:40]!r}")
    return value


def _count(value: Any, where: str, key: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_DURATION:
        raise MapFormatError(f"{where}: '{key}' must be an integer from 1 to {MAX_DURATION}, "
                             f"got {str(value)[:40]!r}")
    return value


__all__ = ["KEYS", "MAX_DURATION", "MAX_PROCESSES", "check_entry", "own_processes", "parse_processes",
           "process_to_dict"]

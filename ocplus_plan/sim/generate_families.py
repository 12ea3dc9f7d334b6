"""The kitchen families of :mod:`.generate`: one builder per family draws the walls.

A builder gets a seeded ``numpy.random.Generator`` and the grid size and returns a
:class:`Sketch`: the grids (border and inner walls are counters, code 1), the named floor
regions, where each station kind may go, which region each cook starts in, and the cells
no station or cook may take (pass-through counters, gates). :func:`.generate.generate_map`
places the stations and cooks on a sketch and checks the result.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .codes import Cell
from .presets import PRESETS, Preset
from .processes import PROCESSES

Rc = tuple[int, int]

#: the smallest (rows, cols) each family can be drawn in (the largest is 12 x 12)
MIN_SIZE: dict[str, tuple[int, int]] = {
    "open": (5, 5),
    "split": (5, 5),
    "corridor": (5, 5),
    "switching": (5, 7),
    "multiroom": (5, 7),
}
MAX_SIZE = 12
#: the fewest cooks each family needs (a split kitchen needs one cook per half)
MIN_COOKS: dict[str, int] = {"open": 1, "split": 2, "corridor": 1, "switching": 1, "multiroom": 1}

_T, _L, _O = int(Cell.TOMATO), int(Cell.LETTUCE), int(Cell.ONION)
_BOARD, _PLATE, _DELIVERY = int(Cell.BOARD), int(Cell.PLATE), int(Cell.DELIVERY)
#: what every generated kitchen gets: (station code, fewest, most)
_BASE = ((_DELIVERY, 1, 1), (_BOARD, 1, 2), (_PLATE, 1, 2), (_T, 1, 1), (_L, 1, 1), (_O, 1, 1))


def _preset_stations(preset: Preset) -> tuple[tuple[int, int, int], ...]:
    """The stations placed on a preset's kitchens: the base, then one of each station the
    preset needs (:data:`.presets.PRESETS`) with, for a process station, the crates of the
    item kinds its shipped record takes that the base lacks (the pan brings steak's)."""
    out = list(_BASE)
    for station in preset.stations:
        code = int(station)
        if any(c == code for c, _, _ in out):
            continue
        out.append((code, 1, 1))
        out += [(int(k), 1, 1) for p in PROCESSES if p.station == station for k in p.takes
                if int(k) != _PLATE and all(c != int(k) for c, _, _ in out)]
    return tuple(out)


#: preset -> (station code, fewest, most) placed on its kitchens
PRESET_STATIONS: dict[str, tuple[tuple[int, int, int], ...]] = {
    name: _preset_stations(p) for name, p in PRESETS.items()}
#: the stations :func:`.generate_checks.structure_problems` requires of a preset's kitchens
REQUIRED: dict[str, frozenset[int]] = {p: frozenset(c for c, _, _ in s)
                                       for p, s in PRESET_STATIONS.items()}


class Retry(Exception):
    """This draw cannot be completed; the generator draws the next candidate."""


@dataclass
class Sketch:
    """Walls and regions of one kitchen before its stations and cooks are placed."""

    grid: np.ndarray
    #: region name -> floor cells
    regions: dict[str, list[Rc]]
    #: station code -> the regions whose floor must touch it (absent: any region)
    station_regions: dict[int, tuple[str, ...]] = field(default_factory=dict)
    #: one region name per cook, in spawn order
    cook_regions: tuple[str, ...] = ()
    #: cells that must stay plain counters or plain floor (no station, no cook)
    reserved: set[Rc] = field(default_factory=set)
    switch_grid: np.ndarray | None = None
    #: stations that the switch layout cuts off (switching family only)
    cut_kind: int | None = None


def _box(rows: int, cols: int) -> np.ndarray:
    grid = np.full((rows, cols), int(Cell.COUNTER), dtype=np.int8)
    grid[1:-1, 1:-1] = int(Cell.FLOOR)
    return grid


def _floor(grid: np.ndarray, rows: range, cols: range) -> list[Rc]:
    return [(r, c) for r in rows for c in cols if int(grid[r, c]) == Cell.FLOOR]


def _alternate(first: str, second: str, cooks: int) -> tuple[str, ...]:
    return tuple(first if i % 2 == 0 else second for i in range(cooks))


def build_open(rng: np.random.Generator, rows: int, cols: int, cooks: int,
               stations: tuple[int, ...]) -> Sketch:
    """One room; on a larger floor, one counter island (cooks walk round it)."""
    grid = _box(rows, cols)
    if rows >= 7 and cols >= 7 and rng.random() < 0.6:
        r = int(rng.integers(3, rows - 3))
        c0 = int(rng.integers(3, cols - 3))
        length = int(rng.integers(1, max(2, cols - 3 - c0)))
        grid[r, c0:c0 + length] = int(Cell.COUNTER)
    interior = _floor(grid, range(1, rows - 1), range(1, cols - 1))
    return Sketch(grid, {"room": interior}, cook_regions=("room",) * cooks)


def build_split(rng: np.random.Generator, rows: int, cols: int, cooks: int,
                stations: tuple[int, ...]) -> Sketch:
    """Two halves divided by a wall of counters: the raw side has the ingredients and the
    window, the cooking side the boards and the pan, so every dish crosses the wall."""
    grid = _box(rows, cols)
    inner = cols - 2
    mid = 1 + inner // 2
    wall = int(rng.integers(max(2, mid - 1), min(cols - 3, mid + 1) + 1))
    grid[1:-1, wall] = int(Cell.COUNTER)
    left = _floor(grid, range(1, rows - 1), range(1, wall))
    right = _floor(grid, range(1, rows - 1), range(wall + 1, cols - 1))
    raw, cook = ("left", "right") if rng.random() < 0.5 else ("right", "left")
    regions = {"left": left, "right": right}
    placement = {int(Cell.DELIVERY): (raw,), int(Cell.BOARD): (cook,), int(Cell.PAN): (cook,)}
    for code in (Cell.TOMATO, Cell.LETTUCE, Cell.ONION, Cell.STEAK):
        placement[int(code)] = (raw,)
    first = raw if rng.random() < 0.5 else cook
    second = cook if first == raw else raw
    passes = {(r, wall) for r in range(rows)}
    return Sketch(grid, regions, placement, _alternate(first, second, cooks), passes)


def build_corridor(rng: np.random.Generator, rows: int, cols: int, cooks: int,
                   stations: tuple[int, ...]) -> Sketch:
    """Two rooms joined by a one-lane corridor through a block of counters; the window is
    in one room and the boards in the other, so the cooks meet in the lane."""
    grid = _box(rows, cols)
    inner = cols - 2
    lane_len = int(rng.integers(max(1, inner // 3), inner - 2 + 1))
    left_w = int(rng.integers(1, inner - lane_len - 1 + 1))
    c0 = 1 + left_w
    c1 = c0 + lane_len  # first column of the right room
    lane_row = int(rng.integers(1, rows - 1))
    grid[1:-1, c0:c1] = int(Cell.COUNTER)
    grid[lane_row, c0:c1] = int(Cell.FLOOR)
    regions = {
        "left": _floor(grid, range(1, rows - 1), range(1, c0)),
        "right": _floor(grid, range(1, rows - 1), range(c1, cols - 1)),
        "lane": [(lane_row, c) for c in range(c0, c1)],
    }
    window, boards = ("left", "right") if rng.random() < 0.5 else ("right", "left")
    placement = {int(Cell.DELIVERY): (window,), int(Cell.BOARD): (boards,)}
    return Sketch(grid, regions, placement, _alternate(boards, window, cooks),
                  reserved=set(regions["lane"]))


def build_switching(rng: np.random.Generator, rows: int, cols: int, cooks: int,
                    stations: tuple[int, ...]) -> Sketch:
    """A room with an alcove behind a gate column: open (or half open) in the main layout,
    walled with blocks in the switch layout. The only boards (or the only pan) are in the
    alcove, so after a switch nobody outside can reach them."""
    grid = _box(rows, cols)
    inner = cols - 2
    alcove_w = int(rng.integers(1, max(1, min(inner // 3, inner - 3)) + 1))
    gate = cols - 2 - alcove_w
    if gate < 2:
        raise Retry
    door_len = int(rng.integers(1, rows - 2 + 1))
    door0 = int(rng.integers(1, rows - 1 - door_len + 1))
    door = [(r, gate) for r in range(door0, door0 + door_len)]
    for r in range(1, rows - 1):
        if (r, gate) not in door:
            grid[r, gate] = int(Cell.BLOCK)
    switch = grid.copy()
    for r, c in door:
        switch[r, c] = int(Cell.BLOCK)
    regions = {
        "main": _floor(grid, range(1, rows - 1), range(1, gate)),
        "alcove": _floor(grid, range(1, rows - 1), range(gate + 1, cols - 1)),
    }
    cut = int(Cell.PAN) if int(Cell.PAN) in stations and rng.random() < 0.5 else int(Cell.BOARD)
    placement = {code: ("main",) for code in stations}
    placement[cut] = ("alcove",)
    reserved = set(door) | {(0, gate), (rows - 1, gate)}
    return Sketch(grid, regions, placement, ("main",) * cooks, reserved, switch, cut)


def build_multiroom(rng: np.random.Generator, rows: int, cols: int, cooks: int,
                    stations: tuple[int, ...]) -> Sketch:
    """Two to four rooms behind counter walls with one-cell doors; the window and the
    boards are in different rooms."""
    grid = _box(rows, cols)
    wall = int(rng.integers(3, cols - 4 + 1))  # rooms at least two columns wide
    grid[1:-1, wall] = int(Cell.COUNTER)
    doors: set[Rc] = set()
    spans = {"w": range(1, wall), "e": range(wall + 1, cols - 1)}
    cuts: dict[str, int | None] = {}
    for side, span in spans.items():
        cut = None
        if rows >= 7 and rng.random() < 0.7:
            cut = int(rng.integers(3, rows - 4 + 1))  # rooms at least two rows tall
            grid[cut, span.start:span.stop] = int(Cell.COUNTER)
            d = (cut, int(rng.integers(span.start, span.stop)))
            grid[d] = int(Cell.FLOOR)
            doors.add(d)
        cuts[side] = cut
    # one door through the long wall for each room of the west side
    west_rooms = ([range(1, cuts["w"]), range(cuts["w"] + 1, rows - 1)]
                  if cuts["w"] is not None else [range(1, rows - 1)])
    for rr in west_rooms:
        east_ok = [r for r in rr if r != cuts["e"]]
        d = (int(rng.choice(east_ok)), wall)
        grid[d] = int(Cell.FLOOR)
        doors.add(d)
    regions: dict[str, list[Rc]] = {}
    for side, span in spans.items():
        cut = cuts[side]
        bands = [range(1, cut), range(cut + 1, rows - 1)] if cut is not None else [
            range(1, rows - 1)]
        for k, band in enumerate(bands):
            regions[f"{side}{k}"] = [rc for rc in _floor(grid, band, span) if rc not in doors]
    names = sorted(regions)
    window, boards = (str(x) for x in rng.choice(names, size=2, replace=False))
    placement = {int(Cell.DELIVERY): (window,), int(Cell.BOARD): (boards,)}
    order = [names[int(i)] for i in rng.permutation(len(names))]
    return Sketch(grid, regions, placement, tuple(order[i % len(order)] for i in range(cooks)),
                  reserved=doors)


BUILDERS: dict[str, Callable[..., Sketch]] = {
    "open": build_open,
    "split": build_split,
    "corridor": build_corridor,
    "switching": build_switching,
    "multiroom": build_multiroom,
}

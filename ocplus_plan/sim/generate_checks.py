"""Structure checks of generated kitchens: what each family of :mod:`.generate` promises.

The checks read a loaded :class:`.maps.Layout` (a map dict, as
:func:`.generate.generate_map` returns it, is loaded first): its grids, spawn points and
station cells. The map parser knows nothing of ``gen:`` names (:mod:`.kitchens` resolves
them, a floor above), so this module imports it and keeps no copy of its accessors.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .codes import STATIONS, WALKABLE, Cell
from .generate_families import REQUIRED
from ..errors import MapFormatError
from .grid import distances, grid_neighbors
from .maps import Layout, load_map

_BOARD, _DELIVERY = int(Cell.BOARD), int(Cell.DELIVERY)
_STEPS = ((0, 1), (1, 0), (0, -1), (-1, 0))


def _walkable(grid: np.ndarray) -> list[bool]:
    return [int(v) in WALKABLE for v in grid.ravel()]


def floor_components(grid: np.ndarray, skip: frozenset[int] = frozenset()) -> list[set[int]]:
    """The 4-connected components of the walkable cells of ``grid`` (flat indices), cells
    in ``skip`` left out, in order of their first cell."""
    rows, cols = grid.shape
    walk = [w and i not in skip for i, w in enumerate(_walkable(grid))]
    nbrs = grid_neighbors(rows, cols)
    seen: set[int] = set()
    out = []
    for cell, ok in enumerate(walk):
        if ok and cell not in seen:
            dist = distances(nbrs, walk, [cell])
            comp = {i for i, d in enumerate(dist) if d >= 0}
            seen |= comp
            out.append(comp)
    return out


def spawn_cuts_off(grids: list[np.ndarray], cell: tuple[int, int],
                   others: list[tuple[int, int]]) -> bool:
    """Would a cook standing still on ``cell`` cut a cook on one of the cells ``others`` off a
    station (or the window) it reaches without it, in one of the layouts ``grids`` (the
    cell is the only way in front of the station, or on a one-lane way to it)?"""
    rows, cols = grids[0].shape
    flat = cell[0] * cols + cell[1]
    nbrs = grid_neighbors(rows, cols)
    stations = {int(s) for s in STATIONS}
    for grid in grids:
        codes = grid.reshape(-1)

        def touched(cells: set[int], codes=codes) -> set[int]:
            return {n for f in cells for n in nbrs[f] if n >= 0 and int(codes[n]) in stations}

        before = floor_components(grid)
        after = floor_components(grid, frozenset({flat}))
        for r, c in others:
            q = r * cols + c
            comp = next((p for p in before if q in p), None)
            if comp is None or flat not in comp or q == flat:
                continue
            piece = next(p for p in after if q in p)
            if touched(piece) != touched(comp):
                return True
    return False


def lane_cells(grid: np.ndarray) -> list[tuple[int, int]]:
    """Walkable cells in a one-cell-wide passage: walkable neighbours on exactly two opposite
    sides and walls on the other two (two cooks cannot pass each other there)."""
    rows, cols = grid.shape
    walk = np.isin(grid, [int(c) for c in WALKABLE])
    out = []
    for r in range(1, rows - 1):
        for c in range(1, cols - 1):
            if not walk[r, c]:
                continue
            across, along = walk[r, c - 1] and walk[r, c + 1], walk[r - 1, c] and walk[r + 1, c]
            horizontal = across and not (walk[r - 1, c] or walk[r + 1, c])
            vertical = along and not (walk[r, c - 1] or walk[r, c + 1])
            if horizontal or vertical:
                out.append((r, c))
    return out


def _touches(layout: Layout, code: int, comp: set[int]) -> bool:
    return any(_touches_cell(layout, cell, comp) for cell in layout.cells_of(code))


def station_reach(layout: Layout, index: int) -> list[tuple[int, tuple[int, int], set[int]]]:
    """(station code, cell, the spawn points whose floor touches it) in layout ``index``."""
    grid = layout.grids()[index]
    comps = floor_components(grid)
    cols = layout.cols
    spawn_of = [next((k for k, comp in enumerate(comps) if r * cols + c in comp), -1)
                for r, c in layout.spawn_points]
    out = []
    for code in sorted(int(s) for s in STATIONS):
        for cell in layout.cells_of(code):
            near = {k for k, comp in enumerate(comps) if _touches_cell(layout, cell, comp)}
            out.append((code, cell, {i for i, k in enumerate(spawn_of) if k in near}))
    return out


def structure_problems(kitchen: dict[str, Any] | Layout, family: str,
                       preset: str = "hard") -> list[str]:
    """What keeps a kitchen (a map dict or a loaded Layout) from being a sound kitchen of
    ``family`` (empty: nothing).

    Every kitchen: the preset's stations are there and, in the main layout, reachable
    from the first cook (from the first two for ``split``). Then per family: ``open`` one
    connected floor; ``split`` two floors, the first two cooks on different ones, window
    and boards on different sides, and counters touching both; ``corridor`` one connected
    floor with one-lane cells; ``switching`` a station kind reachable in the main layout and
    cut off from every cook in the switch layout; ``multiroom`` one floor of two rooms or
    more joined by one-cell doors."""
    if isinstance(kitchen, Layout):
        layout = kitchen
    else:
        try:
            layout = load_map(kitchen)
        except MapFormatError as exc:
            return [str(exc)]
    problems = [f"no {Cell(c).name.lower()}" for c in sorted(REQUIRED[preset])
                if not layout.cells_of(c)]
    cols = layout.cols
    comps = floor_components(layout.grid)
    spawn_comp = [next(i for i, comp in enumerate(comps) if r * cols + c in comp)
                  for r, c in layout.spawn_points]
    first = {0, 1} if family == "split" else {0}
    problems += [f"{Cell(code).name.lower()} at {cell} unreachable from the first cooks"
                 for code, cell, by in station_reach(layout, 0) if not by & first]
    problems += _FAMILY_CHECKS[family](layout, comps, spawn_comp)
    return problems


def _check_open(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    return [] if len(comps) == 1 else [f"{len(comps)} separate floors; an open kitchen has one"]


def _check_split(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    if len(comps) != 2:
        return [f"{len(comps)} separate floors; a split kitchen has two"]
    out = []
    if len(spawn_comp) < 2 or spawn_comp[0] == spawn_comp[1]:
        out.append("the first two cooks are not on different halves")
    window = [i for i, comp in enumerate(comps) if _touches(layout, _DELIVERY, comp)]
    boards = [i for i, comp in enumerate(comps) if _touches(layout, _BOARD, comp)]
    if set(window) & set(boards):
        out.append("a half has both the window and a board: no hand-over is needed")
    passes = [(r, c) for r in range(layout.rows) for c in range(layout.cols)
              if int(layout.grid[r, c]) == Cell.COUNTER
              and all(_touches_cell(layout, (r, c), comp) for comp in comps)]
    if not passes:
        out.append("no pass-through counter touches both halves")
    return out


def _touches_cell(layout: Layout, cell: tuple[int, int], comp: set[int]) -> bool:
    r, c = cell
    return any(0 <= r + dr < layout.rows and 0 <= c + dc < layout.cols
               and (r + dr) * layout.cols + c + dc in comp for dr, dc in _STEPS)


def _check_corridor(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    out = [] if len(comps) == 1 else [f"{len(comps)} separate floors; a corridor kitchen has one"]
    if not lane_cells(layout.grid):
        out.append("no one-lane cell")
    return out


def _check_switching(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    if layout.switch_grid is None or not layout.is_dynamic:
        return ["no switch layout"]
    entries = station_reach(layout, 1)
    cut = {code for code, _, _ in entries} - {code for code, _, by in entries if by}
    return [] if cut else ["the switch layout cuts no station kind off"]


def _check_multiroom(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    if len(comps) != 1:
        return [f"{len(comps)} separate floors; the rooms must be joined by doors"]
    doors = frozenset(r * layout.cols + c for r, c in lane_cells(layout.grid))
    rooms = [comp for comp in floor_components(layout.grid, doors) if len(comp) >= 2]
    return [] if len(rooms) >= 2 else ["fewer than two rooms"]


_FAMILY_CHECKS = {
    "open": _check_open,
    "split": _check_split,
    "corridor": _check_corridor,
    "switching": _check_switching,
    "multiroom": _check_multiroom,
}

"""A seeded kitchen generator: families of kitchens, fixed train/test splits, ``gen:`` names.

:func:`generate_map` returns the map dict that :func:`.maps.load_map` accepts (the YAML
file's keys); :func:`map_to_yaml` writes it. The same arguments give the same bytes: every
draw comes from a ``numpy.random.Generator`` seeded by (family, seed, candidate), and
nothing iterates over an unordered collection.

Families (:mod:`.generate_families` draws their walls):

- ``open``: one room, sometimes with a counter island;
- ``split``: two halves divided by a wall of counters; ingredients and window on one side,
  boards and pan on the other, so every dish is handed over the wall (2 cooks or more);
- ``corridor``: two rooms joined by a one-lane corridor that cooks cannot pass in;
- ``switching``: an alcove behind a gate that the switch layout walls off with blocks;
  the only boards (or the only pan) are in the alcove;
- ``multiroom``: two to four rooms with one-cell doors.

Each kitchen carries the stations of its ``preset`` (SPEC section 7) and one spawn point per
cook; :func:`structure_problems` checks what its family promises, and a draw that fails
is replaced by the next draw of the same seed. Splits: index ``i`` of ``train`` is seed
``i``, of ``test`` seed ``TEST_SEED_BASE + i`` (see :data:`SPLITS`); ``gen:FAMILY:SPLIT:
INDEX[:PRESET]`` names that kitchen wherever a map name is accepted.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from ..errors import ConfigError, MapFormatError
from .codes import WALKABLE, Cell
from .generate_families import BUILDERS, MAX_SIZE, MIN_COOKS, MIN_SIZE, Retry, Sketch
from .maps import Layout, load_map, station_reachability
from .queries import distances, grid_neighbors

FAMILIES: tuple[str, ...] = tuple(BUILDERS)
#: split name -> first seed; index i of a split is seed ``first + i``, i < SPLIT_SIZE
SPLIT_SIZE = 1_000_000
TEST_SEED_BASE = 1_000_000
SPLITS: dict[str, int] = {"train": 0, "test": TEST_SEED_BASE}
GEN_PREFIX = "gen:"
#: draws tried per candidate before the size is declared too small
MAX_DRAWS = 200
MAX_COOKS = 4

_T, _L, _O, _S = int(Cell.TOMATO), int(Cell.LETTUCE), int(Cell.ONION), int(Cell.STEAK)
_BOARD, _PLATE, _DELIVERY = int(Cell.BOARD), int(Cell.PLATE), int(Cell.DELIVERY)
_PAN, _TRASH, _SINK = int(Cell.PAN), int(Cell.TRASH), int(Cell.SINK)
#: preset -> (station code, fewest, most) placed on its kitchens
PRESET_STATIONS: dict[str, tuple[tuple[int, int, int], ...]] = {
    "easy": ((_DELIVERY, 1, 1), (_BOARD, 1, 2), (_PLATE, 1, 2), (_T, 1, 1), (_L, 1, 1),
             (_O, 1, 1)),
}
PRESET_STATIONS["medium"] = PRESET_STATIONS["easy"] + ((_PAN, 1, 1), (_S, 1, 1),
                                                       (_TRASH, 1, 1))
PRESET_STATIONS["hard"] = PRESET_STATIONS["medium"] + ((_SINK, 1, 1),)
#: the stations :func:`structure_problems` requires of a preset's kitchens
REQUIRED: dict[str, frozenset[int]] = {p: frozenset(c for c, _, _ in s)
                                       for p, s in PRESET_STATIONS.items()}
_FAMILY_ID = {f: i for i, f in enumerate(FAMILIES)}
_SWITCH_STEPS = (10, 20)


def _check_args(family: str, preset: str, rows: int | None, cols: int | None,
                cooks: int | None) -> None:
    if family not in BUILDERS:
        raise ConfigError(f"unknown kitchen family {family!r}; choose one of {', '.join(FAMILIES)}")
    if preset not in PRESET_STATIONS:
        raise ConfigError(f"unknown preset {preset!r} for the generator; choose one of "
                          f"{', '.join(PRESET_STATIONS)}")
    lo_r, lo_c = MIN_SIZE[family]
    for name, value, lo in (("rows", rows, lo_r), ("cols", cols, lo_c)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                                  or not lo <= value <= MAX_SIZE):
            raise ConfigError(f"{name}={value!r}: a {family} kitchen has {lo} to {MAX_SIZE} "
                              f"{name}")
    lo_k = MIN_COOKS[family]
    if cooks is not None and (isinstance(cooks, bool) or not isinstance(cooks, int)
                              or not lo_k <= cooks <= MAX_COOKS):
        why = " (one per half at least)" if family == "split" else ""
        raise ConfigError(f"cooks={cooks!r}: a {family} kitchen takes {lo_k} to {MAX_COOKS} "
                          f"cooks{why}")


def generate_map(family: str, seed: int, *, rows: int | None = None, cols: int | None = None,
                 cooks: int | None = None, preset: str = "hard", candidate: int = 0,
                 name: str | None = None) -> dict[str, Any]:
    """The map dict of one generated kitchen (keys as in a YAML map file).

    ``rows``, ``cols`` (each from the family's minimum, see
    :data:`.generate_families.MIN_SIZE`, to 12) and ``cooks`` (1-4; 2-4 for ``split``)
    are drawn from ``seed`` when not given: sizes uniformly, cooks 3 or 4 (so 1 to 3
    cooks can play every kitchen). ``candidate`` k returns the k-th sound draw of this
    seed (a kitchen that fails a later check is replaced by the next candidate). Bad
    arguments raise :class:`ConfigError`.
    """
    _check_args(family, preset, rows, cols, cooks)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"seed must be an integer >= 0, got {seed!r}")
    if isinstance(candidate, bool) or not isinstance(candidate, int) or candidate < 0:
        raise ConfigError(f"candidate must be an integer >= 0, got {candidate!r}")
    fid = _FAMILY_ID[family]
    size_rng = np.random.default_rng([fid, seed])
    lo_r, lo_c = MIN_SIZE[family]
    drawn = (int(size_rng.integers(lo_r, MAX_SIZE + 1)), int(size_rng.integers(lo_c, MAX_SIZE + 1)),
             int(size_rng.integers(max(3, MIN_COOKS[family]), MAX_COOKS + 1)))
    shape = (rows or drawn[0], cols or drawn[1])
    n_cooks = cooks or drawn[2]
    label = name or f"gen-{family}-{seed}" + (f"-c{candidate}" if candidate else "")
    sound = 0
    for draw in range(MAX_DRAWS * (candidate + 1)):
        rng = np.random.default_rng([fid, seed, draw])
        try:
            spec = _draw(family, rng, shape, n_cooks, preset, label)
        except Retry:
            continue
        if structure_problems(load_map(spec), family, preset):
            continue
        if sound == candidate:
            spec["description"] += f" Seed {seed}, draw {draw}."
            return spec
        sound += 1
    raise ConfigError(
        f"could not draw a sound {family} kitchen of {shape[0]}x{shape[1]} with {n_cooks} "
        f"cooks and the {preset} stations (candidate {candidate}); give more rows/cols or "
        "fewer cooks")


def _draw(family: str, rng: np.random.Generator, shape: tuple[int, int], cooks: int,
          preset: str, name: str) -> dict[str, Any]:
    rows, cols = shape
    codes = tuple(c for c, _, _ in PRESET_STATIONS[preset])
    sketch = BUILDERS[family](rng, rows, cols, cooks, codes)
    grid = sketch.grid.copy()
    switch = None if sketch.switch_grid is None else sketch.switch_grid.copy()
    _place_stations(sketch, rng, PRESET_STATIONS[preset], grid, switch)
    spawns = _place_cooks(sketch, rng)
    spec: dict[str, Any] = {
        "name": name,
        "description": f"Generated {family} kitchen ({preset} stations, {cooks} cooks).",
        "dimensions": [cols, rows],
        "game_map": grid.tolist(),
        "max_n_agent": cooks,
        "is_dynamic_map": switch is not None,
    }
    if switch is not None:
        spec["switch_map"] = switch.tolist()
        spec["map_switch_step"] = int(rng.integers(_SWITCH_STEPS[0], _SWITCH_STEPS[1] + 1))
    else:
        spec["map_switch_step"] = 0
    spec["agent_spawn_points"] = [list(p) for p in spawns]
    return spec


def _touching(sketch: Sketch) -> dict[tuple[int, int], frozenset[str]]:
    """Plain counter cells (in every layout) -> the regions whose floor they touch."""
    owner = {cell: region for region, cells in sketch.regions.items() for cell in cells}
    grids = [sketch.grid] if sketch.switch_grid is None else [sketch.grid, sketch.switch_grid]
    rows, cols = sketch.grid.shape
    out: dict[tuple[int, int], frozenset[str]] = {}
    for r in range(rows):
        for c in range(cols):
            if (r, c) in sketch.reserved or any(int(g[r, c]) != Cell.COUNTER for g in grids):
                continue
            near = {owner[n] for n in ((r, c + 1), (r + 1, c), (r, c - 1), (r - 1, c))
                    if n in owner}
            if near:
                out[(r, c)] = frozenset(near)
    return out


def _place_stations(sketch: Sketch, rng: np.random.Generator,
                    wants: tuple[tuple[int, int, int], ...], grid: np.ndarray,
                    switch: np.ndarray | None) -> None:
    """Put each wanted station on a free counter touching only its allowed regions:
    the constrained kinds first, then one of every kind, then the optional extras."""
    touching = _touching(sketch)
    free = sorted(touching)
    ordered = sorted(wants, key=lambda w: (w[0] not in sketch.station_regions, w[0]))
    rounds = [(code, True) for code, _, _ in ordered]
    for code, lo, hi in ordered:
        extra = int(rng.integers(lo, hi + 1)) - 1
        rounds += [(code, lo > 1 + k) for k in range(extra)]
    for code, required in rounds:
        allowed = sketch.station_regions.get(code)
        pool = [cell for cell in free if allowed is None or touching[cell] <= set(allowed)]
        if not pool:
            if required:
                raise Retry
            continue
        cell = pool[int(rng.integers(len(pool)))]
        free.remove(cell)
        grid[cell] = code
        if switch is not None:
            switch[cell] = code


def _place_cooks(sketch: Sketch, rng: np.random.Generator) -> list[tuple[int, int]]:
    taken: set[tuple[int, int]] = set()
    spawns = []
    for region in sketch.cook_regions:
        pool = [c for c in sketch.regions[region] if c not in taken and c not in sketch.reserved]
        if not pool:
            raise Retry
        cell = pool[int(rng.integers(len(pool)))]
        taken.add(cell)
        spawns.append(cell)
    return spawns


# ------------------------------------------------------------------ structure checks

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
            horizontal = walk[r, c - 1] and walk[r, c + 1] and not (walk[r - 1, c] or walk[r + 1, c])
            vertical = walk[r - 1, c] and walk[r + 1, c] and not (walk[r, c - 1] or walk[r, c + 1])
            if horizontal or vertical:
                out.append((r, c))
    return out


def _touches(layout: Layout, code: int, comp: set[int]) -> bool:
    cols = layout.cols
    return any(((r + dr) * cols + c + dc) in comp for r, c in layout.cells_of(code)
               for dr, dc in ((0, 1), (1, 0), (0, -1), (-1, 0))
               if 0 <= r + dr < layout.rows and 0 <= c + dc < cols)


def structure_problems(layout: Layout, family: str, preset: str = "hard") -> list[str]:
    """What keeps ``layout`` from being a sound kitchen of ``family`` (empty: none).

    Every kitchen: the preset's stations are there and, in the main layout, reachable
    from the first cook (from the first two for ``split``). Then per family: ``open`` one
    connected floor; ``split`` two floors, the first two cooks on different ones, window
    and boards on different sides, and counters touching both; ``corridor`` one connected
    floor with one-lane cells; ``switching`` a station kind reachable in the main layout and
    cut off from every cook in the switch layout; ``multiroom`` one floor of two rooms or
    more joined by one-cell doors."""
    problems = [f"no {Cell(c).name.lower()}" for c in sorted(REQUIRED[preset])
                if not layout.cells_of(c)]
    cols = layout.cols
    comps = floor_components(layout.grid)
    spawn_comp = [next(i for i, comp in enumerate(comps) if r * cols + c in comp)
                  for r, c in layout.spawn_points]
    first = {spawn_comp[0]} | ({spawn_comp[1]} if family == "split" and len(spawn_comp) > 1
                               else set())
    unreached = [e for e in station_reachability(layout) if e["layout"] == 0
                 and not set(e["reachable_from"]) & {i for i, k in enumerate(spawn_comp)
                                                      if k in first}]
    problems += [f"{Cell(e['code']).name.lower()} at {e['cell']} unreachable from the first "
                 "cooks" for e in unreached]
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
               and (r + dr) * layout.cols + c + dc in comp
               for dr, dc in ((0, 1), (1, 0), (0, -1), (-1, 0)))


def _check_corridor(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    out = [] if len(comps) == 1 else [f"{len(comps)} separate floors; a corridor kitchen has one"]
    if not lane_cells(layout.grid):
        out.append("no one-lane cell")
    return out


def _check_switching(layout: Layout, comps: list[set[int]], spawn_comp: list[int]) -> list[str]:
    if layout.switch_grid is None or not layout.is_dynamic:
        return ["no switch layout"]
    entries = [e for e in station_reachability(layout) if e["layout"] == 1]
    reached = {e["code"] for e in entries if e["reachable_from"]}
    cut = {e["code"] for e in entries} - reached
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


# ------------------------------------------------------------------ splits and names

def split_seed(split: str, index: int) -> int:
    """The seed of kitchen ``index`` of a split (``train``: seed = index; ``test``:
    seed = 1,000,000 + index)."""
    if split not in SPLITS:
        raise ConfigError(f"unknown split {split!r}; choose one of {', '.join(SPLITS)}")
    if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < SPLIT_SIZE:
        raise ConfigError(f"split index must be an integer from 0 to {SPLIT_SIZE - 1}, "
                          f"got {index!r}")
    return SPLITS[split] + index


def parse_gen_name(text: str) -> tuple[str, str, int, str]:
    """``gen:FAMILY:SPLIT:INDEX[:PRESET]`` -> (family, split, index, preset)."""
    parts = text.split(":")
    usage = ("write gen:FAMILY:SPLIT:INDEX[:PRESET], e.g. gen:split:test:3 or "
             f"gen:open:train:0:easy (families: {', '.join(FAMILIES)}; splits: "
             f"{', '.join(SPLITS)}; presets: {', '.join(PRESET_STATIONS)})")
    if parts[0] != GEN_PREFIX[:-1] or len(parts) not in (4, 5):
        raise MapFormatError(f"map {text!r}: {usage}")
    family, split, index_text = parts[1:4]
    preset = parts[4] if len(parts) == 5 else "hard"
    if family not in BUILDERS or split not in SPLITS or preset not in PRESET_STATIONS \
            or not index_text.isdigit():
        raise MapFormatError(f"map {text!r}: {usage}")
    return family, split, int(index_text), preset


def map_from_name(text: str) -> dict[str, Any]:
    """The map dict a ``gen:`` name stands for (:func:`parse_gen_name`)."""
    family, split, index, preset = parse_gen_name(text)
    try:
        seed = split_seed(split, index)
    except ConfigError as exc:
        raise MapFormatError(f"map {text!r}: {exc}") from None
    return generate_map(family, seed, preset=preset, name=text)


def map_to_yaml(spec: dict[str, Any]) -> str:
    """A generated map dict as YAML text, rows on one line each (the same dict, the same
    bytes)."""
    lines = []
    for key, value in spec.items():
        if key in ("game_map", "switch_map"):
            lines.append(f"{key}:")
            lines += [f"  - [{', '.join(str(v) for v in row)}]" for row in value]
        else:
            lines.append(f"{key}: {json.dumps(value)}")
    return "\n".join(lines) + "\n"


__all__ = [
    "FAMILIES",
    "GEN_PREFIX",
    "PRESET_STATIONS",
    "SPLITS",
    "floor_components",
    "generate_map",
    "lane_cells",
    "map_from_name",
    "map_to_yaml",
    "parse_gen_name",
    "split_seed",
    "structure_problems",
]

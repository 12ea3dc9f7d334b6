"""A seeded kitchen generator: families of kitchens, fixed train/test splits, ``gen:`` names.

:func:`generate_map` returns the map dict that :func:`.maps.load_map` accepts (the YAML
file's keys); :func:`map_to_yaml` writes it. The same arguments give the same bytes: every
draw comes from a ``numpy.random.Generator`` seeded by (family, seed, draw number), and
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
from .codes import Cell
from .generate_families import (
    BUILDERS,
    MAX_SIZE,
    MIN_COOKS,
    MIN_SIZE,
    PRESET_STATIONS,
    REQUIRED,
    Retry,
    Sketch,
)
from .generate_checks import floor_components, lane_cells, spawn_cuts_off, structure_problems

FAMILIES: tuple[str, ...] = tuple(BUILDERS)
#: split name -> first seed; index i of a split is seed ``first + i``, i < SPLIT_SIZE
SPLIT_SIZE = 1_000_000
TEST_SEED_BASE = 1_000_000
SPLITS: dict[str, int] = {"train": 0, "test": TEST_SEED_BASE}
GEN_PREFIX = "gen:"
#: draws tried per candidate before the size is declared too small
MAX_DRAWS = 200
MAX_COOKS = 4

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
        if structure_problems(spec, family, preset):
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
    spawns = _place_cooks(sketch, rng, [grid] if switch is None else [grid, switch])
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


def _place_cooks(sketch: Sketch, rng: np.random.Generator,
                 grids: list[np.ndarray]) -> list[tuple[int, int]]:
    """One spawn cell per cook in its region, never one where a cook standing still cuts
    any floor off a station or the window (``spawn_cuts_off``, in every layout: the only
    cell in front of a station, or on a one-lane way to it): a drawn cell that does is
    moved to the nearest one that does not (no other draw, so the rest of the kitchen
    stays as it was drawn). Only where every free cell of the region does (a one-lane
    region) does the drawn cell stay."""
    taken: set[tuple[int, int]] = set()
    spawns: list[tuple[int, int]] = []
    rows, cols = grids[0].shape
    floor = [(r, c) for r in range(rows) for c in range(cols)
             if any(int(g[r, c]) == Cell.FLOOR for g in grids)]

    def cuts(cell: tuple[int, int]) -> bool:
        return spawn_cuts_off(grids, cell, floor)

    for region in sketch.cook_regions:
        pool = [c for c in sketch.regions[region] if c not in taken and c not in sketch.reserved]
        if not pool:
            raise Retry
        cell = pool[int(rng.integers(len(pool)))]
        if cuts(cell):
            cell = min((c for c in pool if not cuts(c)), default=cell,
                       key=lambda c: (abs(c[0] - cell[0]) + abs(c[1] - cell[1]), c))
        taken.add(cell)
        spawns.append(cell)
    return spawns


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
            or not (index_text.isascii() and index_text.isdigit()):
        raise MapFormatError(f"map {text!r}: {usage}")
    return family, split, int(index_text), preset


def map_from_name(text: str) -> dict[str, Any]:
    """The map dict a ``gen:`` name stands for (:func:`parse_gen_name`)."""
    family, split, index, preset = parse_gen_name(text)
    try:
        seed = split_seed(split, index)
    except ConfigError as exc:
        raise MapFormatError(f"map {text!r}: {exc}") from None
    return generate_map(family, seed, preset=preset, name=text,
                        candidate=first_candidate(family, split, index, preset))


#: (family, split, index) -> the candidate a ``gen:`` name loads where candidate 0 failed
#: its proof (hard stations, every cook; experiments/results/generated_kitchens/)
PROOF_REPLACEMENTS: dict[tuple[str, str, int], int] = {("multiroom", "test", 5): 1}


def first_candidate(family: str, split: str, index: int, preset: str = "hard") -> int:
    """The candidate a split's kitchen starts from: 0, or the proven replacement listed in
    :data:`PROOF_REPLACEMENTS` (for the hard stations it was proven with)."""
    return PROOF_REPLACEMENTS.get((family, split, index), 0) if preset == "hard" else 0


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
    "REQUIRED",
    "SPLITS",
    "first_candidate",
    "floor_components",
    "generate_map",
    "lane_cells",
    "map_from_name",
    "map_to_yaml",
    "parse_gen_name",
    "split_seed",
    "structure_problems",
]

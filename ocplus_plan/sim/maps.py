"""Map files (SPEC section 2): loading, validation and the ``maps/`` registry.

``load_map`` accepts a registered name (``"mapC"``), a path to a YAML file, or an
already-parsed dict. Every problem is a :class:`MapFormatError` whose message names
the source, and the row / column / value or key at fault. Files are read by
:mod:`.map_yaml` within limits (size, nesting, aliases, repeated keys, UTF-8); a grid
has at most ``MAX_GRID_SIDE`` (64) rows and columns (``docs/input-limits.md``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import MapFormatError
from .codes import (
    COUNTERS,
    SPAWN_TILES,
    STATIONS,
    SWITCHABLE,
    VALID_CODES,
    WALKABLE,
    Cell,
)
from .dishes import Dish, parse_recipes
from .process_yaml import parse_processes
from .processes import ADDED, PROCESSES, Process
from .grid import distances, grid_neighbors

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

#: canonical key -> accepted spellings (the paper's first).
KEY_ALIASES: dict[str, tuple[str, ...]] = {
    "name": ("name",),
    "description": ("description",),
    "dimensions": ("dimensions",),
    "game_map": ("game_map", "map"),
    "max_n_agent": ("max_n_agent", "max_n_agnet", "max_agents"),
    "is_dynamic_map": ("is_dynamic_map", "dynamic_map"),
    "switch_map": ("switch_map",),
    "map_switch_step": ("map_switch_step",),
    "agent_spawn_points": ("agent_spawn_points", "agent_initial_coordinates"),
    "processes": ("processes",),
    "recipes": ("recipes",),
}
_SPELLING_TO_KEY = {s: k for k, spellings in KEY_ALIASES.items() for s in spellings}



@dataclass(frozen=True, eq=False)
class Layout:
    """A loaded map: the main grid, the optional switch grid and the spawn points.

    Grids are read-only ``int8`` arrays of cell codes, shape ``(rows, cols)``.
    """

    name: str
    source: str
    grid: np.ndarray
    switch_grid: np.ndarray | None
    spawn_points: tuple[tuple[int, int], ...]
    max_agents: int
    is_dynamic: bool
    #: steps between switches; 0 is allowed on a static map (it never switches)
    map_switch_step: int
    description: str = ""
    #: cell code -> sorted (row, col) cells of that station / spawn tile kind
    stations: dict[int, tuple[tuple[int, int], ...]] = field(default_factory=dict)
    #: ``max_n_agent`` as the file says it (``max_agents`` is capped at the spawn count)
    declared_max_agents: int = 0
    #: the kitchen's process-station records (``processes``); None: the shipped ones
    processes: tuple[Process, ...] | None = None
    #: the kitchen's dishes (``recipes``): its menu; None: the preset draws its pool
    recipes: tuple[Dish, ...] | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.grid.shape[0]), int(self.grid.shape[1]))

    @property
    def rows(self) -> int:
        return int(self.grid.shape[0])

    @property
    def cols(self) -> int:
        return int(self.grid.shape[1])

    def grids(self) -> tuple[np.ndarray, ...]:
        """The layouts in switching order: main first, then the switch grid if any."""
        return (self.grid,) if self.switch_grid is None else (self.grid, self.switch_grid)

    def switching_cells(self) -> list[tuple[int, int]]:
        if self.switch_grid is None:
            return []
        rr, cc = np.nonzero(self.grid != self.switch_grid)
        return [(int(r), int(c)) for r, c in zip(rr, cc)]

    def cells_of(self, code: Cell | int) -> tuple[tuple[int, int], ...]:
        return self.stations.get(int(code), ())

    def spawn_tile_counts(self) -> dict[int, int]:
        return {int(c): len(self.cells_of(c)) for c in SPAWN_TILES}


def available_maps() -> dict[str, Traversable]:
    """Registered map names -> files: the shipped maps (package data from ``maps/``) plus
    the ``*.yaml`` files of the ``OCPLUS_MAPS`` folders."""
    from ..data import data_files

    folders: list[Traversable] = [data_files("maps")]
    extra = os.environ.get("OCPLUS_MAPS", "")
    folders += [Path(p) for p in extra.split(os.pathsep) if p]
    found: dict[str, Traversable] = {}
    for folder in folders:
        if folder.is_dir():
            files = sorted((f for f in folder.iterdir() if f.name.endswith(".yaml")),
                           key=lambda f: f.name)
            for file in files:
                found.setdefault(file.name[: -len(".yaml")], file)
    return found


def load_map(spec: str | os.PathLike[str] | dict[str, Any], *, source: str | None = None) -> Layout:
    """Load a map by registered name, by path, or from a dict (SPEC section 2)."""
    if isinstance(spec, dict):
        return _parse(spec, source or "<dict>")
    text_spec = os.fspath(spec)
    if text_spec.startswith("gen:"):  # generated kitchens load one floor up
        raise MapFormatError(f"map {text_spec!r} is a generated kitchen: load it with "
                             "sim.kitchens.load_kitchen (make_rules and the CLI do)")
    path: Traversable = Path(text_spec)
    if not path.is_file():
        registry = available_maps()
        if text_spec in registry:
            path = registry[text_spec]
        else:
            names = ", ".join(sorted(registry)) or "(none)"
            raise MapFormatError(
                f"map {text_spec!r}: no such file and no registered map of that name; "
                f"registered maps: {names}"
            )
    from .map_yaml import load_yaml  # local: the core imports pyyaml only when a file is read

    raw = load_yaml(path)
    if raw is None:
        raise MapFormatError(f"{path}: the file is empty; a map needs at least 'game_map'")
    if not isinstance(raw, dict):
        raise MapFormatError(
            f"{path}: expected a mapping of keys (name, game_map, ...), got {type(raw).__name__}"
        )
    return _parse(raw, str(path))


#: the largest grid, in rows and in columns (SPEC section 2)
MAX_GRID_SIDE = 64


def _short(value: Any, limit: int = 60) -> str:
    """``repr(value)``, cut to ``limit`` characters (a message stays one short line)."""
    if isinstance(value, (list, dict)) and len(value) > limit:  # no repr of a huge value
        return f"<a {type(value).__name__} of {len(value)} items>"
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _canonical_keys(raw: dict[str, Any], src: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    seen_as: dict[str, str] = {}
    for key, value in raw.items():
        canon = _SPELLING_TO_KEY.get(key) if isinstance(key, str) else None
        if canon is None:
            allowed = ", ".join(sorted(_SPELLING_TO_KEY))
            raise MapFormatError(f"{src}: unknown key {_short(key)}; allowed keys: {allowed}")
        if canon in out:
            raise MapFormatError(
                f"{src}: key {key!r} repeats {seen_as[canon]!r} (two spellings of one key); keep one"
            )
        out[canon] = value
        seen_as[canon] = str(key)
    return out


def _parse_grid(value: Any, src: str, key: str) -> np.ndarray:
    if not isinstance(value, list) or not value:
        raise MapFormatError(f"{src}: '{key}' must be a non-empty list of rows of integer codes")
    if len(value) > MAX_GRID_SIDE:
        raise MapFormatError(f"{src}: '{key}' has {len(value)} rows; a map has at most "
                             f"{MAX_GRID_SIDE} rows and {MAX_GRID_SIDE} columns")
    width = None
    for r, row in enumerate(value):
        if not isinstance(row, list) or not row:
            raise MapFormatError(f"{src}: '{key}' row {r} must be a non-empty list, "
                                 f"got {_short(row)}")
        if len(row) > MAX_GRID_SIDE:
            raise MapFormatError(f"{src}: '{key}' row {r} has {len(row)} cells; a map has at "
                                 f"most {MAX_GRID_SIDE} rows and {MAX_GRID_SIDE} columns")
        if width is None:
            width = len(row)
        elif len(row) != width:
            raise MapFormatError(
                f"{src}: '{key}' row {r} has {len(row)} cells but row 0 has {width}; "
                "every row must have the same length"
            )
        for c, v in enumerate(row):
            if isinstance(v, bool) or not isinstance(v, int) or v not in VALID_CODES:
                codes = ", ".join(str(x) for x in sorted(VALID_CODES))
                raise MapFormatError(f"{src}: '{key}' row {r}, column {c}: invalid cell code "
                                     f"{_short(v)}; valid codes: {codes}")
    grid = np.array(value, dtype=np.int8)
    grid.setflags(write=False)
    return grid


def _check_dimensions(dims: Any, rows: int, cols: int, src: str) -> None:
    if not (isinstance(dims, list) and len(dims) == 2
            and all(isinstance(x, int) and not isinstance(x, bool) for x in dims)):
        raise MapFormatError(f"{src}: 'dimensions' must be [cols, rows], got {_short(dims)}")
    if tuple(dims) != (cols, rows):
        raise MapFormatError(
            f"{src}: 'dimensions' says {_short(dims)} ([cols, rows]) but game_map is "
            f"{cols} columns x {rows} rows"
        )


def _parse_switch_grid(value: Any, grid: np.ndarray, src: str) -> np.ndarray:
    switch_grid = _parse_grid(value, src, "switch_map")
    rows, cols = grid.shape
    if switch_grid.shape != grid.shape:
        raise MapFormatError(
            f"{src}: 'switch_map' is {switch_grid.shape[1]}x{switch_grid.shape[0]} "
            f"but game_map is {cols}x{rows} (cols x rows); they must match"
        )
    for r, c in zip(*np.nonzero(grid != switch_grid)):
        a, b = int(grid[r, c]), int(switch_grid[r, c])
        if a not in SWITCHABLE or b not in SWITCHABLE:
            raise MapFormatError(
                f"{src}: switch_map row {r}, column {c} changes {Cell(a).name.lower()} ({a}) "
                f"to {Cell(b).name.lower()} ({b}); a switch may only change block (-1), "
                "floor (0) and counter (1) cells, never move a station or spawn tile"
            )
    return switch_grid


def _parse_spawns(d: dict[str, Any], grids: list[np.ndarray], src: str) -> list[tuple[int, int]]:
    """``agent_spawn_points`` checked against every layout, or the spawn cells (code 2)."""
    rows, cols = grids[0].shape
    if "agent_spawn_points" not in d:
        spawns = [(int(r), int(c)) for r, c in zip(*np.nonzero(grids[0] == Cell.SPAWN))]
        if not spawns:
            raise MapFormatError(
                f"{src}: no spawn points: add 'agent_spawn_points' or cells with code 2"
            )
        return spawns
    pts = d["agent_spawn_points"]
    if not isinstance(pts, list) or not pts:
        raise MapFormatError(f"{src}: 'agent_spawn_points' must be a non-empty list of [row, col]")
    spawns = []
    for i, p in enumerate(pts):
        if not (isinstance(p, list) and len(p) == 2
                and all(isinstance(x, int) and not isinstance(x, bool) for x in p)):
            raise MapFormatError(f"{src}: agent_spawn_points[{i}] must be [row, col], "
                                 f"got {_short(p)}")
        r, c = p
        if not (0 <= r < rows and 0 <= c < cols):
            raise MapFormatError(
                f"{src}: agent_spawn_points[{i}] = [{r}, {c}] is outside the "
                f"{rows}-row x {cols}-column grid"
            )
        for g, label in zip(grids, ("game_map", "switch_map")):
            if int(g[r, c]) not in WALKABLE:
                raise MapFormatError(
                    f"{src}: agent_spawn_points[{i}] = [{r}, {c}] is on "
                    f"{Cell(int(g[r, c])).name.lower()} ({int(g[r, c])}) in {label}; "
                    "spawn points must be floor (0 or 2)"
                )
        spawns.append((r, c))
    if len(set(spawns)) != len(spawns):
        raise MapFormatError(f"{src}: agent_spawn_points has a repeated cell: {_short(pts)}")
    return spawns


def _text(d: dict[str, Any], key: str, default: str, src: str) -> str:
    value = d.get(key)
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        raise MapFormatError(f"{src}: '{key}' must be text, got a {type(value).__name__}")
    return str(value)


def _parse(raw: dict[str, Any], src: str) -> Layout:
    d = _canonical_keys(raw, src)
    if "game_map" not in d:
        raise MapFormatError(f"{src}: missing 'game_map' (alias 'map'), the grid of cell codes")
    grid = _parse_grid(d["game_map"], src, "game_map")
    rows, cols = grid.shape
    if "dimensions" in d:
        _check_dimensions(d["dimensions"], rows, cols, src)
    if not np.any(grid == Cell.DELIVERY):
        raise MapFormatError(f"{src}: no delivery cell (code 7); a kitchen needs one to serve orders")

    switch_grid = None
    if d.get("switch_map") is not None:
        switch_grid = _parse_switch_grid(d["switch_map"], grid, src)
    is_dynamic = d.get("is_dynamic_map", switch_grid is not None)
    if not isinstance(is_dynamic, bool):
        raise MapFormatError(f"{src}: 'is_dynamic_map' must be true or false, "
                             f"got {_short(is_dynamic)}")
    if is_dynamic and switch_grid is None:
        raise MapFormatError(f"{src}: 'is_dynamic_map' is true but there is no 'switch_map'")
    switch_step = _switch_step(d, bool(is_dynamic), src)
    spawns = _parse_spawns(d, [grid] if switch_grid is None else [grid, switch_grid], src)

    declared = d.get("max_n_agent", len(spawns))
    if isinstance(declared, bool) or not isinstance(declared, int) or declared < 1:
        raise MapFormatError(f"{src}: 'max_n_agent' must be a positive integer, "
                             f"got {_short(declared)}")

    stations: dict[int, tuple[tuple[int, int], ...]] = {}
    for code in STATIONS | {Cell.COUNTER}:
        cells = tuple((int(r), int(c)) for r, c in zip(*np.nonzero(grid == code)))
        if cells:
            stations[int(code)] = cells

    processes = None if d.get("processes") is None else parse_processes(d["processes"], src)
    _check_added_stations(stations, processes, src)
    recipes = None if d.get("recipes") is None else parse_recipes(
        d["recipes"], src, processes or PROCESSES, stations)
    default_name = Path(src).stem if src != "<dict>" else "unnamed"
    return Layout(
        name=_text(d, "name", "", src) or default_name,
        source=src,
        grid=grid,
        switch_grid=switch_grid,
        spawn_points=tuple(spawns),
        # more cooks than spawn points cannot be placed: the paper's mapF says 3 for 2
        max_agents=min(declared, len(spawns)),
        is_dynamic=bool(is_dynamic),
        map_switch_step=switch_step,
        description=_text(d, "description", "", src),
        stations=stations,
        declared_max_agents=declared,
        processes=processes,
        recipes=recipes,
    )


def _check_added_stations(stations: dict[int, Any], processes: tuple[Process, ...] | None,
                          src: str) -> None:
    """A process station added after the shipped ones (the oven) runs only by the
    kitchen's own record: refuse a map that places one without it."""
    running = {int(p.station) for p in processes or PROCESSES}
    for p in ADDED:
        code = int(p.station)
        if code in stations and code not in running:
            name = p.station.name.lower()
            raise MapFormatError(
                f"{src}: cell code {code} ({name}) at {list(stations[code][0])} has no record; "
                f"add one under 'processes' (station: {name}, verb: {p.verb}, takes: "
                f"[{', '.join(k.name.lower() for k in p.takes)}], ...) or remove the cell")


#: the switch period of a dynamic map that does not give one (SPEC section 2's MapC value)
DEFAULT_SWITCH_STEP = 15


def _switch_step(d: dict[str, Any], is_dynamic: bool, src: str) -> int:
    """``map_switch_step``: a positive integer on a dynamic map. A static map never switches,
    so any integer >= 0 is accepted there (the paper's static maps say 0)."""
    step = d.get("map_switch_step", DEFAULT_SWITCH_STEP)
    if isinstance(step, bool) or not isinstance(step, int) or step < (1 if is_dynamic else 0):
        need = "a positive integer on a dynamic map" if is_dynamic else "an integer >= 0"
        raise MapFormatError(f"{src}: 'map_switch_step' must be {need}, got {_short(step)}")
    return step


def reachable_floor(grid: np.ndarray, start: tuple[int, int]) -> set[tuple[int, int]]:
    """Floor cells reachable from ``start`` by 4-connected walking in ``grid``."""
    rows, cols = grid.shape
    walkable = [int(v) in WALKABLE for v in grid.ravel()]
    dist = distances(grid_neighbors(rows, cols), walkable, [start[0] * cols + start[1]])
    return {divmod(f, cols) for f, d in enumerate(dist) if d >= 0}


def floor_regions(grid: np.ndarray) -> dict[tuple[int, int], int]:
    """Each floor cell -> the number of its region (4-connected walking), in one pass."""
    rows, cols = grid.shape
    floor = {(r, c) for r in range(rows) for c in range(cols) if int(grid[r, c]) in WALKABLE}
    label: dict[tuple[int, int], int] = {}
    regions = 0
    for start in sorted(floor):
        if start in label:
            continue
        region, todo = regions, [start]
        regions += 1
        label[start] = region
        while todo:
            r, c = todo.pop()
            for n in ((r, c + 1), (r + 1, c), (r, c - 1), (r - 1, c)):
                if n in floor and n not in label:
                    label[n] = region
                    todo.append(n)
    return label


def station_reachability(layout: Layout) -> list[dict[str, Any]]:
    """For each station and layout: which spawn points can reach a floor cell next to it."""
    out = []
    for li, grid in enumerate(layout.grids()):
        region = floor_regions(grid)
        spawns_in: dict[int, list[int]] = {}
        for i, sp in enumerate(layout.spawn_points):
            if sp in region:
                spawns_in.setdefault(region[sp], []).append(i)
        for code, cells in sorted(layout.stations.items()):
            if code in COUNTERS and code not in SPAWN_TILES:
                continue
            for r, c in cells:
                near = {region[n] for n in ((r, c + 1), (r + 1, c), (r, c - 1), (r - 1, c))
                        if n in region}
                by = sorted(i for reg in near for i in spawns_in.get(reg, ()))
                out.append({"layout": li, "cell": (r, c), "code": code, "reachable_from": by})
    return out

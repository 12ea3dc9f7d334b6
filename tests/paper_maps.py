"""The map files of the paper's public repository, as test fixtures in the paper's format.

545659928/Overcooked-Plus ships ``overcookedPlus/maps/map{A..F}.yaml``. These fixtures are
written here from their grids (row lists) in that format, with its keys and quirks: ``map``,
``dynamic_map: False`` with ``map_switch_step: 0``, ``agent_initial_coordinates :`` (a space
before the colon), ``max_n_agent`` above the spawn count (mapF), ``dimensions`` as
``[cols, rows]`` and the ITEMIDX comment block. mapE is the one the paper's own format
forbids: its switch moves the sink and the onion.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class PaperMap:
    name: str
    rows: tuple[tuple[int, ...], ...]
    max_n_agent: int
    dynamic: bool
    switch_step: int
    spawns: tuple[tuple[int, int], ...]
    switch_rows: tuple[tuple[int, ...], ...] | None = None
    spaced_spawn_key: bool = False  # "agent_initial_coordinates :" as in mapC, mapE, mapF


_C_MAIN = ((1, 1, 1, 1, 1, 6, 1, 6, 1), (1, 0, 0, -1, 0, 0, 0, 0, 10),
           (1, 0, 0, -1, 0, 0, 0, 0, 1), (1, 0, 0, -1, 0, 0, 0, 0, 5),
           (7, 0, 0, 1, 1, 1, 1, 1, 1), (1, 0, 0, 0, 0, 0, 0, 0, 4),
           (1, 0, 0, 0, 0, 0, 0, 0, 8), (1, 0, 0, 0, 0, 0, 0, 0, 3),
           (1, 12, 1, 1, 1, 9, 1, 11, 1))
_C_SWITCH = ((1, 1, 1, 1, 1, 6, 1, 6, 1), (1, 0, 0, 0, 0, 0, 0, 0, 10),
             (1, 0, 0, 0, 0, 0, 0, 0, 1), (1, 0, 0, 0, 0, 0, 0, 0, 5),
             (7, 0, 0, 1, 1, 1, 1, 1, 1), (1, 0, 0, -1, 0, 0, 0, 0, 4),
             (1, 0, 0, -1, 0, 0, 0, 0, 8), (1, 0, 0, -1, 0, 0, 0, 0, 3),
             (1, 12, 1, 1, 1, 9, 1, 11, 1))

PAPER_MAPS: dict[str, PaperMap] = {
    "mapA": PaperMap(
        "mapA",
        ((1, 1, 1, 1, 1, 1, 1), (6, 0, 0, 0, 0, 0, 3), (1, 0, 0, 0, 0, 0, 8),
         (7, 0, 0, 0, 0, 0, 4), (1, 0, 0, 0, 0, 0, 1), (6, 0, 0, 0, 0, 0, 1),
         (1, 1, 1, 1, 5, 1, 1)),
        2, False, 0, ((5, 1), (5, 5))),
    "mapB": PaperMap(
        "mapB",
        ((1, 8, 10, 1, 4, 3, 1), (1, 0, 0, 1, 0, 0, 1), (7, 0, 0, 1, 0, 0, 9),
         (1, 0, 0, 1, 0, 0, 1), (6, 0, 0, 1, 0, 0, 1), (6, 0, 0, 0, 0, 0, 12),
         (1, 1, 1, 5, 1, 1, 1)),
        3, False, 0, ((1, 1), (1, 5), (5, 1))),
    "mapC": PaperMap("mapC", _C_MAIN, 3, True, 15, ((1, 7), (7, 7), (1, 4)), _C_SWITCH, True),
    "mapD": PaperMap(
        "mapD",
        ((1, 1, 1, 3, 1), (6, 0, 0, 0, 1), (1, 0, 0, 0, 1), (1, 0, 0, 0, 5), (1, 1, 7, 1, 1)),
        2, False, 0, ((2, 2), (2, 3))),
    "mapE": PaperMap(
        "mapE",
        ((1, 1, 1, 1, 1, 6, 1, 6, 1), (11, 0, 0, -1, 0, 0, 0, 0, 10),
         (1, 0, 0, -1, 0, 0, 0, 0, 5), (7, 0, 0, 1, 1, 1, 1, 1, 1),
         (1, 0, 0, -1, 0, 0, 0, 0, 3), (1, 0, 0, -1, 0, 0, 0, 0, 4),
         (1, 12, 1, 1, 1, 9, 1, 8, 1)),
        3, True, 15, ((1, 7), (4, 7)),
        ((1, 1, 1, 1, 1, 6, 1, 6, 1), (1, 0, 0, 0, 0, 0, 0, 0, 10),
         (1, 0, 0, 0, 0, 0, 0, 0, 5), (7, 0, 0, 1, 1, 1, 1, 1, 1),
         (1, 0, 0, -1, 0, 0, 0, 0, 3), (1, 0, 0, -1, 0, 0, 0, 0, 4),
         (1, 12, 1, 1, 1, 9, 8, 11, 1)),
        True),
    "mapF": PaperMap(
        "mapF",
        ((1, 6, 1, 5, 6, 1), (11, 0, 0, 0, 0, 10), (1, 0, 0, 3, 8, 1), (7, 0, 0, 0, 0, 4),
         (1, 12, 1, 9, 1, 1)),
        3, False, 15, ((1, 4), (3, 4)), None, True),
}

#: the maps the paper's own format accepts (mapE's switch moves a station)
LOADABLE = ("mapA", "mapB", "mapC", "mapD", "mapF")


def _rows_yaml(rows: tuple[tuple[int, ...], ...]) -> str:
    return "".join(f"  - [{', '.join(str(v) for v in row)}]\n" for row in rows)


def paper_map_text(name: str) -> str:
    """The YAML text of one paper map, laid out as the paper's files are."""
    m = PAPER_MAPS[name]
    dims = [len(m.rows[0]), len(m.rows)]
    spawn_key = "agent_initial_coordinates :" if m.spaced_spawn_key else "agent_initial_coordinates:"
    spawns = ", ".join(f"[{r}, {c}]" for r, c in m.spawns)
    text = ("# ITEMIDX values represent the following:\n"
            "#   block:-1 space: 0, counter: 1, agent: 2, tomato: 3, lettuce: 4,\n"
            "#   plate: 5, knife: 6, delivery: 7, onion: 8, pan: 9,\n"
            "#   steak: 10, sink: 11, trash_can: 12\n"
            f"name: {m.name}\ndimensions: [{dims[0]}, {dims[1]}]\nmap:\n{_rows_yaml(m.rows)}"
            f"max_n_agent: {m.max_n_agent}\ndynamic_map: {m.dynamic}\n")
    if m.switch_rows is not None:
        text += f"switch_map: \n{_rows_yaml(m.switch_rows)}"
    text += f"map_switch_step: {m.switch_step}\n{spawn_key} [{spawns}]\n\n\n"
    return text


def write_paper_maps(folder: Path) -> dict[str, Path]:
    """Write every paper map into ``folder``; name -> path."""
    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for name in PAPER_MAPS:
        path = folder / f"{name}.yaml"
        path.write_text(paper_map_text(name))
        out[name] = path
    return out

"""``ocplus check-map PATH|NAME``: validate a map and print a one-screen summary."""

from __future__ import annotations

import argparse

from ..sim.codes import SPAWN_TILES, Cell
from ..sim.maps import load_map, station_reachability


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("check-map", help="validate a map file and summarise it",
                       description=__doc__)
    p.add_argument("map", help="registered map name (e.g. mapC) or path to a YAML file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    layout = load_map(args.map)
    rows, cols = layout.shape
    print(f"map {layout.name}  ({layout.source})")
    if layout.description:
        print(f"  {layout.description.strip()}")
    capped = (f" (max_n_agent {layout.declared_max_agents}, capped at the spawn points)"
              if layout.declared_max_agents > layout.max_agents else "")
    print(f"size: {rows} rows x {cols} cols; max agents {layout.max_agents}{capped}; "
          f"spawn points {[list(p) for p in layout.spawn_points]}")
    for code, cells in sorted(layout.stations.items()):
        if code == Cell.COUNTER:
            continue
        kind = "spawn tile" if code in SPAWN_TILES else "station"
        print(f"  {Cell(code).name.lower():9s} {kind:10s} x{len(cells)}: {[list(c) for c in cells]}")
    if layout.is_dynamic:
        print(f"dynamic: switches every {layout.map_switch_step} steps; cells that switch: "
              f"{[list(c) for c in layout.switching_cells()]}")
    else:
        print("dynamic: no (static layout)")
    n_layouts = 2 if layout.switch_grid is not None else 1
    problems = []
    for entry in station_reachability(layout):
        if not entry["reachable_from"]:
            problems.append(entry)
    for li in range(n_layouts):
        bad = [e for e in problems if e["layout"] == li]
        label = "main layout" if li == 0 else "switch layout"
        if bad:
            cells = ", ".join(f"{Cell(e['code']).name.lower()} at {list(e['cell'])}" for e in bad)
            print(f"reachability ({label}): UNREACHABLE from every spawn point: {cells}")
        else:
            print(f"reachability ({label}): every station reachable from a spawn point")
    return 0

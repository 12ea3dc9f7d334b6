"""``ocplus check-map PATH|NAME``: validate a map and print a one-screen summary."""

from __future__ import annotations

import argparse
from typing import Any

from ..sim.codes import SPAWN_TILES, Cell
from ..sim.dishes import dish_to_dict
from ..sim.kitchens import load_kitchen
from ..sim.maps import Layout, station_reachability
from ..sim.process_yaml import process_to_dict
from ._common import HelpFormatter, add_output_args, emit


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("check-map", help="validate a map file and summarise it",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("map", help="registered map name (e.g. mapC) or path to a YAML file")
    add_output_args(p)
    p.set_defaults(func=run)


def summary(layout: Layout) -> dict[str, Any]:
    """The map's size, stations, switching and reachability, as data."""
    stations = {Cell(code).name.lower(): [list(c) for c in cells]
                for code, cells in sorted(layout.stations.items()) if code != Cell.COUNTER}
    unreachable = [{"layout": e["layout"], "station": Cell(e["code"]).name.lower(),
                    "cell": list(e["cell"])}
                   for e in station_reachability(layout) if not e["reachable_from"]]
    out = {"name": layout.name, "source": layout.source, "rows": layout.rows,
           "cols": layout.cols, "max_agents": layout.max_agents,
           "declared_max_agents": layout.declared_max_agents,
           "spawn_points": [list(p) for p in layout.spawn_points], "stations": stations,
           "dynamic": layout.is_dynamic,
           "switch_every": layout.map_switch_step if layout.is_dynamic else None,
           "switching_cells": [list(c) for c in layout.switching_cells()],
           "unreachable": unreachable}
    if layout.processes is not None:  # the kitchen file's own process records
        out["processes"] = [process_to_dict(p) for p in layout.processes]
    if layout.recipes is not None:  # the kitchen file's own dishes
        out["recipes"] = [dish_to_dict(d) for d in layout.recipes]
    return out


#: cells listed per line of the text summary (``--json`` lists them all)
SHOWN_CELLS = 12


def _cells(cells: list[Any]) -> str:
    """A list of cells, the first ``SHOWN_CELLS`` of a long one and how many in all."""
    if len(cells) <= SHOWN_CELLS:
        return str(cells)
    return f"{str(cells[:SHOWN_CELLS])[:-1]}, ...] ({len(cells)} in all)"


def run(args: argparse.Namespace) -> int:
    layout = load_kitchen(args.map)
    info = summary(layout)
    if args.json:
        emit(info, args)
        return 0
    print(f"map {layout.name}  ({layout.source})")
    if layout.description:
        print(f"  {layout.description.strip()}")
    capped = (f" (max_n_agent {info['declared_max_agents']}, capped at the spawn points)"
              if info["declared_max_agents"] > info["max_agents"] else "")
    print(f"size: {info['rows']} rows x {info['cols']} cols; max agents {info['max_agents']}"
          f"{capped}; spawn points {_cells(info['spawn_points'])}")
    for name, cells in info["stations"].items():
        kind = "spawn tile" if Cell[name.upper()] in SPAWN_TILES else "station"
        print(f"  {name:9s} {kind:10s} x{len(cells)}: {_cells(cells)}")
    for p in info.get("processes", ()):
        over = f", {p['overrun']['state']} after {p['overrun']['after']}" if "overrun" in p else ""
        print(f"  process   {p['station']}: {p['verb']} {'+'.join(p['takes'])} "
              f"{p['from']} -> {p['to']} by {p['drive']}, {p['duration']}{over}")
    for d in info.get("recipes", ()):
        parts = " + ".join(f"{s} {k}" for x in d["ingredients"] for k, s in x.items())
        worth = f", reward {d['reward']:g}" if "reward" in d else ""
        print(f"  recipe    {parts} on a {d['plate']}{worth}")
    if layout.is_dynamic:
        print(f"dynamic: switches every {info['switch_every']} steps; cells that switch: "
              f"{_cells(info['switching_cells'])}")
    else:
        print("dynamic: no (static layout)")
    for li in range(len(layout.grids())):
        bad = [e for e in info["unreachable"] if e["layout"] == li]
        label = "main layout" if li == 0 else "switch layout"
        if bad:
            cells = ", ".join(f"{e['station']} at {e['cell']}" for e in bad[:SHOWN_CELLS])
            cells += f", ... ({len(bad)} in all)" if len(bad) > SHOWN_CELLS else ""
            print(f"reachability ({label}): UNREACHABLE from every spawn point: {cells}")
        else:
            print(f"reachability ({label}): every station reachable from a spawn point")
    return 0

"""Options several subcommands share (one definition, one help text)."""

from __future__ import annotations

import argparse
import json
from typing import Any


def add_kitchen_args(p: argparse.ArgumentParser, *, step: bool = False) -> None:
    """``--preset --map --n-agents --seed`` (and ``--step`` for commands that compile a
    state reached after random steps)."""
    p.add_argument("--preset", default="easy", help="easy | medium | hard")
    p.add_argument("--map", default=None, help="map name or YAML path (None: the preset's map)")
    p.add_argument("--n-agents", type=int, default=None, help="number of agents (None: the preset's)")
    p.add_argument("--seed", type=int, default=0, help="episode seed")
    if step:
        p.add_argument("--step", type=int, default=0,
                       help="random joint actions to take before compiling")


def add_compile_args(p: argparse.ArgumentParser, *, auto_encoding: bool = False) -> None:
    """``--encoding --granularity --orders --anticipate-switches`` of the planning compiler."""
    if auto_encoding:
        p.add_argument("--encoding", choices=("auto", "classical", "temporal"), default="auto",
                       help="auto = the encoding the planner is registered for")
    else:
        p.add_argument("--encoding", choices=("classical", "temporal"), default="classical")
    p.add_argument("--granularity", choices=("stations", "cells"), default="stations")
    p.add_argument("--orders", type=int, default=None,
                   help="serve only the first k open orders (default: all)")
    p.add_argument("--anticipate-switches", action="store_true",
                   help="temporal only: the coming layout switches as timed initial literals")


def emit(result: dict[str, Any], as_json: bool, width: int = 16) -> None:
    """Print a command's result: one JSON object, or one ``key value`` line per entry."""
    if as_json:
        print(json.dumps(result))
    else:
        for key, value in result.items():
            print(f"{key:{width}s} {value}")

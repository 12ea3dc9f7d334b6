"""``ocplus demo``: the Quick start's small but real evaluation.

An ``ocplus eval`` with other defaults: the three presets (easy, medium, hard) with the
scripted greedy agent, a classical planner (planner:fast-downward-wastar: cost-aware, see the
README section "Planners against the greedy cook"), a temporal planner
(planner:kairos) and random actions, 3 seeds each, 200 steps per episode, plots when
matplotlib is installed; prints the leaderboard and where the results and plots are. A
planner that is not installed (or a controller kind this installation has not
registered) is skipped, with the reason in the results and on the screen.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import time
from pathlib import Path

from ._common import HelpFormatter
from .eval import add_sweep_args, run_sweep

DEMO_AGENTS = ["greedy", "planner:fast-downward-wastar", "planner:kairos", "random"]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="the quick-start demo: a small real evaluation",
                       description=__doc__, formatter_class=HelpFormatter)
    add_sweep_args(p, agents=None, seeds="3", jobs=min(2, os.cpu_count() or 1),
                   episode_timeout=300.0, out="optional")
    p.set_defaults(func=run)
    p.epilog = f"--agents defaults to {','.join(DEMO_AGENTS)}; --out to runs/demo-<date>-<time>"


def run(args: argparse.Namespace) -> int:
    out = Path(args.out) if args.out else Path("runs") / time.strftime("demo-%Y%m%d-%H%M%S")
    plots = args.plots or importlib.util.find_spec("matplotlib") is not None
    return run_sweep(args, agents=args.agents or ",".join(DEMO_AGENTS), out=out, plots=plots)

"""``ocplus demo``: the Quick start's small but real evaluation.

An ``ocplus eval`` with its own agents, on the shared defaults (the three presets easy,
medium and hard, 3 seeds each, 200 steps per episode, one worker): the scripted greedy
agent, a classical planner (planner:fast-downward-wastar: cost-aware, see the README
section "Planners against the greedy cook"), a temporal planner (planner:kairos) and
random actions; prints the leaderboard and where the results are (``--plots`` adds
figures). A planner that is not installed (or a controller kind this
installation has not registered) is skipped, with the reason in the results and on the screen.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ._common import HelpFormatter
from .eval import add_sweep_args, run_sweep

DEMO_AGENTS = ["greedy", "planner:fast-downward-wastar", "planner:kairos", "random"]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="the quick-start demo: a small real evaluation",
                       description=__doc__, formatter_class=HelpFormatter)
    add_sweep_args(p, agents=None)
    p.set_defaults(func=run)
    p.epilog = (f"--agents defaults to {','.join(DEMO_AGENTS)}. On a machine with cores to "
                "spare, --jobs 2 runs two episodes at once.")


def run(args: argparse.Namespace) -> int:
    out = Path(args.out) if args.out else Path("runs") / time.strftime("demo-%Y%m%d-%H%M%S")
    return run_sweep(args, agents=args.agents or ",".join(DEMO_AGENTS), out=out, plots=args.plots)

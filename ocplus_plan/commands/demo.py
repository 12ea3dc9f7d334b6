"""``ocplus demo``: the Quick start's small but real evaluation.

Runs the three presets (easy, medium, hard) with the scripted greedy agent, a classical
planner (planner:fast-downward), a temporal planner (planner:kairos) and random actions,
3 seeds each, 200 steps per episode; prints the leaderboard and where the results and
plots are. A planner that is not installed (or a controller kind this installation has
not registered) is skipped, with the reason in the results and on the screen.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import time
from pathlib import Path

DEMO_PRESETS = ["easy", "medium", "hard"]
DEMO_AGENTS = ["greedy", "planner:fast-downward", "planner:kairos", "random"]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="the quick-start demo: a small real evaluation",
                       description=__doc__,
                       formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (None: runs/demo-<date>-<time>)")
    p.add_argument("--seeds", type=int, default=3, help="seeds per preset and agent")
    p.add_argument("--horizon", type=int, default=200, help="steps per episode")
    p.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1),
                   help="worker processes")
    p.add_argument("--episode-timeout", type=float, default=300.0,
                   help="seconds before a (planner) episode is stopped and reported")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..eval.runner import EvalConfig, run_eval

    out = args.out or Path("runs") / time.strftime("demo-%Y%m%d-%H%M%S")
    plots = importlib.util.find_spec("matplotlib") is not None
    print(f"ocplus demo: presets {', '.join(DEMO_PRESETS)}; agents {', '.join(DEMO_AGENTS)}; "
          f"{args.seeds} seeds; {args.horizon} steps; {args.jobs} worker(s); output {out}")
    cfg = EvalConfig(presets=DEMO_PRESETS, agents=DEMO_AGENTS, seeds=list(range(args.seeds)),
                     out=out, horizon=args.horizon, jobs=args.jobs,
                     episode_timeout=args.episode_timeout, plots=plots)
    t0 = time.monotonic()
    outcome = run_eval(cfg)
    print()
    print(outcome.leaderboard)
    print(f"{outcome.ran} episodes in {time.monotonic() - t0:.0f} s "
          f"({outcome.errors} error(s), {outcome.skipped} configuration(s) skipped)")
    print(f"results: {out / 'results.jsonl'}")
    print(f"summary: {out / 'summary.csv'}")
    if outcome.plots:
        print(f"plots:   {out / 'plots'}/ ({len(outcome.plots)} PNG files, e.g. "
              f"{out / 'plots' / 'leaderboard.png'})")
    else:
        print("plots:   none (matplotlib is missing: pip install -e '.[plots]', then "
              f"`ocplus report {out}`)")
    return 0

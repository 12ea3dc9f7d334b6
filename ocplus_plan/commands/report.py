"""``ocplus report DIR``: leaderboard, summary.csv and PNG plots of an evaluation folder."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import ConfigError
from ..eval.results import SUMMARY_FILE, leaderboard, scan_results, summarise, write_summary
from ._common import HelpFormatter, add_output_args, add_plots_arg, emit


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("report", help="summarise and plot the results of `ocplus eval`",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("dir", type=Path, help="folder written by `ocplus eval --out DIR`")
    add_plots_arg(p)
    add_output_args(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    found = scan_results(args.dir)
    if found.note():
        print(f"ocplus: note: {found.note()}", file=sys.stderr)
    if not args.dir.is_dir():
        raise ConfigError(f"{args.dir} is not a folder; give the folder written by "
                          "`ocplus eval --out DIR`")
    summary = summarise(found.rows)
    write_summary(summary, args.dir / SUMMARY_FILE)
    files = []
    if args.plots:
        from ..eval.plots import make_plots

        files = make_plots(args.dir)
    if args.json:
        emit({"summary": str(args.dir / SUMMARY_FILE), "plots": [str(f) for f in files],
              "leaderboard": summary}, args)
        return 0
    print(leaderboard(summary))
    print(f"summary: {args.dir / SUMMARY_FILE}")
    if args.plots:
        print(f"plots:   {args.dir / 'plots'}/ ({len(files)} PNG files)")
    return 0

"""``ocplus report DIR``: leaderboard, summary.csv and PNG plots of an evaluation folder."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..eval.results import SUMMARY_FILE, leaderboard, read_results, summarise, write_summary


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("report", help="summarise and plot the results of `ocplus eval`",
                       description=__doc__)
    p.add_argument("dir", type=Path, help="folder written by `ocplus eval --out DIR`")
    p.add_argument("--no-plots", action="store_true", help="only the table and summary.csv")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    summary = summarise(read_results(args.dir))
    write_summary(summary, args.dir / SUMMARY_FILE)
    print(leaderboard(summary))
    print(f"summary: {args.dir / SUMMARY_FILE}")
    if not args.no_plots:
        from ..eval.plots import make_plots

        files = make_plots(args.dir)
        print(f"plots:   {args.dir / 'plots'}/ ({len(files)} PNG files)")
    return 0

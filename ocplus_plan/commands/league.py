"""``ocplus league``: score planners on an instance set, as the IPC scores them.

Every planner of --planners (registry names, planner YAML paths, ``command:`` binaries) is
run on every instance of SUITE (a folder written by ``ocplus export-suite``, e.g.
suites/v1) in each encoding it takes, one run per process session, under --cpu-limit CPU
seconds (the planner's whole process group, as the IPC counts them), an optional
--memory-limit (MiB of address space) and a wall-clock safety of 30 x the CPU limit +
60 s. Every plan is validated (unified-planning and VAL) and judged in the kitchen
(collision-free routing, waits allowed): a plan the kitchen cannot carry out to its goal
is ``unfaithful`` and scores 0, like an invalid one.

Writes OUT/runs.jsonl (one row per planner x instance x encoding: status, CPU s, wall s,
cost or makespan, valid, faithful), OUT/scores.json (coverage, IPC quality C*/C, IPC
agile, validity and faithfulness counts, per planner and track) and, with --plots,
OUT/coverage.png (the plots extra); prints the table (--json: the scores). An
interrupted league continues with --resume (rows already in OUT/runs.jsonl are kept).
Planners not installed here are skipped with the reason. Runs are local (--jobs N at
once); there is no --backend ray for the league.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from . import _types
from ._common import (
    HelpFormatter,
    add_jobs_arg,
    add_output_args,
    add_plots_arg,
    emit,
    note,
    say,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("league", help="run planners on an instance set and score them "
                       "(IPC coverage, quality, agile; valid and faithful plans only)",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("suite", help="an instance set folder written by `ocplus export-suite`")
    p.add_argument("--planners", type=_types.name, required=True,
                   help="comma-separated planners: registry names (`ocplus solve --list`) "
                        "or planner YAML paths")
    p.add_argument("--cpu-limit", type=_types.number("--cpu-limit", 0.0, 86400.0),
                   required=True, metavar="SECONDS", help="CPU seconds per run")
    p.add_argument("--memory-limit", type=_types.number("--memory-limit", 16.0, 1048576.0),
                   default=None, metavar="MB",
                   help="MiB of address space per run (None: no limit)")
    p.add_argument("--instances", type=_types.name, default=None,
                   help="comma-separated instance names, e.g. p01,p02 (None: all)")
    add_jobs_arg(p)  # here: planner runs at once, each in its own process session
    p.add_argument("--resume", action="store_true",
                   help="continue the league in --out: keep its rows, run the others")
    g = p.add_argument_group("figures")
    add_plots_arg(g)
    add_output_args(p, out=True, writes="runs.jsonl, scores.json, coverage.png")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..errors import ConfigError
    from ..eval import league
    from ..eval.runner import parse_list

    suite, out = Path(args.suite), Path(args.out)
    if (out / league.RUNS_FILE).is_file() and not args.resume:
        raise ConfigError(f"{out} already holds a league ({league.RUNS_FILE}); give --resume "
                          "to continue it, or a new --out")
    planners = tuple(dict.fromkeys(parse_list(args.planners, "planners")))
    instances = (tuple(parse_list(args.instances, "instances"))
                 if args.instances else None)
    spec = league.LeagueSpec(suite, planners, args.cpu_limit, args.memory_limit, instances,
                             args.jobs or 1)
    league.league_cells(spec)  # bad planners or instances: refused before any run

    def progress(row: dict, done: int, total: int) -> None:
        say(args, f"[{done}/{total}] {row['planner']} {row['instance']} {row['encoding']}: "
                  f"{row['status']} {row.get('cpu_time') or 0:.1f} CPU s"
                  + (f" value {row['value']:g}" if row["status"] == "solved" else ""))

    rows, skipped = league.run_league(spec, out, progress)
    for line in skipped:
        note(args, f"skipped {line}")
    score = league.write_scores(rows, out, suite)
    if args.plots and rows:
        league.plot_coverage(rows, out)
    if args.json:
        emit(score, args)
    else:
        print(league.table_text(score))
        say(args, f"rows: {out / league.RUNS_FILE}; scores: {out / league.SCORES_FILE}")
    return 0

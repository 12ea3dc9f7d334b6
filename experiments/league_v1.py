"""The planner league on an instance set (``suites/v1`` by default), with its conditions.

Runs ``ocplus league`` (``ocplus_plan.eval.league``) at a CPU limit per run, ``--jobs N``,
under ``nice``, on the instances asked for, and writes beside ``runs.jsonl`` and
``scores.json`` a ``conditions.json``: the command, the commit, the machine, the load
(``uptime``) before and after, the cells run and the CPU seconds they used. ``--busy N``
runs N processes spinning on the CPU beside the league (the load check: run the same
cells once alone and once with ``--busy 2``, then ``--compare`` the two folders).

``--report DIR [--markdown]`` prints the league's numbers: the table, the count of plans that VAL and
unified-planning accept and the kitchen refuses (``valid`` and not ``faithful``), the plans
realised only with waits (the strict replay diverged, the judge realised them), and per
temporal engine its solved share of the temporal track's first three fifths. Quality is scored
against the best known values of ``--suite`` as it is now (a row keeps the best known of when
it ran; the set's references may have improved since).

    nice -n 10 .venv/bin/python experiments/league_v1.py --suite suites/v1 --cpu-limit 30 \\
        --instances p01,p02 --out experiments/results/league/v1-p01-p02_all-planners_cpu30
    .venv/bin/python experiments/league_v1.py --report experiments/results/league/...
    .venv/bin/python experiments/league_v1.py --compare A B
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

from ocplus_plan.eval import league
from ocplus_plan.planning.engines import planner_names

ROOT = Path(__file__).resolve().parents[1]


def _uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout.strip()


def _commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=False, cwd=ROOT).stdout.strip()


def _spin() -> None:
    os.nice(10)
    while True:
        pass


def run(args: argparse.Namespace) -> int:
    planners = tuple(args.planners.split(",")) if args.planners else tuple(planner_names())
    instances = tuple(args.instances.split(",")) if args.instances else None
    spec = league.LeagueSpec(Path(args.suite), planners, args.cpu_limit, args.memory_limit,
                             instances, args.jobs)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    before, commit = _uptime(), _commit()
    spinners = [multiprocessing.get_context("fork").Process(target=_spin, daemon=True)
                for _ in range(args.busy)]
    for proc in spinners:
        proc.start()
    start = time.time()
    try:
        rows, skipped = league.run_league(spec, out, lambda row, i, n: print(
            f"[{i}/{n}] {row['planner']} {row['instance']} {row['encoding']} {row['status']} "
            f"{row.get('cpu_time') or 0:.2f} CPU s {row.get('value')}", flush=True))
    finally:
        for proc in spinners:
            proc.kill()
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    score = league.write_scores(rows, out, Path(args.suite))
    conditions = {
        "command": " ".join([Path(sys.executable).name, *sys.argv]), "commit": commit,
        "machine": f"{platform.machine()}, {os.cpu_count()} shared cores",
        "load_before": before, "pythonhashseed": os.environ.get("PYTHONHASHSEED"),
        "load_after": _uptime(), "busy": args.busy, "jobs": args.jobs,
        "cpu_limit": args.cpu_limit, "memory_limit": args.memory_limit,
        "planners": list(planners), "skipped": skipped,
        "cells": [[r["planner"], r["instance"], r["encoding"]] for r in rows],
        "cpu_seconds_of_runs": round(sum(float(r.get("cpu_time") or 0) for r in rows), 1),
        "children_cpu_seconds": round(usage.ru_utime + usage.ru_stime, 1),
        "wall_seconds": round(time.time() - start, 1),
    }
    earlier = out / "conditions.json"
    if earlier.is_file():  # a resumed league keeps the conditions of its earlier parts
        old = json.loads(earlier.read_text("utf-8"))
        conditions["earlier_parts"] = [*old.pop("earlier_parts", []), old]
    (out / "conditions.json").write_text(json.dumps(conditions, indent=1) + "\n", "utf-8")
    print(league.table_text(score))
    return 0


def markdown(score: dict) -> str:
    """The league table as the README shows it: one line per planner, solved of run per
    track, quality and agile over all tracks, and the other statuses."""
    tracks = sorted({t for p in score["planners"].values() for t in p if t != "all"})
    lines = ["| planner | " + " | ".join(tracks) + " | quality | agile | not solved |",
             "|---|" + "---|" * (len(tracks) + 3)]
    for planner in sorted(score["planners"]):
        per = score["planners"][planner]
        cells = [f"{per[t]['coverage']} / {per[t]['instances']}" if t in per else "-"
                 for t in tracks]
        s = per["all"]
        other = ", ".join(f"{v} {k}" for k, v in sorted(s["statuses"].items())
                          if k != "solved") or "-"
        lines.append(f"| {planner} | " + " | ".join(cells) +
                     f" | {s['quality']:.2f} | {s['agile']:.2f} | {other} |")
    return "\n".join(lines)


def report(folder: Path, as_markdown: bool = False, suite: Path | None = None) -> dict:
    rows = league.read_rows(folder / league.RUNS_FILE)
    refused = [r for r in rows if r.get("valid") is True and r.get("faithful") is False]
    waited = [r for r in rows if r.get("faithful") is True and (r.get("waits") or 0) > 0]
    temporal = sorted({r["instance"] for r in rows if r["track"] == "temporal"})
    first = temporal[: (3 * len(temporal)) // 5] if temporal else []
    share = {}
    for planner in sorted({r["planner"] for r in rows if r["encoding"] == "temporal"}):
        solved = {r["instance"] for r in rows if r["planner"] == planner
                  and r["status"] == "solved" and r["instance"] in first}
        share[planner] = f"{len(solved)}/{len(first)}"
    out = {"rows": len(rows), "valid_plans": sum(r.get("valid") is True for r in rows),
           "valid_refused_by_kitchen": len(refused),
           "refused": [[r["planner"], r["instance"], r["reason"]] for r in refused],
           "realised_with_waits": len(waited),
           "temporal_first_three_fifths": first, "temporal_solved_share": share}
    score = league.scores(rows, league.suite_best(suite, rows) if suite else None)
    print(markdown(score) if as_markdown else league.table_text(score))
    print(json.dumps(out, indent=1))
    return out


def compare(a: Path, b: Path) -> dict:
    rows_a = {(r["planner"], r["instance"], r["encoding"]): r
              for r in league.read_rows(a / league.RUNS_FILE)}
    rows_b = {(r["planner"], r["instance"], r["encoding"]): r
              for r in league.read_rows(b / league.RUNS_FILE)}
    common = sorted(set(rows_a) & set(rows_b))
    differ = [[*k, rows_a[k]["status"], rows_a[k].get("value"), rows_b[k]["status"],
               rows_b[k].get("value")] for k in common
              if (rows_a[k]["status"], rows_a[k].get("value"))
              != (rows_b[k]["status"], rows_b[k].get("value"))]
    out = {"cells": len(common), "same": len(common) - len(differ), "differ": differ,
           "planners": sorted({k[0] for k in common})}
    print(json.dumps(out, indent=1))
    return out


def main(argv: list[str] | None = None) -> int:
    if os.environ.get("PYTHONHASHSEED") != "0" and argv is None:
        # in-process Python engines (pyperplan) break ties in the order of sets of strings,
        # which Python's hash randomisation changes from process to process: fix it
        os.execve(sys.executable, [sys.executable, *sys.argv],
                  {**os.environ, "PYTHONHASHSEED": "0"})
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--suite", default="suites/v1")
    p.add_argument("--planners", default=None, help="comma-separated (default: every "
                   "registered planner)")
    p.add_argument("--instances", default=None, help="comma-separated (default: all)")
    p.add_argument("--cpu-limit", type=float, default=30.0)
    p.add_argument("--memory-limit", type=float, default=4096.0)
    p.add_argument("--jobs", type=int, default=1, help="runs at once (each engine keeps "
                   "its own CPU-second limit, so rows do not depend on it)")
    p.add_argument("--busy", type=int, default=0)
    p.add_argument("--out", default=None)
    p.add_argument("--report", type=Path, default=None)
    p.add_argument("--markdown", action="store_true", help="with --report: the table in "
                   "Markdown, as the README shows it")
    p.add_argument("--compare", type=Path, nargs=2, default=None)
    args = p.parse_args(argv)
    if args.report:
        report(args.report, args.markdown, Path(args.suite))
        return 0
    if args.compare:
        compare(*args.compare)
        return 0
    if not args.out:
        p.error("--out DIR is required to run a league")
    return run(args)


if __name__ == "__main__":
    sys.exit(main())

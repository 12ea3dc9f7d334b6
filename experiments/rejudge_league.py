"""Judge again, with the package's current judge, every VAL-valid plan of league folders.

A league row (``runs.jsonl``) records the verdict of the judge of its commit, not the
plan. For each row that VAL and unified-planning accepted, this script takes the plan
from ``--plans DIR`` (``<folder>/<planner>__<instance>.<encoding>.plan``) or, when it is
not there, solves the cell again with the row's planner, CPU limit and memory limit and
stores the plan there (so a second run needs no planner; an anytime or non-deterministic
engine may return another plan: the row's value and the new one are both printed). Each
plan is validated again (UP and VAL) and judged (``planning/fidelity_judge.judge``), and
the script prints per folder and in all: valid plans, faithful, realised with waits
(the strict replay diverged, the judge realised them), refused with the failing step.

    nice -n 10 .venv/bin/python experiments/rejudge_league.py \\
        experiments/results/league/v1-* --plans experiments/results/rejudge/plans \\
        --out experiments/results/rejudge/rejudged.jsonl

``--stored-only`` solves nothing (a row without a stored plan is counted as such).
A folder whose suite is not here (``conditions.json`` names it) is skipped with a line.
"""

from __future__ import annotations

import argparse
import json
import platform
import resource
import subprocess
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _suite_of(folder: Path) -> Path | None:
    """The suite a league folder ran on (its ``conditions.json`` command's ``--suite``)."""
    try:
        conditions = json.loads((folder / "conditions.json").read_text(encoding="utf-8"))
        words = conditions["command"].split()
        suite = Path(words[words.index("--suite") + 1])
    except (OSError, ValueError, KeyError, IndexError):
        return None
    suite = suite if suite.is_absolute() else ROOT / suite
    return suite if (suite / "manifest.json").is_file() else None


def _plan_of(row: dict, suite: Path, plans: Path, folder: Path,
             stored_only: bool) -> tuple[object, object, str]:
    """(the instance, the plan read back, where it came from): stored, or solved again."""
    from ocplus_plan.eval.suite import load_instance
    from ocplus_plan.planning.engines import solve
    from ocplus_plan.planning.plan_io import format_plan, read_plan

    instance = load_instance(suite / row["instance"])
    compiled = instance.compiled(row["encoding"])
    name = f"{Path(row['planner']).stem}__{row['instance'].replace('/', '_')}"
    path = plans / folder.name / f"{name}.{row['encoding']}.plan"
    if not path.is_file() and stored_only:
        return instance, None, "no stored plan (--stored-only)"
    if not path.is_file():
        result = solve(compiled.problem, row["planner"], timeout=row["cpu_limit"],
                       memory_limit=row.get("memory_limit"))
        if result.plan is None:
            return instance, None, f"solved again: {result.status}"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(format_plan(result.plan, f"{row['planner']} on {row['instance']} "
                                    f"({row['encoding']}), solved again"), encoding="utf-8")
        source = f"solved again ({result.cpu_time} CPU s)"
    else:
        source = "stored"
    return (instance, compiled), read_plan(path, compiled.problem), source


def rejudge(folder: Path, plans: Path, stored_only: bool = False) -> list[dict]:
    """One output row per VAL-valid row of ``folder``."""
    from ocplus_plan.planning.fidelity_judge import judge
    from ocplus_plan.planning.validate import plan_quality, validate_plan

    suite = _suite_of(folder)
    if suite is None:
        print(f"{folder.name}: its suite is not here; skipped")
        return []
    out = []
    for line in (folder / "runs.jsonl").read_text(encoding="utf-8").splitlines():
        row = json.loads(line)
        if row.get("valid") is not True:
            continue
        got, plan, source = _plan_of(row, suite, plans, folder, stored_only)
        entry = {"folder": folder.name, "planner": row["planner"], "instance": row["instance"],
                 "encoding": row["encoding"], "row_value": row["value"],
                 "row_faithful": row["faithful"], "row_failed_step": row.get("failed_step"),
                 "source": source}
        if plan is None:
            out.append({**entry, "valid": None})
            print(f"{row['planner']:>24} {row['instance']:<24} {source}")
            continue
        instance, compiled = got
        check = validate_plan(compiled.problem, plan)
        quality = plan_quality(compiled.problem, plan)
        value = quality.makespan if row["encoding"] == "temporal" else quality.cost
        entry.update(valid=check.ok is True, value=None if value is None else float(value))
        if check.ok is True:
            verdict = judge(compiled, plan, instance.state)
            entry.update(faithful=verdict.faithful, judged=verdict.how, waits=verdict.waits,
                         failed_step=verdict.failed_step, reason=verdict.reason)
        out.append(entry)
        print(f"{row['planner']:>24} {row['instance']:<24} value {entry['value']} (row "
              f"{row['value']}) valid {entry['valid']} faithful {entry.get('faithful')} "
              f"{entry.get('judged', '')} waits {entry.get('waits')} "
              f"{'step ' + str(entry['failed_step']) + ': ' + entry['reason'] if entry.get('failed_step') is not None or entry.get('faithful') is False else ''}")
    return out


def counts(rows: list[dict]) -> dict[str, object]:
    valid = [r for r in rows if r.get("valid")]
    refused = [r for r in valid if r.get("faithful") is False]
    return {"league rows valid": len(rows), "plans valid again": len(valid),
            "same value as the row": sum(r["value"] == r["row_value"] for r in valid),
            "faithful": sum(r.get("faithful") is True for r in valid),
            "realised with waits": sum(r.get("faithful") is True and (r.get("waits") or 0) > 0
                                       for r in valid),
            "refused": [f"{r['planner']} {r['instance']} step {r['failed_step']}: "
                        f"{r['reason']}" for r in refused],
            "no plan to judge": sum(r.get("valid") is None for r in rows)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folders", nargs="+", type=Path)
    parser.add_argument("--plans", type=Path, default=ROOT / "experiments/results/rejudge/plans")
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--stored-only", action="store_true",
                        help="judge the stored plans only; solve nothing")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    start = time.process_time()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    every = []
    for folder in args.folders:
        rows = rejudge(folder, args.plans, args.stored_only)
        if rows:
            print(f"== {folder.name}: {json.dumps(counts(rows))}")
        every.extend(rows)
    summary = {"counts": counts(every), "commit": commit, "machine":
               f"{platform.machine()}, 2 shared cores", "load_before": load,
               "load_after": subprocess.run(["uptime"], capture_output=True,
                                            text=True).stdout.strip(),
               "cpu_s": round(time.process_time() - start + resource.getrusage(
                   resource.RUSAGE_CHILDREN).ru_utime + resource.getrusage(
                   resource.RUSAGE_CHILDREN).ru_stime, 1),
               "command": " ".join([Path(sys.argv[0]).name, *(argv or sys.argv[1:])])}
    print(json.dumps(summary, indent=1))
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text("".join(json.dumps(r, sort_keys=True) + "\n" for r in every)
                            + json.dumps({"summary": summary}, sort_keys=True) + "\n",
                            encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

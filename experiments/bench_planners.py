"""Compile time and, per planner, solve time, status and plan quality.

For the initial state (seed 0) of each preset with 1 and 2 agents:

* ``compile``: median wall time of ``compile(state, ...)`` over ``--compile-runs``
  runs, for both encodings at the stations granularity (target: < 5 ms);
* ``solve``: every registered planner on the encoding it is registered for
  (stations granularity), the goal being the first open order (``--orders``),
  with a time limit of ``--timeout`` seconds. Reports the status, the planning
  time (wall, including the process start), the plan length, the cost (classical:
  steps of the sequential plan) or the makespan (temporal), and validation.

Prints one JSON line per measurement; ``--table`` prints the Markdown table for
the README from those lines instead (``--from FILE`` reuses a saved run)::

    python experiments/bench_planners.py > experiments/results/bench_planners.jsonl
    python experiments/bench_planners.py --table --from experiments/results/bench_planners.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from typing import Any

CONFIGS = [("easy", 1), ("easy", 2), ("medium", 1), ("medium", 2), ("hard", 1), ("hard", 2)]


def bench_compile(state: Any, encoding: str, granularity: str, runs: int,
                  orders: int | None) -> dict[str, Any]:
    from ocplus_plan.planning import compile

    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        compiled = compile(state, encoding=encoding, granularity=granularity, max_orders=orders)
        times.append(time.perf_counter() - t0)
    problem = compiled.problem
    return {"compile_ms_median": round(1000 * statistics.median(times), 3),
            "compile_ms_min": round(1000 * min(times), 3), "runs": runs,
            "objects": len(problem.all_objects), "actions": len(problem.actions),
            "initial_facts": len(problem.explicit_initial_values)}


def run(args: argparse.Namespace) -> list[dict[str, Any]]:
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import get_planner, planner_names, solve
    from ocplus_plan.sim import make_rules, new_state

    names = planner_names() if args.planners == "all" else args.planners.split(",")
    configs = [get_planner(n) for n in names]
    rows = []
    for preset, n_agents in CONFIGS:
        if args.presets != "all" and preset not in args.presets.split(","):
            continue
        rules = make_rules(preset, n_agents=n_agents)
        state = new_state(rules, args.seed)
        base = {"preset": preset, "map": rules.layout.name, "n_agents": n_agents,
                "seed": args.seed, "granularity": args.granularity, "orders": args.orders}
        problems = {}
        for encoding in ("classical", "temporal"):
            row = {"bench": "compile", **base, "encoding": encoding,
                   **bench_compile(state, encoding, args.granularity, args.compile_runs,
                                   args.orders)}
            emit(row, rows)
            problems[encoding] = compile(state, encoding=encoding, granularity=args.granularity,
                                         max_orders=args.orders).problem
        for config in configs:
            result = solve(problems[config.encoding], config, timeout=args.timeout)
            info = result.to_dict()
            emit({"bench": "solve", **base, "encoding": config.encoding, "planner": config.name,
                  "engine": config.engine, "timeout_s": args.timeout,
                  "status": info["status"], "planning_time_s": info["planning_time"],
                  "cpu_time_s": info["cpu_time"],
                  "plan_length": info["plan_length"], "cost": info["cost"],
                  "makespan": info["makespan"], "optimal": info["optimal"],
                  "validated": info["validated"], "reason": info["reason"][:300],
                  "notes": info["notes"], "python": platform.python_version(),
                  "load_avg_1min": round(os.getloadavg()[0], 2)}, rows)
    return rows


def emit(row: dict[str, Any], rows: list[dict[str, Any]]) -> None:
    rows.append(row)
    print(json.dumps(row), flush=True)


def table(rows: list[dict[str, Any]]) -> str:
    """One Markdown table: a row per planner, a column per (preset, agents)."""
    cols = [(p, n) for p, n in CONFIGS
            if any(r["preset"] == p and r["n_agents"] == n for r in rows)]
    head = ["planner (encoding)"] + [f"{p} {n}a" for p, n in cols]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for enc in ("classical", "temporal"):
        comp = {(r["preset"], r["n_agents"]): r for r in rows
                if r["bench"] == "compile" and r["encoding"] == enc}
        lines.append("| compile " + enc + " (median ms) | "
                     + " | ".join(f"{comp[c]['compile_ms_median']:.2f}" if c in comp else "-"
                                  for c in cols) + " |")
    planners = sorted({(r["encoding"], r["planner"]) for r in rows if r["bench"] == "solve"})
    for enc, name in planners:
        cells = []
        for c in cols:
            hit = [r for r in rows if r["bench"] == "solve" and r["planner"] == name
                   and (r["preset"], r["n_agents"]) == c]
            cells.append(_cell(hit[0]) if hit else "-")
        lines.append(f"| {name} ({enc}) | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _cell(r: dict[str, Any]) -> str:
    if r["status"] in ("solved", "invalid"):
        quality = (f"cost {r['cost']:g}" if r["makespan"] is None
                   else f"makespan {r['makespan']:g}")
        mark = "" if r["validated"] else " **invalid**"
        cpu = f" (cpu {r['cpu_time_s']:.2f})" if r.get("cpu_time_s") is not None else ""
        return f"{r['planning_time_s']:.2f} s{cpu}, {quality}{mark}"
    return f"{r['status']} ({r['planning_time_s']:.1f} s)"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--presets", default="all", help="comma list or 'all'")
    p.add_argument("--planners", default="all", help="comma list of registry names or 'all'")
    p.add_argument("--timeout", type=float, default=10.0, help="seconds per solve")
    p.add_argument("--orders", type=int, default=1, help="serve the first k orders")
    p.add_argument("--granularity", default="stations", choices=("stations", "cells"))
    p.add_argument("--compile-runs", type=int, default=50)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--table", action="store_true", help="print the README table")
    p.add_argument("--from", dest="source", default=None,
                   help="with --table: read JSON lines from this file instead of running")
    args = p.parse_args(argv)
    if args.table and args.source:
        with open(args.source, encoding="utf-8") as fh:
            rows = [json.loads(line) for line in fh if line.strip()]
    else:
        rows = run(args)
    if args.table:
        print(table(rows), file=sys.stdout if args.source else sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

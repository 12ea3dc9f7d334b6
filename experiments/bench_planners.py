"""Compile time and, per planner, solve time, status and plan quality beside a lower bound.

For the initial state of each preset with 1 and 2 agents, for every seed of ``--seed``
(a comma list):

* ``compile``: median wall time of ``compile(state, ...)`` over ``--compile-runs``
  runs, for both encodings at the stations granularity (target: < 5 ms);
* ``solve``: every planner of ``--planners`` (default: every registered planner that is
  installed here) on the encoding it is registered for (stations granularity), the
  goal being the first ``--orders`` open orders, with a limit of ``--timeout`` CPU
  seconds (the planner's process group, as the IPC counts them) or the planner's own if
  smaller (an anytime planner's budget). Reports the status, the planning time (wall,
  including the process start) and CPU time, the plan length, the cost (classical: steps of the sequential plan) or the
  makespan (temporal), validation, and beside the plan's quality (``value``: cost
  for a classical planner, makespan for a temporal one) the lower bound of
  :func:`ocplus_plan.eval.bounds.plan_bound` for the same state, orders and cooks
  (``bound``) and ``ratio`` = value / bound (1.0 would be a plan as good as the bound).

Prints one JSON line per measurement; ``--table`` prints the Markdown table for
the README from those lines instead (``--from FILE`` reuses a saved run)::

    python experiments/bench_planners.py --seed 0,4 > experiments/results/bench_planners.jsonl
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


def planners_to_run(spec: str) -> list[str]:
    """``available`` (installed here), ``all`` (registered) or a comma list of names."""
    from ocplus_plan.planning.engines import available_planners, planner_names

    if spec == "available":
        return available_planners()
    return planner_names() if spec == "all" else spec.split(",")


def bound_fields(state: Any, orders: int | None) -> dict[str, Any]:
    """The plan bound of a state, as row fields (``None`` when some order cannot be made)."""
    from ocplus_plan.eval.bounds import plan_bound

    b = plan_bound(state, max_orders=orders)

    def num(x: float) -> float | None:
        return None if x == float("inf") else round(float(x), 3)

    return {"bound_cost": num(b.cost), "bound_makespan": num(b.makespan),
            "bound_walk": num(b.walk), "bound_work_classical": b.work_classical,
            "bound_work_temporal": b.work_temporal, "bound_critical_path": num(b.critical_path)}


def quality(info: dict[str, Any], encoding: str, bounds: dict[str, Any]) -> dict[str, Any]:
    """value (cost or makespan), the bound of the same kind, and their ratio."""
    value = info["cost"] if encoding == "classical" else info["makespan"]
    bound = bounds["bound_cost"] if encoding == "classical" else bounds["bound_makespan"]
    if info["status"] != "solved":
        value = None
    ratio = round(value / bound, 3) if value is not None and bound else None
    return {"quality": "cost" if encoding == "classical" else "makespan",
            "value": value, "bound": bound, "ratio": ratio}


def run(args: argparse.Namespace) -> list[dict[str, Any]]:
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import get_planner, solve
    from ocplus_plan.sim import make_rules, new_state

    configs = [get_planner(n) for n in planners_to_run(args.planners)]
    rows: list[dict[str, Any]] = []
    for seed in args.seeds:
        for preset, n_agents in CONFIGS:
            if args.presets != "all" and preset not in args.presets.split(","):
                continue
            if args.agents and n_agents not in args.agents:
                continue
            rules = make_rules(preset, n_agents=n_agents)
            state = new_state(rules, seed)
            base = {"preset": preset, "map": rules.layout.name, "n_agents": n_agents,
                    "seed": seed, "granularity": args.granularity, "orders": args.orders}
            bounds = bound_fields(state, args.orders)
            problems = {}
            for encoding in ("classical", "temporal"):
                if args.compile_runs > 0:
                    emit({"bench": "compile", **base, "encoding": encoding,
                          **bench_compile(state, encoding, args.granularity, args.compile_runs,
                                          args.orders)}, rows)
                problems[encoding] = compile(state, encoding=encoding,
                                             granularity=args.granularity,
                                             max_orders=args.orders).problem
            for config in configs:
                limit = min(args.timeout, config.timeout)  # an anytime planner's own budget
                result = solve(problems[config.encoding], config, timeout=limit)
                info = result.to_dict()
                emit({"bench": "solve", **base, "encoding": config.encoding,
                      "planner": config.name, "engine": config.engine,
                      "timeout_s": limit, "status": info["status"],
                      "planning_time_s": info["planning_time"], "cpu_time_s": info["cpu_time"],
                      "plan_length": info["plan_length"], "cost": info["cost"],
                      "makespan": info["makespan"], "optimal": info["optimal"],
                      **quality(info, config.encoding, bounds), **bounds,
                      "validated": info["validated"], "reason": info["reason"][:300],
                      "notes": info["notes"], "python": platform.python_version(),
                      "load_avg_1min": round(os.getloadavg()[0], 2)}, rows)
    return rows


def emit(row: dict[str, Any], rows: list[dict[str, Any]]) -> None:
    rows.append(row)
    print(json.dumps(row), flush=True)


def table(rows: list[dict[str, Any]]) -> str:
    """One Markdown table: a row per planner, a column per (preset, agents).

    Each planner cell: the plan's cost or makespan, its ratio to the lower bound and
    the wall time; with several seeds, each seed's value in seed order ('-': not
    solved), the mean ratio over the solved seeds, how many were solved, and the
    median wall time of the solved runs.
    """
    solves = [r for r in rows if r["bench"] == "solve"]
    cols = [(p, n) for p, n in CONFIGS
            if any(r["preset"] == p and r["n_agents"] == n for r in rows)]
    head = ["planner (encoding)"] + [f"{p} {n}a" for p, n in cols]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for enc in ("classical", "temporal"):
        comp = [r for r in rows if r["bench"] == "compile" and r["encoding"] == enc]
        if comp:
            lines.append(f"| compile {enc} (median ms) | " + " | ".join(
                _median_cell([r["compile_ms_median"] for r in comp
                              if (r["preset"], r["n_agents"]) == c], "{:.2f}") for c in cols)
                + " |")
    bound_rows = {}
    for r in solves:
        bound_rows.setdefault((r["preset"], r["n_agents"], r["seed"]), r)
    for label, key in (("lower bound: cost", "bound_cost"),
                       ("lower bound: makespan", "bound_makespan")):
        cells = []
        for c in cols:
            values = [r[key] for (p, n, _), r in sorted(bound_rows.items()) if (p, n) == c]
            cells.append(" / ".join("-" if v is None else f"{v:g}" for v in values) or "-")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    planners = sorted({(r["encoding"], r["planner"]) for r in solves})
    for enc, name in planners:
        cells = []
        for c in cols:
            hits = sorted((r for r in solves if r["planner"] == name
                           and (r["preset"], r["n_agents"]) == c), key=lambda r: r["seed"])
            cells.append(_cell(hits) if hits else "-")
        lines.append(f"| {name} ({enc}) | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _median_cell(values: list[float], fmt: str) -> str:
    return fmt.format(statistics.median(values)) if values else "-"


def _cell(hits: list[dict[str, Any]]) -> str:
    if len(hits) == 1:
        r = hits[0]
        if r["status"] in ("solved", "invalid"):
            q = r.get("quality") or ("cost" if r["makespan"] is None else "makespan")
            value = r["cost"] if q == "cost" else r["makespan"]
            ratio = f" = {r['ratio']:.2f}x bound" if r.get("ratio") else ""
            mark = "" if r["validated"] else " **invalid**"
            return f"{q} {value:g}{ratio}, {r['planning_time_s']:.1f} s{mark}"
        return f"{r['status']} ({r['planning_time_s']:.1f} s)"
    solved = [r for r in hits if r["status"] == "solved"]
    if not solved:
        return "none of " + str(len(hits)) + " (" + ", ".join(sorted({r["status"] for r in hits})) + ")"
    q = solved[0].get("quality") or "value"
    values = "/".join(f"{r['value']:g}" if r.get("value") is not None else "-" for r in hits)
    ratios = [r["ratio"] for r in solved if r.get("ratio")]
    ratio = f" = {statistics.mean(ratios):.2f}x bound (mean)" if ratios else ""
    secs = statistics.median(r["planning_time_s"] for r in solved)
    return f"{q} {values}{ratio}, {len(solved)}/{len(hits)} solved, {secs:.1f} s"


def _ints(text: str) -> list[int]:
    return [int(x) for x in text.split(",") if x.strip()]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--presets", default="all", help="comma list or 'all'")
    p.add_argument("--agents", type=_ints, default=None,
                   help="comma list of cook counts (default: 1 and 2)")
    p.add_argument("--planners", default="available",
                   help="comma list of registry names, 'available' (installed here) or 'all'")
    p.add_argument("--timeout", type=float, default=10.0,
                   help="CPU seconds per solve (at most; a planner's own smaller limit wins)")
    p.add_argument("--orders", type=int, default=1, help="serve the first k orders")
    p.add_argument("--granularity", default="stations", choices=("stations", "cells"))
    p.add_argument("--compile-runs", type=int, default=50, help="0: skip the compile timing")
    p.add_argument("--seed", dest="seeds", type=_ints, default=[0],
                   help="initial-state seed, or a comma list of seeds")
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

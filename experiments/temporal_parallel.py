"""Temporal planning from the presets' initial states: does a temporal engine return a
validated plan within the time budget, and do two cooks really work in parallel?

For each preset and seed, the initial state with 1 cook and with 2 cooks is compiled to
the temporal stations encoding for the same orders (the first ``--orders`` open orders:
the order stream depends only on the seed) and solved by each ``--planners`` engine with
``--timeout``; the plan is validated by unified-planning and VAL. When the problem is
unsolvable in the current layout (MapC: one cook is cut off from half the stations until
the layout switches), it is compiled again with the coming switches as timed initial
literals (``anticipate_switches``) and solved once more, within the same budget.

One JSON line per (preset, cooks, planner, seed): status, planning time, wall time of
compile + solve + validation, makespan, whether switches were anticipated; then per
preset and planner the ratio of the 2-cook makespan to the 1-cook makespan.

    .venv/bin/python experiments/temporal_parallel.py --planners kairos kairos-anytime \\
        --presets easy medium hard --seeds 1 --orders 1 --timeout 10
    .venv/bin/python experiments/temporal_parallel.py --table experiments/results/temporal_parallel.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.planning.compile import compile as compile_state
from ocplus_plan.planning.engines import availability, get_planner, solve
from ocplus_plan.sim import make_rules, new_state


def run_one(preset: str, cooks: int, planner: str, seed: int, orders: int,
            timeout: float) -> dict:
    state = new_state(make_rules(preset, n_agents=cooks), seed)
    row = {"preset": preset, "cooks": cooks, "planner": planner, "seed": seed,
           "orders": [list(map(int, o.recipe)) for o in state.orders[:orders]]}
    t0 = time.perf_counter()
    for anticipate in (False, True):
        if anticipate and not state.rules.dynamic:
            break
        compiled = compile_state(state, encoding="temporal", max_orders=orders,
                                 anticipate_switches=anticipate)
        left = timeout - (time.perf_counter() - t0)
        if left <= 0.5:
            row.update(status="timeout", anticipate=anticipate)
            break
        # an anytime engine runs for its whole limit: its own (smaller) limit is its budget
        res = solve(compiled.problem, planner, timeout=min(left, get_planner(planner).timeout),
                    validate=True)
        row.update(status=res.status, anticipate=anticipate,
                   planning_time=round(res.planning_time, 3), makespan=res.makespan,
                   validated=res.validated, reason=res.reason[:200])
        if res.status != "unsolvable":
            break
    row["wall"] = round(time.perf_counter() - t0, 3)
    return row


def ratios(rows: list[dict]) -> list[dict]:
    out = []
    keys = sorted({(r["preset"], r["planner"], r["seed"]) for r in rows})
    for preset, planner, seed in keys:
        by = {r["cooks"]: r for r in rows
              if (r["preset"], r["planner"], r["seed"]) == (preset, planner, seed)}
        one, two = by.get(1, {}).get("makespan"), by.get(2, {}).get("makespan")
        out.append({"ratio": True, "preset": preset, "planner": planner, "seed": seed,
                    "makespan_1": one, "makespan_2": two,
                    "two_over_one": round(two / one, 3) if one and two else None})
    return out


def table(path: Path) -> str:
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    runs = [r for r in rows if not r.get("ratio")]
    lines = [("| preset | planner | seed | 1 cook: status, s, makespan "
              "| 2 cooks: status, s, makespan | 2 / 1 |"), "|---|---|---|---|---|---|"]
    for q in (r for r in rows if r.get("ratio")):
        cells = []
        for cooks in (1, 2):
            r = next((x for x in runs if (x["preset"], x["planner"], x["seed"], x["cooks"])
                      == (q["preset"], q["planner"], q["seed"], cooks)), None)
            if r is None:
                cells.append("-")
                continue
            mark = " (switches anticipated)" if r.get("anticipate") else ""
            ok = "validated" if r.get("validated") else r["status"]
            cells.append(f"{ok}{mark}, {r['wall']:.1f} s, {r.get('makespan') or '-'}")
        ratio = q["two_over_one"]
        lines.append(f"| {q['preset']} | {q['planner']} | {q['seed']} | {cells[0]} | {cells[1]} "
                     f"| {ratio if ratio is not None else '-'} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--planners", nargs="+", default=["kairos", "kairos-anytime"])
    p.add_argument("--presets", nargs="+", default=["easy", "medium", "hard"])
    p.add_argument("--seeds", type=int, default=1, help="seeds 0..N-1 (default: %(default)s)")
    p.add_argument("--orders", type=int, default=1, help="open orders to serve (default: 1)")
    p.add_argument("--timeout", type=float, default=10.0,
                   help="seconds for compile + solve, both attempts together (default: 10)")
    p.add_argument("--out", type=Path, default=None, help="also append the JSON lines here")
    p.add_argument("--table", type=Path, default=None, help="print the README table and stop")
    args = p.parse_args(argv)
    if args.table:
        print(table(args.table))
        return 0
    warnings.simplefilter("ignore")
    out = args.out.open("a") if args.out else None
    rows = []
    for planner in args.planners:
        a = availability(planner)
        if not a.ok:
            print(json.dumps({"planner": planner, "skipped": a.reason}), flush=True)
            continue
        for preset in args.presets:
            for seed in range(args.seeds):
                for cooks in (1, 2):
                    row = run_one(preset, cooks, planner, seed, args.orders, args.timeout)
                    rows.append(row)
                    print(json.dumps(row), flush=True)
                    if out:
                        out.write(json.dumps(row) + "\n")
    for r in ratios(rows):
        print(json.dumps(r), flush=True)
        if out:
            out.write(json.dumps(r) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

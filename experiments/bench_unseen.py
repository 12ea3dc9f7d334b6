"""Benchmark the planning pipeline on generated kitchens it has never seen, against greedy.

Grid: families x ``--kitchens-per-family`` test-split kitchens (``gen:FAMILY:test:INDEX:PRESET``)
x ``--cooks`` x ``--seeds`` x ``--steps`` steps; each cell is played by greedy and by the
planner (``--planner``, default the default configuration ``fast-downward``), and for 2 cooks
or more also by the planner beside each ``--partners`` agent playing the last cook (``idle``:
it stands still; ``greedy``). One JSON line per episode, then summary lines and a table:

- per family: greedy's and the planner's mean dishes and their ratio (and overall);
- every episode where the planner serves 0 dishes and greedy 2 or more, with its cause;
- livelock stretches (30 steps or more with blocked replans and no plan step done);
- partners: with an idle partner, the planner's dishes against the planner alone with one
  cook fewer (target 0.8 or more); with a greedy partner, against greedy with every cook.

Planner calls are limited in CPU seconds (``--timeout``), so dishes do not depend on the
machine's load; rows give each episode's planning wall and CPU seconds and the 1-minute load
average when it started. ``--busy N`` runs N processes that spin on the CPU beside the whole
run; ``--compare A B`` lists the cells whose dishes differ between two runs (the load check:
the same grid once alone and once with ``--busy 2``).

Examples::

    .venv/bin/python experiments/bench_unseen.py --kitchens-per-family 1 --seeds 1 \\
        --out experiments/results/unseen/grid.jsonl
    .venv/bin/python experiments/bench_unseen.py --table experiments/results/unseen/grid.jsonl
    .venv/bin/python experiments/bench_unseen.py --kitchens-per-family 2 --cooks 2 --busy 2 \\
        --out loaded.jsonl && .venv/bin/python experiments/bench_unseen.py --compare grid.jsonl loaded.jsonl
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import statistics
import sys
import time
import warnings
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.agents import make_controller, run_episode  # noqa: E402
from ocplus_plan.agents import with_partner  # noqa: E402
from ocplus_plan.agents.planner import make_planner_agent  # noqa: E402
from ocplus_plan.sim import make_rules, new_state  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402
from ocplus_plan.sim.queries import stations_cut_off  # noqa: E402
from ocplus_plan.sim.stations import KIND_OF  # noqa: E402

#: the kitchens of these families switch layouts (the hard rules); the others are static
DYNAMIC = frozenset({"switching"})


def run_one(family: str, index: int, cooks: int, seed: int, agent: str, partner: str | None,
            args: argparse.Namespace) -> dict:
    name = f"gen:{family}:{args.split}:{index}:{args.preset}"
    rules = make_rules(args.preset, map=name, n_agents=cooks, horizon=args.steps,
                       dynamic=family in DYNAMIC)
    state = new_state(rules, seed)
    if agent.startswith("planner:"):
        controller = make_planner_agent(agent.partition(":")[2], seed, timeout=args.timeout)
    else:
        controller = make_controller(agent, seed)
    cuts = idle_cuts(state) if partner == "idle" else None
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    stats = run_episode(state, with_partner(controller, partner, cooks, seed))
    wall = time.perf_counter() - t0
    info = controller.info()
    return {
        "family": family, "kitchen": name, "index": index, "cooks": cooks, "seed": seed,
        "agent": agent, "partner": partner, "steps": stats["t"],
        "dishes": stats["dishes_served"], "wall_s": round(wall, 2), "load_1min": round(load, 2),
        "busy": args.busy, **({"partner_cuts": cuts} if cuts is not None else {}),
        **({k: info.get(k) for k in (
            "planner_calls", "statuses", "replans_by_reason", "planning_time", "planning_cpu_s",
            "livelocks_detected", "livelock_stretches", "gave_way", "all_cooks_fallbacks",
            "proven_answers_reused", "steps_done", "failure_messages")}
           if "planner_calls" in info else {}),
    }


def idle_cuts(state: object) -> list[str]:
    """The stations an idle last cook, standing on its spawn cell all episode, cuts off from
    every other cook (the kitchen then cannot serve what needs them, whoever plans)."""
    geo = state.geo
    last = state.n_agents - 1
    cells = stations_cut_off(geo, state.layout_index, state.agent_pos[last],
                             [state.agent_pos[a] for a in range(last)])
    return sorted({KIND_OF[geo.terrains[state.layout_index][c]].name for c in cells})


def cause(row: dict) -> str:
    """Why a planner episode served nothing, read from its counts."""
    if row.get("livelock_stretches"):
        return f"livelock: {row['livelock_stretches']}"
    statuses = row.get("statuses") or {}
    if not statuses.get("solved"):
        msgs = row.get("failure_messages") or {}
        return "no plan found: " + (next(iter(msgs)) if msgs else json.dumps(statuses))
    replans = row.get("replans_by_reason") or {}
    stuck = {k: v for k, v in replans.items() if k in ("blocked", "deadlock", "stalled",
                                                         "unreachable", "action_failed")}
    if stuck:
        return f"plans made ({statuses.get('solved')}) but execution stuck: {stuck}"
    return f"plans made ({statuses.get('solved')}), {row.get('steps_done')} steps done, none served"


def summarise(rows: list[dict], planner: str) -> list[dict]:
    """Summary lines: per family and overall, the failures with causes, livelocks, partners."""
    def mean(xs: list[float]) -> float | None:
        return round(statistics.mean(xs), 3) if xs else None

    # one row per episode (the last one run), and per family only the cells both played
    cell = {(r["kitchen"], r["cooks"], r["seed"], r["agent"], r["partner"]): r for r in rows}
    rows = list(cell.values())
    for r in rows:  # files written before rows carried it
        if r["partner"] == "idle" and "partner_cuts" not in r:
            preset = r["kitchen"].rsplit(":", 1)[1]
            rules = make_rules(preset, map=r["kitchen"], n_agents=r["cooks"],
                               dynamic=r["family"] in DYNAMIC)
            r["partner_cuts"] = idle_cuts(new_state(rules, r["seed"]))
    solo = [r for r in rows if r["partner"] is None
            and (r["kitchen"], r["cooks"], r["seed"], planner, None) in cell
            and (r["kitchen"], r["cooks"], r["seed"], "greedy", None) in cell]
    out = []
    by_family: dict[str, dict[str, list[int]]] = defaultdict(lambda: defaultdict(list))
    for r in solo:
        by_family[r["family"]][r["agent"]].append(r["dishes"])
        by_family["all"][r["agent"]].append(r["dishes"])
    for family, d in by_family.items():
        g, p = mean(d["greedy"]), mean(d[planner])
        out.append({"summary": "family", "family": family, "episodes": len(d[planner]),
                    "greedy": g, "planner": p,
                    "ratio": round(p / g, 3) if g and p is not None else None})
    for r in solo:
        if r["agent"] != planner or r["dishes"]:
            continue
        g = cell.get((r["kitchen"], r["cooks"], r["seed"], "greedy", None))
        if g is not None and g["dishes"] >= 2:
            out.append({"summary": "planner_0_greedy_2", "kitchen": r["kitchen"],
                        "cooks": r["cooks"], "seed": r["seed"], "greedy": g["dishes"],
                        "cause": cause(r)})
    stretches = [(r["kitchen"], r["cooks"], r["seed"], r["partner"], r["livelock_stretches"])
                 for r in rows if r.get("livelock_stretches")]
    out.append({"summary": "livelock", "episodes_with_stretches": len(stretches),
                "stretches": stretches})
    for partner, versus in (("idle", "alone with one cook fewer"),
                            ("greedy", "greedy, every cook")):
        pairs = []
        for r in rows:
            if r["partner"] != partner:
                continue
            ref = cell.get((r["kitchen"], r["cooks"] - 1, r["seed"], planner, None)) \
                if partner == "idle" else cell.get((r["kitchen"], r["cooks"], r["seed"],
                                                    "greedy", None))
            if ref is not None:
                pairs.append((r["dishes"], ref["dishes"], r))
        if pairs:
            a, b = mean([x for x, _, _ in pairs]), mean([y for _, y, _ in pairs])
            line = {"summary": f"partner_{partner}", "versus": versus,
                    "episodes": len(pairs), "with_partner": a, "reference": b,
                    "ratio": round(a / b, 3) if b else None}
            if partner == "idle":
                free = [(x, y) for x, y, r in pairs if not r.get("partner_cuts")]
                fa, fb = mean([x for x, _ in free]), mean([y for _, y in free])
                line.update(episodes_not_cut=len(free), ratio_not_cut=round(fa / fb, 3)
                            if fb else None,
                            cut=[[r["kitchen"], r["cooks"], r["seed"], r["partner_cuts"], x, y]
                                 for x, y, r in pairs if r.get("partner_cuts")])
            out.append(line)
    return out


def table(summary: list[dict]) -> str:
    lines = ["| family | episodes | greedy | planner | planner / greedy |", "|---|---|---|---|---|"]
    for s in summary:
        if s["summary"] == "family":
            lines.append(f"| {s['family']} | {s['episodes']} | {s['greedy']} | {s['planner']} "
                         f"| {s['ratio']} |")
    return "\n".join(lines)


def compare(paths: list[Path]) -> dict:
    """Cells (kitchen, cooks, seed, agent, partner) played in both files, and those whose
    dishes differ, with the load each ran at."""
    runs = []
    for path in paths:
        rows = [json.loads(line) for line in path.read_text().splitlines()]
        runs.append({(r["kitchen"], r["cooks"], r["seed"], r["agent"], r["partner"]): r
                     for r in rows if "summary" not in r})
    both = sorted(set(runs[0]) & set(runs[1]), key=str)
    differ = [{"cell": list(k), "dishes": [runs[0][k]["dishes"], runs[1][k]["dishes"]],
               "load_1min": [runs[0][k].get("load_1min"), runs[1][k].get("load_1min")]}
              for k in both if runs[0][k]["dishes"] != runs[1][k]["dishes"]]
    loads = [[r.get("load_1min") for k, r in run.items() if k in set(both)] for run in runs]
    return {"summary": "compare", "files": [str(p) for p in paths], "cells": len(both),
            "same": len(both) - len(differ), "differ": differ,
            "load_1min_median": [statistics.median([x for x in ls if x is not None] or [0])
                                 for ls in loads]}


def _spin() -> None:
    while True:
        pass


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--families", nargs="+", default=list(FAMILIES), choices=FAMILIES)
    p.add_argument("--split", default="test")
    p.add_argument("--kitchens-per-family", type=int, default=2)
    p.add_argument("--first-kitchen", type=int, default=0, help="index of the first kitchen")
    p.add_argument("--cooks", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--seeds", type=int, default=1, help="seeds FIRST..FIRST+N-1")
    p.add_argument("--first-seed", type=int, default=0, help="the first seed (FIRST)")
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--preset", default="medium", help="stations and recipes (easy, medium, hard)")
    p.add_argument("--planner", default="planner:fast-downward-wastar",
                   help="the planner configuration (default: the default configuration)")
    p.add_argument("--partners", nargs="*", default=["idle", "greedy"],
                   help="agents that play the last cook beside the planner (2 cooks or more)")
    p.add_argument("--partners-only", action="store_true",
                   help="play only the partner variants (the solo rows come from another run)")
    p.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per planner call")
    p.add_argument("--out", type=Path, default=None, help="also append the JSON lines here")
    p.add_argument("--table", type=Path, nargs="+", default=None,
                   help="summarise these --out files and stop")
    p.add_argument("--busy", type=int, default=0,
                   help="processes spinning on the CPU beside the run (the load check)")
    p.add_argument("--compare", type=Path, nargs=2, default=None, metavar=("A", "B"),
                   help="the cells whose dishes differ between two --out files, and stop")
    args = p.parse_args(argv)
    if args.compare:
        print(json.dumps(compare(args.compare)))
        return 0
    if args.table:
        rows = [json.loads(line) for path in args.table for line in path.read_text().splitlines()]
        rows = [r for r in rows if "summary" not in r]
        summary = summarise(rows, args.planner)
        for s in summary:
            print(json.dumps(s))
        print(table(summary))
        return 0
    warnings.simplefilter("ignore")
    spinners = [multiprocessing.get_context("fork").Process(target=_spin, daemon=True)
                for _ in range(args.busy)]
    for proc in spinners:
        proc.start()
    try:
        return _run(args)
    finally:
        for proc in spinners:
            proc.kill()


def _run(args: argparse.Namespace) -> int:
    out = args.out.open("a") if args.out else None
    rows = []
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        for index in range(args.first_kitchen, args.first_kitchen + args.kitchens_per_family):
            for family in args.families:
                for cooks in args.cooks:
                    runs = [] if args.partners_only else [("greedy", None), (args.planner, None)]
                    runs += [(args.planner, q) for q in args.partners if cooks >= 2]
                    for agent, partner in runs:
                        row = run_one(family, index, cooks, seed, agent, partner, args)
                        rows.append(row)
                        line = json.dumps(row)
                        print(line, flush=True)
                        if out:
                            out.write(line + "\n")
                            out.flush()
    summary = summarise(rows, args.planner)
    for s in summary:
        line = json.dumps(s)
        print(line, flush=True)
        if out:
            out.write(line + "\n")
    print(table(summary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

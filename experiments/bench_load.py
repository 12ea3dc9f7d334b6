"""Do planner outcomes depend on machine load? The same planner calls twice: alone, then
beside ``--busy`` processes that spin on the CPU.

Calls (``--calls``): for each preset and number of cooks of ``--configs``, the initial
state of seed 0 and ``--samples`` sampled states (the instance sets' sampler), the
first open order as the goal, solved by every planner of ``--planners`` with
``--timeout`` seconds. With ``--limit cpu`` (the default) the limit is CPU seconds of
the planner's process group (the package's semantics); with ``--limit wall`` the same
number is a wall-clock limit (the old semantics, for contrast). Episodes
(``--episodes N``): the executive with ``--episode-planner`` on ``--episode-config`` for
seeds 0..N-1, ``--horizon`` steps, each planner call limited as above; dishes per seed.

Each outcome is compared between the two phases: status, plan (a hash of its steps) and
cost for a call; dishes, planner calls and statuses for an episode. One JSON line per
run and a summary line at the end (``same`` of ``total``), with the load average before
each phase::

    python experiments/bench_load.py --busy 4 --out experiments/results/load/calls_cpu.jsonl
"""

from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing
import os
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any


def _spin() -> None:
    while True:
        pass


def _calls(configs: list[str], samples: int) -> list[tuple[str, Any, Any]]:
    from ocplus_plan.planning.fidelity import sample_state
    from ocplus_plan.sim import make_rules, new_state

    out = []
    for config in configs:
        preset, cooks = config.split(":")
        rules = make_rules(preset, n_agents=int(cooks))
        out.append((f"{config}:initial", rules, new_state(rules, 0)))
        for k in range(samples):
            out.append((f"{config}:sample{k}", rules, sample_state(rules, 0, k, 120)))
    return out


def run_calls(args: argparse.Namespace) -> list[dict[str, Any]]:
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import get_planner, solve

    rows = []
    for name, _, state in _calls(args.configs, args.samples):
        for planner in args.planners:
            encoding = get_planner(planner).encoding
            compiled = compile(state, encoding=encoding, max_orders=1)
            if args.limit == "cpu":
                result = solve(compiled.problem, planner, timeout=args.timeout)
            else:
                result = solve(compiled.problem, planner, timeout=1e9, wall_limit=args.timeout)
            plan = json.dumps(result.steps, sort_keys=True)
            rows.append({"kind": "call", "instance": name, "planner": planner,
                         "status": result.status, "cost": result.cost,
                         "makespan": result.makespan, "plan_length": result.plan_length,
                         "plan_hash": hashlib.sha256(plan.encode()).hexdigest()[:16],
                         "cpu_time_s": result.cpu_time, "wall_time_s": result.planning_time,
                         "limit_hit": result.limit_hit})
    return rows


def run_episodes(args: argparse.Namespace) -> list[dict[str, Any]]:
    from ocplus_plan.agents import run_episode
    from ocplus_plan.agents.planner import PlannerAgent
    from ocplus_plan.sim import make_rules, new_state

    preset, cooks = args.episode_config.split(":")
    rows = []
    for seed in range(args.episodes):
        rules = make_rules(preset, n_agents=int(cooks))
        state = new_state(rules, seed)
        agent = PlannerAgent(args.episode_planner, timeout=args.timeout)
        t0 = time.perf_counter()
        stats = run_episode(state, [(agent, list(range(int(cooks))))], None, args.horizon)
        info = agent.info()
        rows.append({"kind": "episode", "config": args.episode_config, "seed": seed,
                     "planner": args.episode_planner, "dishes": stats["dishes_served"],
                     "planner_calls": info["planner_calls"], "statuses": info["statuses"],
                     "planning_time_s": info["planning_time"],
                     "wall_s": round(time.perf_counter() - t0, 3)})
    return rows


def _key(row: dict[str, Any]) -> tuple[Any, ...]:
    if row["kind"] == "call":
        return (row["instance"], row["planner"])
    return (row["config"], row["seed"], row["planner"])


def _outcome(row: dict[str, Any]) -> tuple[Any, ...]:
    if row["kind"] == "call":
        return (row["status"], row["plan_hash"], row["cost"], row["makespan"])
    return (row["dishes"], row["planner_calls"], tuple(sorted(row["statuses"].items())))


def phase(args: argparse.Namespace, busy: int) -> list[dict[str, Any]]:
    ctx = multiprocessing.get_context("fork")
    spinners = [ctx.Process(target=_spin, daemon=True) for _ in range(busy)]
    for proc in spinners:
        proc.start()
    try:
        time.sleep(5 if busy else 0)  # let the load average see them
        load = os.getloadavg()
        rows = (run_calls(args) if args.calls else []) + \
            (run_episodes(args) if args.episodes else [])
    finally:
        for proc in spinners:
            proc.kill()
            proc.join(5)
    for row in rows:
        row.update(busy=busy, loadavg_1min_at_start=round(load[0], 2), limit=args.limit,
                   timeout_s=args.timeout)
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--configs", nargs="+", default=["easy:1", "easy:2", "medium:1",
                                                    "medium:2", "hard:2"])
    p.add_argument("--samples", type=int, default=1, help="sampled states per config")
    p.add_argument("--planners", nargs="+", default=["fast-downward", "fast-downward-bjolp"])
    p.add_argument("--timeout", type=float, default=5.0, help="seconds per planner call")
    p.add_argument("--limit", choices=["cpu", "wall"], default="cpu")
    p.add_argument("--busy", type=int, default=4, help="spinning processes in phase two")
    p.add_argument("--no-calls", dest="calls", action="store_false")
    p.add_argument("--episodes", type=int, default=0, help="episodes (seeds 0..N-1)")
    p.add_argument("--episode-config", default="easy:2")
    p.add_argument("--episode-planner", default="fast-downward")
    p.add_argument("--horizon", type=int, default=100)
    p.add_argument("--out", type=Path, default=None, help="write the JSON lines here too")
    args = p.parse_args(argv)
    if args.limit == "wall" and args.episodes:
        p.error("--limit wall is for planner calls only (the executive's calls use CPU limits)")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, check=False).stdout.strip()
    alone, loaded = phase(args, 0), phase(args, args.busy)
    before = {_key(r): _outcome(r) for r in alone}
    same = [_key(r) for r in loaded if before.get(_key(r)) == _outcome(r)]
    differ = [list(_key(r)) for r in loaded if before.get(_key(r)) != _outcome(r)]
    summary = {"kind": "summary", "limit": args.limit, "timeout_s": args.timeout,
               "busy": args.busy, "same": len(same), "total": len(loaded), "differ": differ,
               "cpu_s_alone": round(sum(r.get("cpu_time_s") or 0 for r in alone), 2),
               "wall_s_alone": round(sum(r.get("wall_time_s") or r.get("wall_s") or 0
                                         for r in alone), 2),
               "wall_s_busy": round(sum(r.get("wall_time_s") or r.get("wall_s") or 0
                                        for r in loaded), 2),
               "commit": commit, "machine": f"{platform.node()} {os.cpu_count()} cores",
               "python": sys.version.split()[0], "argv": sys.argv[1:]}
    lines = [json.dumps(r, sort_keys=True) for r in (*alone, *loaded, summary)]
    print("\n".join(lines))
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Benchmark the executive: a planner-backed controller playing whole episodes.

For each planner, preset / agent count and seed, one episode of ``--steps`` steps
(default: the preset's horizon, 200) is played by ``PlannerAgent`` and one JSON
line is printed: dishes served, replans by reason, planner calls and statuses,
planning time and its share of the wall time, wall time, and the ratio to an
upper bound on dishes per episode. A summary line per configuration follows.

Upper bound (``dish_bound``): the shortest single-agent cycle that serves one dish
of the cheapest recipe of the pool, starting and ending at the serving window:
walk to each ingredient's spawn tile and on to its station, fetch the plate (and
wash it when plates get dirty), collect every ingredient on the plate, serve.
Walking distances are the shortest between any interaction spots (in whichever
layout is shorter), bumps are counted exactly (pick, put, chop/wash steps, plate,
serve), cooking waits and collisions are ignored. With perfect parallelism the
team serves at most ``n_agents * steps / cycle`` dishes.

Examples::

    .venv/bin/python experiments/bench_executive.py --configs easy:1 --seeds 2
    .venv/bin/python experiments/bench_executive.py --planners fast-downward kairos \\
        --configs easy:1 easy:2 medium:1 medium:2 hard:1 hard:2 --seeds 10
    .venv/bin/python experiments/bench_executive.py --configs medium:1 --faults burns \\
        --policies on_event never --seeds 5
"""

from __future__ import annotations

import argparse
import itertools
import json
import statistics
import sys
import time
import warnings
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.agents.planner import PlannerAgent
from ocplus_plan.execution.faults import FaultSchedule, run_episode
from ocplus_plan.execution.paths import bfs_distances, interaction_spots
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import VEGETABLES, Cell, Item
from ocplus_plan.sim.rules import Recipe, Rules
from ocplus_plan.sim.state import Geometry


def _cells(geo: Geometry, code: int) -> list[int]:
    return [c for c, v in enumerate(geo.terrains[0]) if v == code]


def _seeded_bfs(geo: Geometry, walk: tuple[bool, ...] | list[bool], seed: list[float]) -> list[float]:
    """Unit-step shortest distances in one layout from cells that start at ``seed`` values."""
    import heapq

    dist = [v if walk[c] else float("inf") for c, v in enumerate(seed)]
    heap = [(v, c) for c, v in enumerate(dist) if v < float("inf")]
    heapq.heapify(heap)
    while heap:
        d, c = heapq.heappop(heap)
        if d > dist[c]:
            continue
        for nb in geo.neighbors[c]:
            if nb >= 0 and walk[nb] and d + 1 < dist[nb]:
                dist[nb] = d + 1
                heapq.heappush(heap, (d + 1, nb))
    return dist


def dish_cycle(rules: Rules, geo: Geometry, recipe: Recipe) -> int:
    """Lower bound on the steps one agent needs per dish of ``recipe`` in steady state."""
    targets = set(_cells(geo, Cell.DELIVERY) + _cells(geo, Cell.PLATE) + _cells(geo, Cell.SINK)
                  + _cells(geo, Cell.BOARD) + list(geo.pans))
    for kind in recipe:
        targets.update(_cells(geo, int(kind)))
    to: dict[int, list[float]] = {}
    for y in targets:
        # shortest walk to a spot of y, allowing one layout switch on the way (optimistic)
        best = [float("inf")] * len(geo.neighbors)
        for last in range(len(geo.walkables)):
            spots = interaction_spots(geo, geo.walkables[last], y)
            if not spots:
                continue
            d_last = [float(v) if v >= 0 else float("inf")
                      for v in bfs_distances(geo, geo.walkables[last], spots)]
            for first in range(len(geo.walkables)):
                d = d_last if first == last else _seeded_bfs(geo, geo.walkables[first], d_last)
                best = [min(a, b) for a, b in zip(best, d)]
        to[y] = best

    def dist(x: int, y: int) -> float:
        return min((to[y][s] for walk in geo.walkables for s in interaction_spots(geo, walk, x)),
                   default=float("inf"))

    bumps = 2 + (2 + rules.wash_steps if rules.dirty_plates else 0)
    for kind in recipe:
        bumps += 3 + (rules.chop_steps if kind in VEGETABLES else 0)
    best = float("inf")
    delivery = _cells(geo, Cell.DELIVERY)
    plates = _cells(geo, Cell.PLATE)
    sinks = _cells(geo, Cell.SINK) if rules.dirty_plates else [None]
    choices = [[(s, st) for s in _cells(geo, int(k))
                for st in (list(geo.pans) if k == Item.STEAK else _cells(geo, Cell.BOARD))]
               for k in recipe]
    for D, P, S in itertools.product(delivery, plates, sinks):
        for combo in itertools.product(*choices):
            for perm in itertools.permutations(combo):
                loc, walk = D, 0.0
                for spawn, station in perm:
                    walk += dist(loc, spawn) + dist(spawn, station)
                    loc = station
                walk += dist(loc, P)
                loc = P
                if S is not None:
                    walk += dist(P, S)
                    loc = S
                for _, station in perm:
                    walk += dist(loc, station)
                    loc = station
                walk += dist(loc, D)
                best = min(best, walk)
    return int(best) + bumps


def dish_bound(rules: Rules, steps: int) -> tuple[int, float]:
    """(cheapest dish cycle, upper bound on dishes in ``steps`` steps with perfect parallelism)."""
    geo = Geometry.build(rules)
    cycle = min(dish_cycle(rules, geo, r) for r in rules.recipes)
    return cycle, rules.n_agents * steps / cycle


def run_one(planner: str, preset: str, n_agents: int, seed: int, steps: int | None,
            policy: str, faults: str, granularity: str, timeout: float) -> dict:
    rules = make_rules(preset, n_agents=n_agents)
    state = new_state(rules, seed)
    from ocplus_plan.planning.engines import get_planner

    encoding = get_planner(planner).encoding
    agent = PlannerAgent(planner, encoding, granularity, policy, timeout=timeout)
    schedule = None
    if faults == "burns":
        schedule = FaultSchedule(burns=[20, 80, 140])
    elif faults == "switches":
        schedule = FaultSchedule(switches=[10, 50, 90, 130])
    t0 = time.perf_counter()
    stats = run_episode(state, [(agent, list(range(n_agents)))], schedule, steps)
    wall = time.perf_counter() - t0
    info = agent.info()
    horizon = stats["t"]
    cycle, bound = dish_bound(rules, horizon)
    return {
        "planner": planner, "encoding": encoding, "preset": preset, "agents": n_agents,
        "seed": seed, "policy": policy, "faults": faults, "steps": horizon,
        "dishes": stats["dishes_served"], "burns": stats["burns"],
        "wrong_deliveries": stats["wrong_deliveries"], "blocked_moves": stats["blocked_moves"],
        "replans": info["replans"], "replans_by_reason": info["replans_by_reason"],
        "planner_calls": info["planner_calls"], "statuses": info["statuses"],
        "planning_time": info["planning_time"], "wall": round(wall, 3),
        "planning_share": round(info["planning_time"] / wall, 3) if wall else 0.0,
        "dish_cycle": cycle, "dish_bound": round(bound, 2),
        "bound_ratio": round(stats["dishes_served"] / bound, 3) if bound else 0.0,
    }


def summarise(rows: list[dict]) -> dict:
    reasons: Counter[str] = Counter()
    for r in rows:
        reasons.update(r["replans_by_reason"])
    n = len(rows)
    return {
        "summary": True, **{k: rows[0][k] for k in ("planner", "preset", "agents", "policy",
                                                     "faults")},
        "episodes": n,
        "dishes_mean": round(statistics.mean(r["dishes"] for r in rows), 2),
        "dishes_min": min(r["dishes"] for r in rows),
        "episodes_with_a_dish": sum(r["dishes"] > 0 for r in rows),
        "replans_per_episode": round(sum(r["replans"] for r in rows) / n, 2),
        "replans_by_reason_per_episode": {k: round(v / n, 2) for k, v in sorted(reasons.items())},
        "planning_share": round(sum(r["planning_time"] for r in rows)
                                / max(1e-9, sum(r["wall"] for r in rows)), 3),
        "wall_mean": round(statistics.mean(r["wall"] for r in rows), 2),
        "wall_max": round(max(r["wall"] for r in rows), 2),
        "dish_bound": rows[0]["dish_bound"],
        "bound_ratio_mean": round(statistics.mean(r["bound_ratio"] for r in rows), 3),
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--planners", nargs="+", default=["fast-downward"])
    p.add_argument("--configs", nargs="+", default=["easy:1", "easy:2", "medium:1", "medium:2",
                                                    "hard:1", "hard:2"],
                   help="PRESET:AGENTS pairs (default: %(default)s)")
    p.add_argument("--seeds", type=int, default=10, help="seeds 0..N-1 (default: %(default)s)")
    p.add_argument("--steps", type=int, default=None, help="steps per episode (default: horizon)")
    p.add_argument("--policies", nargs="+", default=["on_event"])
    p.add_argument("--faults", choices=["none", "burns", "switches"], default="none")
    p.add_argument("--granularity", choices=["stations", "cells"], default="stations")
    p.add_argument("--timeout", type=float, default=10.0, help="seconds per planner call")
    p.add_argument("--out", type=Path, default=None, help="also append the JSON lines here")
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    out = args.out.open("a") if args.out else None
    for planner, config, policy in itertools.product(args.planners, args.configs, args.policies):
        preset, _, n = config.partition(":")
        rows = []
        for seed in range(args.seeds):
            row = run_one(planner, preset, int(n or 1), seed, args.steps, policy, args.faults,
                          args.granularity, args.timeout)
            rows.append(row)
            for line in (json.dumps(row),):
                print(line, flush=True)
                if out:
                    out.write(line + "\n")
        line = json.dumps(summarise(rows))
        print(line, flush=True)
        if out:
            out.write(line + "\n")
            out.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

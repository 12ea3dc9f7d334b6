"""Benchmark the executive: a planner-backed controller playing whole episodes.

For each planner, preset / agent count and seed, one episode of ``--steps`` steps
(default: the preset's horizon, 200) is played by ``PlannerAgent`` and one JSON
line is printed: dishes served, replans by reason, planner calls and statuses,
planning time and its share of the wall time, wall time, and the ratio to an
upper bound on dishes per episode. A summary line per configuration follows.

Upper bound: ``ocplus_plan.eval.bounds.dish_bound`` for the episode's own seed (its
order stream is known in advance): per agent, the first dish from its spawn cell
and then, per dish, the shortest closed tour through every tile the dish needs
(in any order, over cells walkable in any layout) plus the fewest bumps it
takes; cooking waits and collisions are ignored. See that module's docstring.

Examples::

    .venv/bin/python experiments/bench_executive.py --configs easy:1 --seeds 2
    .venv/bin/python experiments/bench_executive.py --planners fast-downward kairos \\
        --configs easy:1 easy:2 medium:1 medium:2 hard:1 hard:2 --seeds 10
    .venv/bin/python experiments/bench_executive.py --configs medium:1 --faults burns \\
        --policies on_event never --seeds 5
    .venv/bin/python experiments/bench_executive.py --planners kairos --configs hard:1 \
        --anticipate --seeds 10
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

from ocplus_plan.agents import run_episode
from ocplus_plan.agents import with_partner
from ocplus_plan.agents.planner import PlannerAgent
from ocplus_plan.eval.bounds import dish_bound
from ocplus_plan.execution.faults import FaultSchedule
from ocplus_plan.execution.spec import PlannerSpec
from ocplus_plan.sim import make_rules, new_state


def run_one(spec: PlannerSpec, preset: str, n_agents: int, seed: int, steps: int | None,
            faults: str, timeout: float, orders_per_plan: int | str | None = "auto",
            partner: str | None = None) -> dict:
    rules = make_rules(preset, n_agents=n_agents)
    state = new_state(rules, seed)
    from ocplus_plan.planning.engines import get_planner

    encoding = get_planner(spec.name).encoding
    agent = PlannerAgent(spec.name, encoding, spec.granularity, spec.policy, timeout=timeout,
                         orders_per_plan=orders_per_plan, **spec.agent_keywords())
    schedule = None
    if faults == "burns":
        schedule = FaultSchedule(burns=[20, 80, 140])
    elif faults == "switches":
        schedule = FaultSchedule(switches=[10, 50, 90, 130])
    t0 = time.perf_counter()
    stats = run_episode(state, with_partner(agent, partner, n_agents, seed), schedule, steps)
    wall = time.perf_counter() - t0
    info = agent.info()
    bound = dish_bound(rules, stats["t"], seed=seed)
    return {
        "planner": spec.name, "encoding": encoding, "preset": preset, "agents": n_agents,
        "seed": seed, "policy": spec.policy, "faults": faults, "partner": partner,
        "anticipate": spec.anticipate_switches, "schedule": spec.schedule_cooks,
        "orders_per_plan": orders_per_plan, "plan_cooks": spec.plan_cooks,
        "chain_orders": spec.chain_orders, "over_switches": spec.over_switches,
        "options": spec.options_text(),
        "steps": stats["t"],
        "dishes": stats["dishes_served"], "burns": stats["burns"],
        "wrong_deliveries": stats["wrong_deliveries"], "blocked_moves": stats["blocked_moves"],
        "replans": info["replans"], "replans_by_reason": info["replans_by_reason"],
        "planner_calls": info["planner_calls"], "statuses": info["statuses"],
        "planning_time": info["planning_time"], "wall": round(wall, 3),
        "planning_share": round(info["planning_time"] / wall, 3) if wall else 0.0,
        "dish_bound": bound.dishes, "dish_cycles": bound.cycles,
        "bound_ratio": round(bound.ratio(stats["dishes_served"]), 3),
    }


def summarise(rows: list[dict]) -> dict:
    reasons: Counter[str] = Counter()
    for r in rows:
        reasons.update(r["replans_by_reason"])
    n = len(rows)
    return {
        "summary": True, **{k: rows[0][k] for k in ("planner", "preset", "agents", "policy",
                                                     "faults", "anticipate", "schedule",
                                                     "orders_per_plan", "plan_cooks",
                                                     "chain_orders", "options", "partner")},
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
        "dish_bound_mean": round(statistics.mean(r["dish_bound"] for r in rows), 2),
        "bound_ratio_mean": round(statistics.mean(r["bound_ratio"] for r in rows), 3),
    }


def table(paths: list[Path]) -> list[str]:
    """README rows (markdown) from the summary lines of earlier ``--out`` files."""
    rows = []
    for path in paths:
        for line in path.read_text().splitlines():
            d = json.loads(line)
            if not d.get("summary"):
                continue
            options = d.get("options", "anticipate" if d.get("anticipate") else "")
            name = d["planner"] + (f" ({options})" if options else "")
            rows.append(
                f"| {name} | {d['preset']} {d['agents']} | {d['dishes_mean']:g} ({d['dishes_min']}) "
                f"| {d['episodes_with_a_dish']}/{d['episodes']} | {d['replans_per_episode']:g} "
                f"| {d['planning_share']:.2f} | {d['wall_mean']:.1f} / {d['wall_max']:.1f} "
                f"| {d['dish_bound_mean']:g} | {d['bound_ratio_mean']:.2f} |")
    return rows


def with_flags(spec: PlannerSpec, args: argparse.Namespace, policy: str | None) -> PlannerSpec:
    """The spec named in ``--planners`` with the options the flags add."""
    changes: dict = {} if policy is None else {"policy": policy}
    if args.granularity != "stations":
        changes["granularity"] = args.granularity
    if args.anticipate:
        changes["anticipate_switches"] = True
    if args.no_schedule:
        changes["schedule_cooks"] = False
    if args.plan_cooks != "all":
        changes["plan_cooks"] = args.plan_cooks
    if args.chain_orders != 1:
        changes["chain_orders"] = args.chain_orders
    if args.over_switches:
        changes["over_switches"] = True
    return spec.with_options(**changes)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--planners", nargs="+", default=["fast-downward"],
                   help="planner specs NAME[:GRANULARITY[:POLICY[:OPTIONS]]] as after planner: "
                        "(the flags below add options)")
    p.add_argument("--configs", nargs="+", default=["easy:1", "easy:2", "medium:1", "medium:2",
                                                    "hard:1", "hard:2"],
                   help="PRESET:AGENTS pairs (default: %(default)s)")
    p.add_argument("--seeds", type=int, default=10, help="seeds 0..N-1 (default: %(default)s)")
    p.add_argument("--steps", type=int, default=None, help="steps per episode (default: horizon)")
    p.add_argument("--policies", nargs="+", default=[None],
                   help="replanning policies (default: the spec's, on_event)")
    p.add_argument("--faults", choices=["none", "burns", "switches"], default="none")
    p.add_argument("--granularity", choices=["stations", "cells"], default="stations")
    p.add_argument("--timeout", type=float, default=10.0, help="seconds per planner call")
    p.add_argument("--anticipate", action="store_true",
                   help="temporal planners: plan around the coming layout switches (timed literals)")
    p.add_argument("--no-schedule", action="store_true",
                   help="run a sequential plan's steps with the cooks the planner chose instead "
                        "of scheduling its segments over the cooks (execution/schedule.py)")
    p.add_argument("--plan-cooks", choices=["all", "one"], default="all",
                   help="model every cook, or only the cooks holding an item (one when none "
                        "does) and schedule the plan over all (default: %(default)s)")
    p.add_argument("--chain-orders", type=int, default=1,
                   help="classical: plan up to K open orders one after the other, each from the "
                        "state the previous plan leaves (default: %(default)s)")
    p.add_argument("--over-switches", action="store_true",
                   help="switching maps: schedule the plan's walks over the coming layout "
                        "switches and expect every switch instead of replanning on it")
    p.add_argument("--orders-per-plan", default="auto",
                   help="'auto', 'all' or K: open orders one planner call covers (default: auto)")
    p.add_argument("--partner", default=None,
                   help="the last cook is played by this agent (idle, greedy, ...), the planner "
                        "drives the others")
    p.add_argument("--table", type=Path, nargs="+", default=None,
                   help="print the README table rows of these --out files and stop")
    p.add_argument("--out", type=Path, default=None, help="also append the JSON lines here")
    args = p.parse_args(argv)
    if args.table:
        print("\n".join(table(args.table)))
        return 0
    warnings.simplefilter("ignore")
    out = args.out.open("a") if args.out else None
    orders: int | str | None = args.orders_per_plan
    if orders == "all":
        orders = None
    elif orders != "auto":
        orders = int(orders)
    for planner, config, policy in itertools.product(args.planners, args.configs, args.policies):
        preset, _, n = config.partition(":")
        spec = with_flags(PlannerSpec.parse(planner), args, policy)
        rows = []
        for seed in range(args.seeds):
            row = run_one(spec, preset, int(n or 1), seed, args.steps, args.faults,
                          args.timeout, orders, args.partner)
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

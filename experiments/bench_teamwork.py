"""Benchmark the planning cook beside cooks it does not drive, and on the preset kitchens.

Groups (``--groups``; kitchens x ``--seeds`` seeds x ``--steps`` steps, one JSON line per
episode, then the targets with their numbers):

- ``greedy-partner``: medium and hard (the presets' maps) and the generated test kitchens
  (``--gen``, default kitchens 0-1 of every family, medium stations), 2 cooks: the default
  planner beside a greedy partner, and greedy driving both cooks. Targets: pooled at least
  what two greedy cooks serve, and at least 0.8x on each kitchen.
- ``idle-partner``: the generated kitchens: the default planner beside an idle partner
  (2 cooks) and alone with 1 cook. Target: at least 0.8 of the dishes served alone.
- ``learned-partner``: the generated kitchens, 2 cooks: the default planner beside a
  learned agent (``--learned``, default ``ppo``: on a generated kitchen the shipped
  generalist for 2 cooks, see docs/rl.md), and that agent driving both cooks. Target: pooled
  at least what the learned agent serves with itself.
- ``presets``: easy, medium, hard with 1 and 2 cooks: the default planner and greedy.
  Target: the planner at or above greedy on all six (hard with 2 cooks at least 3.0).
- ``zero``: ``--zero-kitchens`` test kitchens per family, 2 cooks, seed ``--first-seed``
  only: greedy and the default planner (``--zero-agents``: any planner configurations).
  Target: no kitchen where a planner configuration serves 0 and greedy 2 or more.

Every episode records its stalls (``execution/stall.py``: stretches of 30 steps or more
with no progress toward any open order, for any agent); the target is none in a planner
episode. Planner calls are limited in CPU seconds (``--timeout``); each row gives the
episode's CPU seconds (this process and its planner processes) and the 1-minute load.
``--resume`` skips the episodes already in ``--out``; ``--table FILE...`` prints the targets
of files already written.

Examples::

    nice -n 10 .venv/bin/python experiments/bench_teamwork.py --groups greedy-partner \\
        --seeds 1 --out experiments/results/teamwork/run.jsonl --resume
    nice -n 10 .venv/bin/python experiments/bench_teamwork.py --groups greedy-partner \\
        --kitchens hard --out experiments/results/teamwork/hard.jsonl
    .venv/bin/python experiments/bench_teamwork.py --table experiments/results/teamwork/run.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import sys
import time
import warnings
from collections import Counter, defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from experiments.bench_unseen import DYNAMIC  # noqa: E402
from ocplus_plan.agents import Episode, make_controller, with_partner  # noqa: E402
from ocplus_plan.agents.planner import make_planner_agent  # noqa: E402
from ocplus_plan.execution.stall import STALL_STRETCH, StallWatch  # noqa: E402
from ocplus_plan.sim import make_rules, new_state  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402

GROUPS = ("greedy-partner", "idle-partner", "learned-partner", "presets", "zero")
PLANNER = "planner:"  # the default planner
INFO = ("planner_calls", "statuses", "replans_by_reason", "planning_cpu_s", "partner_repairs",
        "claimed_plans",
        "stall_strategies", "livelock_stretches", "all_cooks_fallbacks", "failure_fallbacks",
        "default_planner_fallbacks", "failure_messages")


def _cpu() -> float:
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def gen_kitchens(spec: list[str] | None, per_family: int = 2, first: int = 0) -> list[str]:
    """``FAMILY:INDEX`` names (default: kitchens FIRST..FIRST+N-1 of every family)."""
    if spec:
        return [f"gen:{s.split(':')[0]}:test:{s.split(':')[1]}:medium" for s in spec]
    return [f"gen:{f}:test:{i}:medium" for f in FAMILIES for i in range(first, first + per_family)]


def kitchen_rules(kitchen: str, cooks: int, steps: int):
    """The rules of a preset (``hard``) or a generated kitchen (``gen:...:medium``, the
    switching family with its layout switches on)."""
    preset, map_name = (kitchen, None) if not kitchen.startswith("gen:") else ("medium", kitchen)
    extra = {} if map_name is None else {"dynamic": kitchen.split(":")[1] in DYNAMIC}
    return make_rules(preset, map=map_name, n_agents=cooks, horizon=steps, **extra)


def run_one(group: str, kitchen: str, cooks: int, seed: int, agent: str, partner: str | None,
            args: argparse.Namespace) -> dict:
    """One episode: its dishes, stalls and the planner's counts."""
    state = new_state(kitchen_rules(kitchen, cooks, args.steps), seed)
    if agent.startswith("planner:"):
        controller = make_planner_agent(agent.partition(":")[2], seed, timeout=args.timeout)
    else:
        controller = make_controller(agent, seed)
    stalls = StallWatch(state)
    load, cpu0, t0 = os.getloadavg()[0], _cpu(), time.perf_counter()
    Episode(state, with_partner(controller, partner, cooks, seed)).run(
        on_step=lambda ep, res: stalls.update(state))
    info = controller.info()
    return {"group": group, "kitchen": kitchen, "cooks": cooks, "seed": seed, "agent": agent,
            "partner": partner, "dishes": state.stats["dishes_served"], **stalls.info(),
            "cpu_s": round(_cpu() - cpu0, 2), "wall_s": round(time.perf_counter() - t0, 2),
            "load_1min": round(load, 2), **{k: info[k] for k in INFO if k in info}}


def cells(args: argparse.Namespace) -> list[tuple[str, str, int, int, str, str | None]]:
    """(group, kitchen, cooks, seed, agent, partner) of every episode asked for."""
    gens = gen_kitchens(args.gen, args.gen_per_family, args.gen_first)
    seeds = range(args.first_seed, args.first_seed + args.seeds)
    out = []
    for seed in seeds:
        if "greedy-partner" in args.groups:
            for k in ["medium", "hard", *gens]:
                out += [("greedy-partner", k, 2, seed, PLANNER, "greedy"),
                        ("greedy-partner", k, 2, seed, "greedy", None)]
        if "idle-partner" in args.groups:
            for k in gens:
                out += [("idle-partner", k, 2, seed, PLANNER, "idle"),
                        ("idle-partner", k, 1, seed, PLANNER, None)]
        if "learned-partner" in args.groups:
            for k in gens:
                out += [("learned-partner", k, 2, seed, PLANNER, args.learned),
                        ("learned-partner", k, 2, seed, args.learned, None)]
        if "presets" in args.groups:
            for k in ("easy", "medium", "hard"):
                for n in (1, 2):
                    out += [("presets", k, n, seed, PLANNER, None),
                            ("presets", k, n, seed, "greedy", None)]
    if "zero" in args.groups:
        for f in FAMILIES:
            for i in range(args.zero_kitchens):
                k = f"gen:{f}:test:{i}:medium"
                out += [("zero", k, 2, args.first_seed, "greedy", None)]
                out += [("zero", k, 2, args.first_seed, a, None) for a in args.zero_agents]
    return out


def _key(r: dict) -> tuple:
    return (r["group"], r["kitchen"], r["cooks"], r["seed"], r["agent"], r["partner"])


def _ratio(a: float, b: float) -> float | None:
    return round(a / b, 3) if b else None


def targets(rows: list[dict]) -> list[dict]:
    """The targets, each with its number and whether it is reached (on the rows given)."""
    cell = {_key(r): r for r in rows}
    out: list[dict] = []
    pairs = defaultdict(list)  # kitchen -> (with greedy partner, greedy every cook)
    for r in cell.values():
        if r["group"] == "greedy-partner" and r["partner"] == "greedy":
            ref = cell.get(("greedy-partner", r["kitchen"], 2, r["seed"], "greedy", None))
            if ref is not None:
                pairs[r["kitchen"]].append((r["dishes"], ref["dishes"], r["seed"]))
    if pairs:
        per = {k: (sum(a for a, _, _ in v), sum(b for _, b, _ in v), len(v)) for k, v in pairs.items()}
        a, b = sum(x for x, _, _ in per.values()), sum(y for _, y, _ in per.values())
        low = {k: _ratio(x, y) for k, (x, y, _) in per.items() if y and x < 0.8 * y}
        out.append({"target": "greedy partner: pooled >= 1.0x two greedy cooks, >= 0.8x each",
                    "episodes": sum(n for _, _, n in per.values()), "planner_with_partner": a,
                    "two_greedy": b, "pooled_ratio": _ratio(a, b),
                    "per_kitchen": {k: [x, y, n] for k, (x, y, n) in per.items()},
                    "below_0.8": low, "reached": bool(b) and a >= b and not low})
    idle = [(r["dishes"], cell[("idle-partner", r["kitchen"], 1, r["seed"], PLANNER, None)]["dishes"])
            for r in cell.values() if r["group"] == "idle-partner" and r["partner"] == "idle"
            and ("idle-partner", r["kitchen"], 1, r["seed"], PLANNER, None) in cell]
    if idle:
        a, b = sum(x for x, _ in idle), sum(y for _, y in idle)
        out.append({"target": "idle partner: >= 0.8 of the dishes served alone",
                    "episodes": len(idle), "with_idle_partner": a, "alone": b,
                    "ratio": _ratio(a, b), "reached": bool(b) and a >= 0.8 * b})
    out += _learned_target(cell)
    presets = defaultdict(lambda: defaultdict(list))
    for r in cell.values():
        if r["group"] == "presets":
            presets[f"{r['kitchen']} {r['cooks']}"][r["agent"]].append(r["dishes"])
    if presets:
        means = {k: {a: round(statistics.mean(v), 2) for a, v in d.items()} for k, d in presets.items()}
        below = [k for k, m in means.items() if m.get(PLANNER, 0) < m.get("greedy", 0)]
        hard2 = means.get("hard 2", {}).get(PLANNER)
        out.append({"target": "presets: planner >= greedy on all six, hard 2 >= 3.0",
                    "means": means, "seeds": {k: len(d[PLANNER]) for k, d in presets.items()},
                    "below_greedy": below, "hard_2": hard2,
                    "reached": not below and hard2 is not None and hard2 >= 3.0
                    and len(means) == 6})
    zero = [f"{r['agent']} {r['kitchen']}" for r in cell.values() if r["group"] == "zero"
            and r["agent"].startswith("planner:") and r["dishes"] == 0
            and cell.get(("zero", r["kitchen"], 2, r["seed"], "greedy", None),
                         {"dishes": 0})["dishes"] >= 2]
    n_zero = Counter(r["agent"] for r in cell.values() if r["group"] == "zero"
                     and r["agent"].startswith("planner:"))
    if n_zero:
        out.append({"target": "no kitchen with planner 0 and greedy >= 2", "kitchens": n_zero,
                    "planner_0_greedy_2": zero, "reached": not zero})
    stalls = [[_key(r), r["stall_stretches"]] for r in cell.values()
              if r["agent"].startswith("planner") and r.get("stall_stretches")]
    out.append({"target": f"no stall of {STALL_STRETCH} steps in a planner episode",
                "planner_episodes": sum(1 for r in cell.values() if r["agent"].startswith("planner")),
                "with_stall": len(stalls), "stalls": stalls, "reached": not stalls})
    out.append({"cpu_s": round(sum(r.get("cpu_s", 0) for r in cell.values()), 1),
                "episodes": len(cell)})
    return out


def _learned_target(cell: dict[tuple, dict]) -> list[dict]:
    """Beside a learned partner against that agent driving both cooks (pooled, per kitchen)."""
    per: dict[str, list[int]] = defaultdict(lambda: [0, 0, 0])
    for r in cell.values():
        if r["group"] == "learned-partner" and r["agent"] == PLANNER:
            ref = cell.get(("learned-partner", r["kitchen"], 2, r["seed"], r["partner"], None))
            if ref is not None:
                row = per[r["kitchen"]]
                row[0], row[1], row[2] = row[0] + r["dishes"], row[1] + ref["dishes"], row[2] + 1
    if not per:
        return []
    a, b = sum(x for x, _, _ in per.values()), sum(y for _, y, _ in per.values())
    return [{"target": "learned partner: pooled >= what it serves with itself",
             "episodes": sum(n for _, _, n in per.values()), "planner_with_learned": a,
             "learned_both_cooks": b, "pooled_ratio": _ratio(a, b), "per_kitchen": dict(per),
             "reached": a >= b}]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--groups", nargs="+", default=list(GROUPS), choices=GROUPS)
    p.add_argument("--seeds", type=int, default=5, help="seeds FIRST..FIRST+N-1")
    p.add_argument("--first-seed", type=int, default=0)
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--gen", nargs="*", default=None, metavar="FAMILY:INDEX",
                   help="generated test kitchens (default: --gen-per-family of every family)")
    p.add_argument("--kitchens", nargs="+", default=None, metavar="KITCHEN",
                   help="only these kitchens (hard, gen:corridor:test:0:medium, ...)")
    p.add_argument("--gen-per-family", type=int, default=2)
    p.add_argument("--gen-first", type=int, default=0)
    p.add_argument("--zero-kitchens", type=int, default=20, help="kitchens per family (zero)")
    p.add_argument("--zero-agents", nargs="+", default=[PLANNER], metavar="planner:SPEC",
                   help="the planner configurations of zero (default: the default planner)")
    p.add_argument("--learned", default="ppo",
                   help="the learned agent of learned-partner (ppo: the shipped generalist)")
    p.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per planner call")
    p.add_argument("--out", type=Path, default=None, help="also append the JSON lines here")
    p.add_argument("--resume", action="store_true", help="skip the episodes already in --out")
    p.add_argument("--table", type=Path, nargs="+", default=None,
                   help="print the targets of these files, and stop")
    args = p.parse_args(argv)
    if args.table:
        rows = [json.loads(line) for path in args.table for line in path.read_text().splitlines()]
        for t in targets([r for r in rows if "group" in r]):
            print(json.dumps(t))
        return 0
    warnings.simplefilter("ignore")
    done: set[tuple] = set()
    if args.resume and args.out and args.out.exists():
        done = {_key(json.loads(line)) for line in args.out.read_text().splitlines()
                if '"group"' in line}
    out = args.out.open("a") if args.out else None
    rows = []
    for group, kitchen, cooks, seed, agent, partner in cells(args):
        if (group, kitchen, cooks, seed, agent, partner) in done or \
                (args.kitchens and kitchen not in args.kitchens):
            continue
        row = run_one(group, kitchen, cooks, seed, agent, partner, args)
        rows.append(row)
        print(json.dumps(row), flush=True)
        if out:
            out.write(json.dumps(row) + "\n")
            out.flush()
    for t in targets(rows):
        print(json.dumps(t))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The README's planners-against-greedy table: planner episodes (``bench_executive.py --out``
files) beside the greedy cook on the same presets, cook counts and seeds.

The greedy episodes are played here (they take a second); each planner column is the mean
dishes of one results file over its episodes of that configuration; the bound column is
the mean of the episodes' ``dish_bound`` (the seed's upper bound, ``eval/bounds.py``), and
the last column the best planner mean over that bound.

    .venv/bin/python experiments/planners_vs_greedy.py \\
        "fd-bjolp one-cook+chain2=experiments/results/executive/all-presets-1-2cooks_fast-downward-bjolp_one-cook-chain2_code-604ae5c.jsonl" \\
        "fd-wastar=experiments/results/executive/all-presets-1-2cooks_fast-downward-wastar_code-604ae5c.jsonl" \\
        "kairos=experiments/results/executive/all-presets-1-2cooks_kairos_code-604ae5c.jsonl"
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.agents import make_controller, run_episode
from ocplus_plan.sim import make_rules, new_state

CONFIGS = [("easy", 1), ("easy", 2), ("medium", 1), ("medium", 2), ("hard", 1), ("hard", 2)]


def greedy_dishes(preset: str, cooks: int, seeds: list[int]) -> list[int]:
    out = []
    for seed in seeds:
        state = new_state(make_rules(preset, n_agents=cooks), seed)
        stats = run_episode(state, [(make_controller("greedy", seed), list(range(cooks)))])
        out.append(stats["dishes_served"])
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("columns", nargs="+", help="LABEL=PATH of a bench_executive --out file")
    args = p.parse_args(argv)
    columns = []
    for col in args.columns:
        label, _, path = col.partition("=")
        rows = [json.loads(line) for line in Path(path).read_text().splitlines() if line.strip()]
        columns.append((label, [r for r in rows if not r.get("summary")]))
    print("| config | greedy | " + " | ".join(label for label, _ in columns) + " | bound | best / bound |")
    print("|---" * (len(columns) + 4) + "|")
    for preset, cooks in CONFIGS:
        cells, bounds, seeds = [], [], set()
        for _, rows in columns:
            mine = [r for r in rows if (r["preset"], r["agents"]) == (preset, cooks)]
            seeds.update(r["seed"] for r in mine)
            bounds += [r["dish_bound"] for r in mine]
            cells.append(statistics.mean(r["dishes"] for r in mine) if mine else None)
        if not seeds:
            continue
        greedy = statistics.mean(greedy_dishes(preset, cooks, sorted(seeds)))
        best = max((c for c in cells if c is not None), default=None)
        bound = statistics.mean(bounds)
        shown = [("-" if c is None else (f"**{c:g}**" if c >= greedy else f"{c:g}")) for c in cells]
        print(f"| {preset} {cooks} | {greedy:g} | " + " | ".join(shown)
              + f" | {bound:g} | {best / bound:.2f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

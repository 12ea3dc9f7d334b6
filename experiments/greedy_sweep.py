"""The scripted greedy controller on every shipped map, preset and agent count.

For each (preset, map, n_agents) that the rules accept, runs SEEDS episodes of 200 steps
with ``greedy`` and prints one JSON line (dishes served, burns, wrong deliveries, mean and
min/max over seeds), then a totals line. Used for the greedy numbers in the README.

    .venv/bin/python experiments/greedy_sweep.py [--seeds 5] [--agent greedy]
"""

from __future__ import annotations

import argparse
import json
import statistics

from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.runner import EpisodeSpec, evaluate_episode
from ocplus_plan.sim import available_maps, make_rules


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--agent", default="greedy")
    ap.add_argument("--horizon", type=int, default=200)
    args = ap.parse_args()
    totals = {"configs": 0, "episodes": 0, "dishes_served": 0, "burns": 0, "wrong_deliveries": 0,
              "configs_serving": 0}
    for preset in ("easy", "medium", "hard"):
        for name in sorted(available_maps()):
            for n in (1, 2, 3):
                try:
                    make_rules(preset, map=name, n_agents=n)
                except ConfigError:
                    continue
                rows = [evaluate_episode(EpisodeSpec(preset, name, name, n, args.agent, seed,
                                                args.horizon)) for seed in range(args.seeds)]
                dishes = [r["metrics"]["dishes_served"] for r in rows]
                burns = sum(r["metrics"]["burns"] for r in rows)
                wrong = sum(r["metrics"]["wrong_deliveries"] for r in rows)
                print(json.dumps({"preset": preset, "map": name, "n_agents": n,
                                  "agent": args.agent, "seeds": args.seeds,
                                  "dishes_mean": round(statistics.mean(dishes), 2),
                                  "dishes_min": min(dishes), "dishes_max": max(dishes),
                                  "burns": burns, "wrong_deliveries": wrong,
                                  "errors": sum(r["status"] != "ok" for r in rows)}))
                totals["configs"] += 1
                totals["episodes"] += len(rows)
                totals["dishes_served"] += sum(dishes)
                totals["burns"] += burns
                totals["wrong_deliveries"] += wrong
                totals["configs_serving"] += min(dishes) > 0
    print(json.dumps({"totals": totals}))


if __name__ == "__main__":
    main()

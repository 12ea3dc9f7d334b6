"""Steps per second of the raw transition, per preset, with random actions.

Median of 5 runs of N steps each on one core (actions drawn up front so the
timing is the transition alone; episodes restart with ``new_state`` at the
horizon, which is included). Prints one JSON line per configuration.

    python experiments/bench_sim.py [--steps 50000] [--runs 5]
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time

import numpy as np

from ocplus_plan.sim import make_rules, new_state, transition

CONFIGS = [("easy", 1), ("easy", 2), ("medium", 1), ("medium", 2), ("hard", 2)]


def bench_transition(preset: str, n_agents: int, steps: int, runs: int) -> dict:
    rules = make_rules(preset, n_agents=n_agents)
    actions = np.random.default_rng(0).integers(0, 5, size=(steps, n_agents)).tolist()
    rates = []
    for run in range(runs):
        state = new_state(rules, run)
        t0 = time.perf_counter()
        for joint in actions:
            if transition(state, joint).truncated:
                state = new_state(rules, run)
        rates.append(steps / (time.perf_counter() - t0))
    return {
        "bench": "transition", "preset": preset, "map": rules.layout.name, "n_agents": n_agents,
        "steps": steps, "runs": runs, "steps_per_s_median": round(statistics.median(rates)),
        "steps_per_s_min": round(min(rates)), "python": platform.python_version(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=50_000)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    for preset, n in CONFIGS:
        print(json.dumps(bench_transition(preset, n, args.steps, args.runs)), flush=True)


if __name__ == "__main__":
    main()

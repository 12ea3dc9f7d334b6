"""Speed of two source trees side by side, in one run: the single env, the raw transition and
the numba batch engine, in CPU seconds, the trees taking turns (A B A B ...) so load on a
shared machine hits both alike.

Each measurement runs in a fresh interpreter whose ``ocplus_plan`` is imported from the
given tree (``PYTHONPATH``), with random actions drawn up front from a fixed seed:

* ``env``: ``OvercookedPlusEnv.step`` on the hard preset, 2 cooks, vector observations
  (resets included), CPU microseconds per step;
* ``transition``: ``sim.transition`` alone on the same kitchen, CPU microseconds per step;
* ``numba``: ``BatchSim`` (compiled, hard preset, 2 cooks, whole-map observations) stepping
  ``--kitchens`` kitchens, CPU microseconds per kitchen-step (compilation excluded: one
  warm-up step first; numba's on-disk cache is per tree).

Prints one JSON line per measurement and, last, the median of each tree and the ratio
B / A per measurement (above 1: B is slower).

    git worktree add /tmp/base a76b01c
    .venv/bin/python experiments/bench_ab.py /tmp/base . --rounds 4
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

CODE = {
    "env": """
import time, numpy as np
from ocplus_plan.env.gym_env import OvercookedPlusEnv
env = OvercookedPlusEnv("hard", n_agents=2, mode="vector")
acts = np.random.default_rng(0).integers(0, 5, size=(STEPS, 2)).tolist()
env.reset(seed=0)
t0 = time.process_time()
for a in acts:
    _, _, te, tr, _ = env.step(a)
    if te or tr:
        env.reset()
print((time.process_time() - t0) / STEPS * 1e6)
""",
    "transition": """
import time, numpy as np
from ocplus_plan.sim import make_rules, new_state, transition
rules = make_rules("hard", n_agents=2)
acts = np.random.default_rng(0).integers(0, 5, size=(STEPS, 2)).tolist()
s = new_state(rules, 0)
t0 = time.process_time()
for a in acts:
    r = transition(s, a)
    if r.terminated or r.truncated:
        s = new_state(rules, 0)
print((time.process_time() - t0) / STEPS * 1e6)
""",
    "numba": """
import time, numpy as np
from ocplus_plan.sim import make_rules
from ocplus_plan.sim.fast.batch import BatchSim
sim = BatchSim(make_rules("hard", n_agents=2), KITCHENS, seed=0, compiled=True, threads=1)
sim.reset()
rounds = max(1, STEPS // KITCHENS)
acts = np.random.default_rng(0).integers(0, 5, size=(rounds, KITCHENS, 2))
sim.step(acts[0])
t0 = time.process_time()
for a in acts:
    sim.step(a)
print((time.process_time() - t0) / (rounds * KITCHENS) * 1e6)
""",
}


def measure(tree: Path, what: str, steps: int, kitchens: int) -> float:
    code = CODE[what].replace("STEPS", str(steps)).replace("KITCHENS", str(kitchens))
    env = dict(os.environ, PYTHONPATH=str(tree.resolve()))
    out = subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, capture_output=True,
                         text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a", type=Path, help="tree A (before)")
    ap.add_argument("b", type=Path, help="tree B (after)")
    ap.add_argument("--rounds", type=int, default=4)
    ap.add_argument("--steps", type=int, default=20_000, help="env and transition steps")
    ap.add_argument("--batch-steps", type=int, default=400_000, help="kitchen-steps, numba")
    ap.add_argument("--kitchens", type=int, default=64)
    ap.add_argument("--only", nargs="+", default=list(CODE), choices=list(CODE))
    args = ap.parse_args()
    results: dict[tuple[str, str], list[float]] = {}
    for what in args.only:
        steps = args.batch_steps if what == "numba" else args.steps
        for tree in (args.a, args.b):  # warm-up: numba's cache, bytecode
            measure(tree, what, min(steps, 2000), args.kitchens)
        for r in range(args.rounds):
            for label, tree in (("A", args.a), ("B", args.b)):
                us = measure(tree, what, steps, args.kitchens)
                results.setdefault((what, label), []).append(us)
                print(json.dumps({"what": what, "tree": label, "round": r,
                                  "us_cpu_per_step": round(us, 3)}), flush=True)
    for what in args.only:
        a, b = (statistics.median(results[(what, x)]) for x in ("A", "B"))
        print(json.dumps({"what": what, "median_us_A": round(a, 3), "median_us_B": round(b, 3),
                          "ratio_B_over_A": round(b / a, 3), "rounds": args.rounds}), flush=True)


if __name__ == "__main__":
    main()

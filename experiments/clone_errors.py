"""On which decisions a behaviour clone of the greedy cook errs, and how often.

    .venv/bin/python experiments/clone_errors.py experiments/checkpoints/generalist_2agent/policy.npz \\
        --split test --kitchens-per-family 10 --cooks 2

The greedy cook drives every cook of kitchens 0..N-1 of each family (medium stations, one
episode each, seed 0); at every step the policy (a weights-only ``.npz``: what ``ocplus
train`` writes or rl/npz_export.py exports) is asked which action it would take (argmax).
Each cook-step is labelled with what greedy was doing (its subtask: ``fetch``, ``chop``,
``to_plate``, ..., or ``idle`` with no subtask, from ``GreedyAgent.goals``) and whether
greedy moved or stayed. The table gives, per label, the cook-steps, the clone's
disagreements and their share of all disagreements: where the clone lacks what greedy
decides on.
"""

from __future__ import annotations

import argparse
import collections
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ocplus_plan.agents.greedy import GreedyAgent  # noqa: E402
from ocplus_plan.agents.ppo import load_checkpoint  # noqa: E402
from ocplus_plan.eval.generalise import kitchen_name, rules_for  # noqa: E402
from ocplus_plan.rl.obs import make_encoder  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402
from ocplus_plan.sim.state import new_state  # noqa: E402
from ocplus_plan.sim.step import transition  # noqa: E402

_STAY = 4


def episode(policy, rules, seed: int, tally: dict) -> None:
    """One greedy-driven episode; adds (label, moved) -> [steps, disagreements] to tally."""
    meta = policy.meta
    enc = make_encoder(meta["obs"], rules, meta.get("obs_radius", 0))
    state = new_state(rules, seed)
    greedy = GreedyAgent(seed)
    greedy.reset(state)
    while not state.done:
        obs = enc.encode_all(state)
        view, goals = greedy.goals(state)  # what act() does, with the goals kept
        actions = greedy._moves(view, goals)
        predicted = policy.probs(obs).argmax(axis=1)
        for cook, (label, guess) in enumerate(zip(actions, predicted)):
            goal = goals.get(cook)
            key = (goal[1] if goal else "idle", "stay" if label == _STAY else "move")
            tally[key][0] += 1
            tally[key][1] += int(label != guess)
        result = transition(state, actions)
        greedy.observe(state, result.events)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("policy", help="a weights-only policy (.npz)")
    p.add_argument("--split", default="test", choices=("train", "test"))
    p.add_argument("--kitchens-per-family", type=int, default=10)
    p.add_argument("--cooks", type=int, default=2)
    p.add_argument("--preset", default="medium")
    args = p.parse_args()
    if not args.policy.endswith(".npz"):
        raise SystemExit(f"{args.policy!r}: give a weights-only .npz policy")
    policy = load_checkpoint(args.policy)
    families = [f for f in FAMILIES if not (f == "split" and args.cooks < 2)]
    tally: dict = collections.defaultdict(lambda: [0, 0])
    for family in families:
        for index in range(args.kitchens_per_family):
            name = kitchen_name(family, args.split, index, args.preset)
            episode(policy, rules_for(name, args.preset, args.cooks, 200), 0, tally)
    steps = sum(n for n, _ in tally.values())
    wrong = sum(e for _, e in tally.values())
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    print(f"policy {args.policy}, {args.split} kitchens 0-{args.kitchens_per_family - 1} of "
          f"{', '.join(families)}, {args.cooks} cooks, commit {commit}, "
          f"load {os.getloadavg()[0]:.2f}")
    print(f"agreement with greedy: {1 - wrong / steps:.3f} of {steps} cook-steps\n")
    print("| greedy's subtask | greedy's action | cook-steps | clone disagrees | "
          "share of disagreements |")
    print("|---|---|---|---|---|")
    for (label, moved), (n, e) in sorted(tally.items(), key=lambda kv: -kv[1][1]):
        print(f"| {label} | {moved} | {n} | {e / n:.2f} | {e / wrong:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

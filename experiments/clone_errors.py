"""On which decisions a behaviour clone of the greedy cook errs, how often, and why.

    .venv/bin/python experiments/clone_errors.py experiments/checkpoints/generalist_2agent/policy.npz \\
        --split test --kitchens-per-family 10 --cooks 2 --driver clone

Kitchens 0..N-1 of each family (medium stations, one episode each, seed 0). ``--driver
greedy``: the greedy cook drives every cook; ``--driver clone``: the policy drives (sampled
actions, as it plays), so the table covers the states the clone reaches itself. At every step
the greedy cook labels each cook (what it would do) and the policy (a weights-only ``.npz``)
is asked for its argmax. The first table gives, per greedy subtask (``fetch``, ``to_plate``,
..., ``idle``) and move/stay, the cook-steps, the disagreements and the share of those where
the clone would stay. The second sorts each
disagreement by what greedy's choice rests on, read from the same state:

* ``blocked wait``: greedy stays because its path is blocked by the other cook (it waits
  ``patience`` steps, then steps aside at random): a counter the observation lacks;
* ``idle``: greedy has no subtask (every task is taken or none is useful);
* ``goal seen, same step``: greedy's goal cell is the nearest cell of some feature target and
  the feature's first step is greedy's action: the clone had it and chose another target;
* ``goal seen, other step``: the goal is such a nearest cell, but the feature's shortest path
  starts another way (a tie, or the path around the other cook);
* ``goal hidden``: greedy heads for a cell that is no target's nearest (the nearest is the
  other cook's claim, a kept task, or a joint assignment); ``claimed`` counts those where
  the nearest cell of the goal's kind is the other cook's goal.
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
from ocplus_plan.rl.features import FeatureEncoder  # noqa: E402
from ocplus_plan.rl.obs import make_encoder  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402
from ocplus_plan.sim.state import new_state  # noqa: E402
from ocplus_plan.sim.step import transition  # noqa: E402

_STAY = 4


def _cause(feat: FeatureEncoder, state, greedy: GreedyAgent, cook: int, goals: dict,
           label: int) -> str:
    goal = goals.get(cook)
    if goal is None:
        return "idle"
    if label == _STAY and greedy.waited[cook] > 0:
        return "blocked wait"
    _cost, act, cells, _w = feat._nearest(state, cook)
    seen = [t for t, c in enumerate(cells) if c == goal[0]]
    if seen:
        return ("goal seen, same step" if any(act[t] == label for t in seen)
                else "goal seen, other step")
    others = {g[0] for b, g in goals.items() if b != cook}
    return "goal hidden, claimed" if others & set(cells) else "goal hidden"


def episode(policy, rules, seed: int, driver: str, tally: dict, causes: dict) -> int:
    """One episode; adds (subtask, move/stay) -> [steps, disagreements, clone stays] to ``tally`` and
    cause -> disagreements to ``causes``; returns the dishes served."""
    meta = policy.meta
    enc = make_encoder(meta["obs"], rules, meta.get("obs_radius", 0))
    feat = FeatureEncoder(rules)
    state = new_state(rules, seed)
    greedy = GreedyAgent(seed)
    greedy.reset(state)
    rng = np.random.default_rng(seed)
    while not state.done:
        obs = enc.encode_all(state)
        view, goals = greedy.goals(state)  # what act() does, with the goals kept
        labels = greedy._moves(view, goals)
        predicted = policy.probs(obs).argmax(axis=1)
        for cook, (label, guess) in enumerate(zip(labels, predicted)):
            goal = goals.get(cook)
            key = (goal[1] if goal else "idle", "stay" if label == _STAY else "move")
            tally[key][0] += 1
            if label != guess:
                tally[key][1] += 1
                tally[key][2] += int(guess == _STAY)
                causes[_cause(feat, state, greedy, cook, goals, label)] += 1
        played = labels if driver == "greedy" else policy.act(obs, rng)
        result = transition(state, played)
        greedy.observe(state, result.events)
    return int(state.stats["dishes_served"])


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("policy", help="a weights-only policy (.npz)")
    p.add_argument("--split", default="test", choices=("train", "test"))
    p.add_argument("--kitchens-per-family", type=int, default=10)
    p.add_argument("--cooks", type=int, default=2)
    p.add_argument("--preset", default="medium")
    p.add_argument("--driver", default="greedy", choices=("greedy", "clone"))
    args = p.parse_args()
    if not args.policy.endswith(".npz"):
        raise SystemExit(f"{args.policy!r}: give a weights-only .npz policy")
    policy = load_checkpoint(args.policy)
    families = [f for f in FAMILIES if not (f == "split" and args.cooks < 2)]
    tally: dict = collections.defaultdict(lambda: [0, 0, 0])
    causes: collections.Counter = collections.Counter()
    dishes = []
    for family in families:
        for index in range(args.kitchens_per_family):
            name = kitchen_name(family, args.split, index, args.preset)
            dishes.append(episode(policy, rules_for(name, args.preset, args.cooks, 200), 0,
                                  args.driver, tally, causes))
    steps = sum(n for n, _, _ in tally.values())
    wrong = sum(e for _, e, _ in tally.values())
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    print(f"policy {args.policy}, {args.split} kitchens 0-{args.kitchens_per_family - 1} of "
          f"{', '.join(families)}, {args.cooks} cooks, {args.driver} drives, commit {commit}, "
          f"load {os.getloadavg()[0]:.2f}; dishes per episode {np.mean(dishes):.2f}")
    print(f"agreement with greedy: {1 - wrong / steps:.3f} of {steps} cook-steps\n")
    print("| greedy's subtask | greedy's action | cook-steps | clone disagrees | "
          "share of disagreements | clone would stay |")
    print("|---|---|---|---|---|---|")
    for (label, moved), (n, e, st) in sorted(tally.items(), key=lambda kv: -kv[1][1])[:12]:
        print(f"| {label} | {moved} | {n} | {e / n:.2f} | {e / wrong:.2f} | "
              f"{st / max(e, 1):.2f} |")
    print("\n| why greedy chose its action | disagreements | share |\n|---|---|---|")
    for cause, n in causes.most_common():
        print(f"| {cause} | {n} | {n / wrong:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

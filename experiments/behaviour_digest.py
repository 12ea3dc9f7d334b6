"""Digests of what the simulator and its readers produce, to show a refactoring changes
no behaviour: run it on two commits and compare the lines.

Per preset and cook count, one seeded episode of ``--steps`` random joint actions; per
step the state hash, the vector observation (``VectorEncoder``, whole map), the text
observation of every cook, the RL features of every cook (``FeatureEncoder``) and, every
``--bound-every`` steps, the planning bound (``plan_bound``). Each is folded into one
SHA-256 per (preset, cooks, what); one JSON line per digest. Planner-free, about a minute
on one core.

Example::

    .venv/bin/python experiments/behaviour_digest.py --out experiments/results/refactor/behaviour-digest.jsonl
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ocplus_plan.eval.bounds import plan_bound
from ocplus_plan.rl.features import FeatureEncoder
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.observe import VectorEncoder
from ocplus_plan.sim.observe_text import text_observations
from ocplus_plan.sim.rules import PRESETS


def digests(preset: str, n_agents: int, steps: int, bound_every: int) -> dict[str, str]:
    rules = make_rules(preset, n_agents=n_agents)
    state = new_state(rules, 7)
    rng = np.random.default_rng([n_agents, steps])
    vec, feats = VectorEncoder(rules), FeatureEncoder(rules)
    h = {k: hashlib.sha256() for k in ("state", "vector", "text", "features", "plan_bound")}
    for t in range(steps):
        h["state"].update(state.state_hash().encode() if isinstance(state.state_hash(), str)
                          else repr(state.state_hash()).encode())
        h["vector"].update(vec.encode(state).tobytes())
        h["text"].update("\x00".join(text_observations(state)).encode())
        h["features"].update(feats.encode_all(state).tobytes())
        if t % bound_every == 0:
            h["plan_bound"].update(repr(plan_bound(state)).encode())
        transition(state, rng.integers(0, 5, size=n_agents).tolist())
    return {k: v.hexdigest() for k, v in h.items()}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--bound-every", type=int, default=25)
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=Path(__file__).parent).stdout.strip()
    lines = []
    for preset in PRESETS:
        for n in (1, 2, 3):
            try:
                found = digests(preset, n, args.steps, args.bound_every)
            except Exception as e:  # a preset that does not take n cooks
                found = {"error": type(e).__name__}
            for what, digest in found.items():
                lines.append({"preset": preset, "agents": n, "what": what, "sha256": digest,
                              "steps": args.steps, "commit": commit})
    for line in lines:
        print(json.dumps(line))
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with args.out.open("w") as f:
            f.writelines(json.dumps(line) + "\n" for line in lines)


if __name__ == "__main__":
    main()

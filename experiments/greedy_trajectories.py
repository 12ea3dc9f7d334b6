"""Greedy driving every cook, step by step: one digest of the joint actions and dishes per
episode, to show a change to the greedy cook leaves its moves alone (or which episodes it
changes). Run it on two commits and compare the lines.

Episodes: easy, medium and hard with 1 and 2 cooks, and the generated test kitchens 0-1 of
every family (medium stations, 2 cooks), seeds 0-4, 200 steps (the check in
docs/executive.md, "Greedy as a partner"). Planner-free, under a minute on one core.

    .venv/bin/python experiments/greedy_trajectories.py > /tmp/greedy-before.jsonl
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from experiments.bench_unseen import DYNAMIC  # noqa: E402
from ocplus_plan.agents import Episode, make_controller  # noqa: E402
from ocplus_plan.sim import make_rules, new_state  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402


def kitchens() -> list[tuple[str, str | None, int]]:
    """(preset, generated map or None, cooks) of every episode's kitchen."""
    out: list[tuple[str, str | None, int]] = [(p, None, n) for p in ("easy", "medium", "hard")
                                              for n in (1, 2)]
    out += [("medium", f"gen:{f}:test:{i}:medium", 2) for f in FAMILIES for i in range(2)]
    return out


def digest(preset: str, map_name: str | None, cooks: int, seed: int, steps: int) -> dict:
    extra = {} if map_name is None else {"map": map_name,
                                         "dynamic": map_name.split(":")[1] in DYNAMIC}
    state = new_state(make_rules(preset, n_agents=cooks, horizon=steps, **extra), seed)
    h = hashlib.sha256()

    def on_step(ep: object, res: object) -> None:
        h.update(repr((state.t, tuple(state.agent_pos), tuple(state.agent_hand))).encode())

    Episode(state, make_controller("greedy", seed)).run(on_step=on_step)
    return {"kitchen": map_name or preset, "cooks": cooks, "seed": seed,
            "dishes": state.stats["dishes_served"], "digest": h.hexdigest()[:16]}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--steps", type=int, default=200)
    args = p.parse_args(argv)
    for preset, map_name, cooks in kitchens():
        for seed in range(args.seeds):
            print(json.dumps(digest(preset, map_name, cooks, seed, args.steps)), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

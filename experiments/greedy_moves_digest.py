"""Digests of the greedy controller's moves when it drives every cook, to show that a change
to what greedy does beside cooks it does not drive leaves it unchanged step by step: run it
on two commits and compare the lines.

Per kitchen (easy, medium and hard with 1 and 2 cooks; the generated test kitchens 0-1 of
every family with 2 cooks) and seed: one 200-step episode with greedy driving every cook,
the SHA-256 of its joint actions step by step, and its dishes. Planner-free, seconds.

    .venv/bin/python experiments/greedy_moves_digest.py --seeds 5 > before.txt
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from experiments.bench_teamwork import gen_kitchens, kitchen_rules  # noqa: E402
from ocplus_plan.agents import Episode, make_controller  # noqa: E402
from ocplus_plan.sim import new_state  # noqa: E402


def digest(kitchen: str, cooks: int, seed: int, steps: int) -> tuple[str, int]:
    """(SHA-256 of the joint actions, dishes) of one greedy episode."""
    state = new_state(kitchen_rules(kitchen, cooks, steps), seed)
    ctl = make_controller("greedy", seed)
    h = hashlib.sha256()
    Episode(state, ctl).run(on_step=lambda ep, res: h.update(repr(ep.joint).encode()))
    return h.hexdigest()[:16], state.stats["dishes_served"]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--steps", type=int, default=200)
    args = p.parse_args(argv)
    kitchens = [(k, n) for k in ("easy", "medium", "hard") for n in (1, 2)]
    kitchens += [(k, 2) for k in gen_kitchens(None)]
    for kitchen, cooks in kitchens:
        for seed in range(args.seeds):
            d, dishes = digest(kitchen, cooks, seed, args.steps)
            print(kitchen, cooks, seed, d, dishes)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The generated test kitchens whose floor is one lane for the cooks at their spawn cells
(``execution.paths.cooks_in_one_lane``, the planning step's own test): where the executive
plans every cook with cells. Planner-free, seconds.

    .venv/bin/python experiments/one_lane_kitchens.py --per-family 20 --cooks 2
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from ocplus_plan.execution.paths import cooks_in_one_lane  # noqa: E402
from ocplus_plan.sim import make_rules, new_state  # noqa: E402
from ocplus_plan.sim.generate import FAMILIES  # noqa: E402


def lanes(per_family: int, cooks: int) -> list[str]:
    """The one-lane kitchens among test kitchens 0..per_family-1 of every family."""
    out = []
    for family in FAMILIES:
        for i in range(per_family):
            kitchen = f"gen:{family}:test:{i}"
            rules = make_rules("medium", map=kitchen, n_agents=cooks)
            state = new_state(rules, 0)
            if cooks_in_one_lane(state, range(cooks)):
                out.append(kitchen)
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--per-family", type=int, default=20)
    p.add_argument("--cooks", type=int, default=2)
    args = p.parse_args(argv)
    found = lanes(args.per_family, args.cooks)
    print("\n".join(found))
    print(f"{len(found)} of {args.per_family * len(FAMILIES)} kitchens", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

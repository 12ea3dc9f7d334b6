"""``ocplus demo``: the Quick start's main job on the embedded defaults.

Until the evaluation (``ocplus eval``) lands, the demo checks every shipped map and
runs one random-agent episode per preset.
"""

from __future__ import annotations

import argparse

from ..sim import available_maps


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("demo", help="the quick-start demo", description=__doc__)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..cli import main

    for name in sorted(available_maps()):
        main(["check-map", name])
        print()
    for preset in ("easy", "medium", "hard"):
        main(["rollout", "--preset", preset, "--agents", "random", "--seed", "0"])
        print()
    return 0

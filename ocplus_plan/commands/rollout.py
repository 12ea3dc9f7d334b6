"""``ocplus rollout``: run one episode of the simulator with given controllers."""

from __future__ import annotations

import argparse
import time

from ..sim import conservation_problems, new_state
from . import _types
from ._common import (
    add_trust_arg,
    HelpFormatter,
    add_deprecated_alias,
    add_kitchen_args,
    add_output_args,
    emit,
    rules_from_args,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("rollout", help="run one episode and print its statistics",
                       description=__doc__, formatter_class=HelpFormatter)
    add_kitchen_args(p)
    p.add_argument("--agents", type=_types.name, default="random",
                   help="controller for all agents (random, stay, greedy, planner:NAME, ...)")
    add_trust_arg(p)
    add_output_args(p)
    add_deprecated_alias(p, "--steps", "--horizon", takes_value=True, type=_types.horizon)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..agents import Episode, make_controller

    rules = rules_from_args(args)
    state = new_state(rules, args.seed)
    controller = make_controller(args.agents, args.seed)
    broken: list[str] = []

    def check(episode: Episode, _result: object) -> None:
        broken.extend(conservation_problems(episode.state))

    t0 = time.perf_counter()
    episode = Episode(state, controller).run(on_step=check)
    out = {
        "preset": rules.preset, "map": rules.layout.name, "n_agents": rules.n_agents,
        "agents": args.agents, "seed": args.seed, "steps": state.t,
        **state.stats,
        "reward": round(sum(episode.rewards), 6),
        "reward_per_agent": [round(r, 6) for r in episode.rewards],
        "items_conserved": not broken, "state_hash": state.state_hash(),
        "wall_time_s": round(time.perf_counter() - t0, 4),
        **{f"controller_{k}": v for k, v in controller.info().items()},
    }
    emit(out, args, width=18)
    return 0

"""One episode, step by step: where each cook is, what it holds, its next queued steps, the
replans, and when each dish is served (the trace behind docs/executive.md's account of
where the plan loses time on hard with two cooks).

    nice -n 10 .venv/bin/python experiments/trace_episode.py hard 2 0 planner:
    .venv/bin/python experiments/trace_episode.py hard 2 0 greedy
    .venv/bin/python experiments/trace_episode.py medium 2 0 planner: --partner greedy
    .venv/bin/python experiments/trace_episode.py medium 2 0 planner: --partner greedy \\
        --map gen:corridor:test:0:medium

One line per step (``t``, layout, dishes, each cook's cell and held item id, each driven
cook's next three steps ``kind@(row, col)``, a replan as ``REPLAN [(step, reason)]``), then
the dish times and the planner's counts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from experiments.bench_unseen import DYNAMIC  # noqa: E402
from ocplus_plan.agents import Episode, make_controller, with_partner  # noqa: E402
from ocplus_plan.agents.planner import make_planner_agent  # noqa: E402
from ocplus_plan.sim import make_rules, new_state  # noqa: E402
from ocplus_plan.sim.observe_text import kitchen_text  # noqa: E402

INFO = ("planner_calls", "statuses", "replans_by_reason", "replan_log", "stall_stretches",
        "stall_strategies", "planning_cpu_s", "partner_repairs", "claimed_plans")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("preset")
    p.add_argument("cooks", type=int)
    p.add_argument("seed", type=int)
    p.add_argument("agent", help="planner:SPEC or a registered agent (greedy, ...)")
    p.add_argument("--partner", default=None, help="plays the last cook")
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per planner call")
    p.add_argument("--map", default=None,
                   help="a generated kitchen (gen:FAMILY:SPLIT:INDEX:STATIONS) on PRESET's recipes")
    p.add_argument("--show", default="",
                   help="comma-separated steps after which the whole kitchen is printed "
                        "(items, their states, the orders), as the text interface gives it")
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    extra = {} if args.map is None else {"map": args.map,
                                         "dynamic": args.map.split(":")[1] in DYNAMIC}
    state = new_state(make_rules(args.preset, n_agents=args.cooks, horizon=args.steps, **extra),
                      args.seed)
    if args.agent.startswith("planner:"):
        ctl = make_planner_agent(args.agent.partition(":")[2], args.seed, timeout=args.timeout)
    else:
        ctl = make_controller(args.agent, args.seed)
    ex = getattr(ctl, "executive", None)
    rc, seen, served = state.geo.rc, [0], []
    show = {int(t) for t in args.show.split(",") if t}

    def on_step(ep: object, res: object) -> None:
        line = [f"t={state.t:3d} L{state.layout_index} d={state.stats['dishes_served']}"]
        if state.stats["dishes_served"] > len(served):
            served.append(state.t)
        line += [f"a{a}@{rc(state.agent_pos[a])} h={state.agent_hand[a]}"
                 for a in range(state.n_agents)]
        if ex is not None:
            line += [f"q{a}:" + ",".join(f"{x.step.kind}@{rc(x.step.target)}"
                                         for x in list(ex.queues[a])[:3]) for a in ex.agent_ids]
            if len(ex.replans) > seen[0]:
                line.append(f"REPLAN {ex.replans[seen[0]:]}")
                seen[0] = len(ex.replans)
        print(" ".join(line))
        if state.t in show:
            print(kitchen_text(state))

    Episode(state, with_partner(ctl, args.partner, args.cooks, args.seed)).run(on_step=on_step)
    print("dishes", state.stats["dishes_served"], "served at steps", served)
    if ex is not None:
        info = ctl.info()
        for k in INFO:
            print(k, info.get(k))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Aries on one instance's temporal problem with its one cook moved to other start cells.

Aries ran out of 30 CPU s on the state that ``suites/v1`` classical-1cook p01 holds (easy,
one order, the cook at s_2_2 with a plate in hand), which once opened the temporal track
too; this measures whether the state is hard or Aries' time is erratic: the same kitchen,
orders and items, with only the cook's start cell changed::

    .venv/bin/python experiments/aries_start_cells.py suites/v1/classical-1cook/p01 30
    .venv/bin/python experiments/aries_start_cells.py suites/v1/classical-1cook/p01 30 s_2_1 s_1_3

With no cells named it tries the cook's own cell and every cell next to a station. Each run
is ``planning/engines.solve`` with the registry's ``aries`` at a CPU-second limit of its
process group; one line per cell: status, CPU and wall seconds, makespan.
"""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str] | None = None) -> int:
    from ocplus_plan.eval.suite import load_instance
    from ocplus_plan.planning import compile
    from ocplus_plan.planning.engines import solve

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("instance", help="an instance folder of an exported set (one cook)")
    ap.add_argument("cpu", type=float, help="CPU seconds per run")
    ap.add_argument("cells", nargs="*", help="start cells (spot names such as s_2_1)")
    args = ap.parse_args(argv)
    inst = load_instance(args.instance)
    base = compile(inst.state, encoding="temporal", granularity=inst.manifest["granularity"],
                   max_orders=inst.manifest["max_orders"]).problem
    at, adj = base.fluent("agent_at"), base.fluent("adj")
    cooks = [o for o in base.all_objects if o.type.name == "agent"]
    if len(cooks) != 1:
        raise SystemExit(f"{args.instance}: {len(cooks)} cooks; this moves one cook")
    cook = cooks[0]
    spots = [o for o in base.all_objects if o.type.name == "spot"]
    init = base.explicit_initial_values
    start = next(s for s in spots if init.get(at(cook, s)) is not None
                 and init[at(cook, s)].bool_constant_value())
    cells = args.cells or [start.name] + sorted(
        {k.args[0].object().name for k, v in init.items()
         if k.fluent() == adj and v.bool_constant_value()} - {start.name})
    for name in cells:
        problem = base.clone()
        problem.set_initial_value(at(cook, start), False)
        problem.set_initial_value(at(cook, problem.object(name)), True)
        r = solve(problem, "aries", timeout=args.cpu)
        print(f"{args.instance} start {name}{' (its own)' if name == start.name else ''}: "
              f"{r.status} {r.cpu_time} CPU s, {r.planning_time:.1f} wall s, "
              f"makespan {r.makespan}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

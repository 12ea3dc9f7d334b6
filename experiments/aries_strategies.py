"""Aries on one instance of an exported set under one search strategy.

Aries runs several strategies at once (one thread each); ``ARIES_STRATEGIES`` picks one.
This runs ``aries`` from the planner registry with that variable added to its ``env``, at
a CPU-second limit of the planner's process group (``planning/engines.solve``), and prints
the status, CPU and wall seconds and the makespan of the instance's state in the temporal
encoding (any encoding's instance folder: classical-1cook p01 holds easy's sample 0, the
state Aries timed out on)::

    .venv/bin/python experiments/aries_strategies.py suites/v1/classical-1cook/p01 causal 30
    .venv/bin/python experiments/aries_strategies.py suites/v1/classical-1cook/p01 act-bool 30
    .venv/bin/python experiments/aries_strategies.py suites/v1/classical-1cook/p01 default 30
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from ocplus_plan.eval.suite import load_instance
from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import get_planner, solve


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("instance", help="an instance folder of an exported set")
    ap.add_argument("strategy", help="an ARIES_STRATEGIES value, or 'default' (all)")
    ap.add_argument("cpu", type=float, help="CPU seconds")
    args = ap.parse_args(argv)
    config = get_planner("aries")
    if args.strategy != "default":
        config = dataclasses.replace(config, env={**config.env,
                                                  "ARIES_STRATEGIES": args.strategy})
    instance = load_instance(args.instance)
    problem = compile(instance.state, encoding="temporal",
                      granularity=instance.manifest["granularity"],
                      max_orders=instance.manifest["max_orders"]).problem
    result = solve(problem, config, timeout=args.cpu)
    print(args.instance, args.strategy, result.status, result.cpu_time,
          round(result.planning_time, 1), result.makespan, result.reason[:100], flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

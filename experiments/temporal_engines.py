"""Which temporal engines handle the temporal encoding's cooking constructs?

Three problems (temporal encoding, stations granularity, first order only):

* ``no-steak``: the easy preset's initial state (no cooking at all: the baseline);
* ``envelope``: the medium preset's initial state; the steak must be cooked with the
  ``cook`` envelope (duration in [cook_time, burn_time - 1], required concurrency of
  the put at its start and the take-off at its end);
* ``til``: medium with a steak already on the pan for 2 ticks: it must be taken off
  inside a window opened and closed by timed initial literals (``take_off``), the
  envelope is needed for no other steak.

Each is solved by every registered temporal planner through ``planning.engines.solve``
(validated with UP's validator and VAL). Prints one JSON line per (problem, planner).

    python experiments/temporal_engines.py [--timeout 30]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile

from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import planner_names, solve
from ocplus_plan.sim import make_rules, new_state, transition


def problems() -> dict:
    easy = new_state(make_rules("easy"), 0)
    medium = new_state(make_rules("medium"), 0)
    cooking = new_state(make_rules("medium"), 0)
    for a in (2, 2, 1, 2, 4):  # pick the steak, step down, put it on the pan, wait
        transition(cooking, [a])
    return {"no-steak": easy, "envelope": medium, "til": cooking}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--timeout", type=float, default=30.0)
    parser.add_argument("--planners", nargs="*", default=None)
    args = parser.parse_args()
    os.chdir(tempfile.mkdtemp(prefix="ocplus-temporal-"))
    names = args.planners or planner_names("temporal")
    for label, state in problems().items():
        compiled = compile(state, encoding="temporal", max_orders=1)
        for planner in names:
            r = solve(compiled.problem, planner, timeout=args.timeout)
            print(json.dumps({
                "bench": "temporal_engines", "problem": label, "planner": planner,
                "status": r.status, "validated": r.validated, "makespan": r.makespan,
                "planning_time_s": r.planning_time, "plan_length": r.plan_length,
                "reason": r.reason[:160],
            }), flush=True)


if __name__ == "__main__":
    main()

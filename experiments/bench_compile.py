"""Compile time of ``planning.compile`` per preset, encoding and granularity.

Warm timings (after one compile has imported unified_planning and built the domain;
the first call of a process pays ~1-6 s for UP's environment, which imports its
engine factory). States: the initial state plus ``--states`` sampled reachable
states per preset; each is compiled ``--repeats`` times. Prints JSON lines.

    python experiments/bench_compile.py [--states 20] [--repeats 5]

Target: median under 5 ms for the stations granularity.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import time

from ocplus_plan.planning import ENCODINGS, compile
from ocplus_plan.planning.fidelity import sample_states
from ocplus_plan.sim import make_rules, new_state


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--states", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    t0 = time.perf_counter()
    compile(new_state(make_rules("easy"), 0))
    print(json.dumps({"bench": "compile_first_call", "seconds": round(time.perf_counter() - t0, 3)}))
    for preset in ("easy", "medium", "hard"):
        states = [new_state(make_rules(preset), 0)] + sample_states(preset, args.states, seed=1)
        for encoding in ENCODINGS:
            for granularity in ("stations", "cells"):
                compile(states[0], encoding=encoding, granularity=granularity)  # warm
                times = []
                for state in states:
                    for _ in range(args.repeats):
                        t = time.perf_counter()
                        c = compile(state, encoding=encoding, granularity=granularity)
                        times.append((time.perf_counter() - t) * 1000)
                times.sort()
                print(json.dumps({
                    "bench": "compile", "preset": preset, "encoding": encoding,
                    "granularity": granularity, "states": len(states), "runs": len(times),
                    "ms_median": round(statistics.median(times), 3),
                    "ms_p90": round(times[int(0.9 * (len(times) - 1))], 3),
                    "objects": len(c.problem.all_objects),
                    "facts": len(c.problem.explicit_initial_values),
                    "python": platform.python_version(),
                }), flush=True)


if __name__ == "__main__":
    main()

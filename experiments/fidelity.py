"""Fidelity of the planning model: does the simulator do what each plan step predicts?

Per preset: sample N reachable states (random rollouts of random length, seeded),
compile each one (classical, stations), solve it with ``fast-downward`` through
``planning.engines.solve`` (validated by UP's validator), replay the plan in the
simulator one action at a time and compare every predicted effect (item places
and states, agent cells, steps taken, served orders). Prints one JSON line per
configuration, plus one per mismatch with ``--verbose``.

    python experiments/fidelity.py [--states 200] [--presets easy medium hard hard-frozen]
    python experiments/fidelity.py --states 50 --presets corridor3-stations corridor3-cells \
        ring-stations ring-cells

``hard`` replays with the layout switching as the simulator does (the model holds
the current layout, so a switch during the replay can break a plan: reported as
category ``layout_switch``); ``hard-frozen`` replays the same kind of states with
switches off during the replay, which isolates model errors from switch effects.
``corridor3-*`` / ``ring-*``: two cooks on one-lane maps (easy recipes), where the
stations granularity's distances ignore the other cook (a replay then finds the
way blocked: category ``blocked``) and the cells granularity does not.
``hard*`` compile the first order only (``max_orders=1``): with one plate and dirty
plates, two orders take lama-first tens of seconds (see README, planning model).
``*-temporal`` compile the temporal encoding, solve it with Kairos (validated by UP and
VAL) and replay the plan time-triggered (``planning.fidelity_temporal``: each agent
acts at its planned steps, the model applies the happenings, the two are compared at
every action's end).

    python experiments/fidelity.py --presets easy-temporal medium-temporal \
        hard-frozen-temporal

``hard-anticipate`` / ``hard1-anticipate`` (2 cooks / 1 cook): the temporal encoding
with ``anticipate_switches=True`` (the coming switches as timed literals, stations
moves per layout), replayed with the layout switching live, as in ``hard``.

    python experiments/fidelity.py --states 50 --presets hard1-anticipate hard-anticipate
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import statistics
import tempfile
import time

from ocplus_plan.planning import compile
from ocplus_plan.planning.engines import solve
from ocplus_plan.planning.fidelity import replay, sample_states
from ocplus_plan.planning.fidelity_temporal import replay_temporal

#: config name -> (preset, max_orders, freeze_layout, granularity, rule overrides)
CONFIGS: dict[str, tuple] = {
    "easy": ("easy", None, False, "stations", {}),
    "medium": ("medium", None, False, "stations", {}),
    "hard": ("hard", 1, False, "stations", {}),
    "hard-frozen": ("hard", 1, True, "stations", {}),
    # narrow maps, two cooks: stations ignore the other cook when they price a walk
    "corridor3-stations": ("easy", None, False, "stations", {"map": "corridor3", "n_agents": 2}),
    "corridor3-cells": ("easy", None, False, "cells", {"map": "corridor3", "n_agents": 2}),
    "ring-stations": ("easy", None, False, "stations", {"map": "medium_ring", "n_agents": 2}),
    "ring-cells": ("easy", None, False, "cells", {"map": "medium_ring", "n_agents": 2}),
    # temporal encoding, solved by Kairos, validated (UP + VAL) and replayed time-triggered
    # (planning.fidelity_temporal: every agent acts at its planned steps, concurrently)
    "easy-temporal": ("easy", None, False, "stations", {}),
    "medium-temporal": ("medium", 1, False, "stations", {}),
    "hard-frozen-temporal": ("hard", 1, True, "stations", {}),
    # live switches, anticipated: the coming switches are timed literals of the problem
    # (stations moves per layout), so the plan must hold while the layout switches under it
    # (states of the first 40 steps: the switches are modelled up to the episode's end,
    # and a plan from a late state can outlast the 200-step episode)
    "hard-anticipate": ("hard", 1, False, "stations", {"max_steps": 40}),
    "hard1-anticipate": ("hard", 1, False, "stations", {"n_agents": 1, "max_steps": 40}),
}
TEMPORAL = {"easy-temporal": "kairos", "medium-temporal": "kairos",
            "hard-frozen-temporal": "kairos", "hard-anticipate": "kairos",
            "hard1-anticipate": "kairos"}
ANTICIPATE = {"hard-anticipate", "hard1-anticipate"}


def run(config: str, n: int, seed: int, timeout: float, verbose: bool) -> dict:
    preset, max_orders, freeze, granularity, overrides = CONFIGS[config]
    statuses: collections.Counter[str] = collections.Counter()
    categories: collections.Counter[str] = collections.Counter()
    compile_ms, solve_s, lengths = [], [], []
    replayed = faithful = validated = outlasted = 0
    overrides = dict(overrides)
    max_steps = overrides.pop("max_steps", 120)
    for index, state in enumerate(sample_states(preset, n, seed=seed, max_steps=max_steps,
                                                **overrides)):
        t0 = time.perf_counter()
        temporal = config in TEMPORAL
        compiled = compile(state, max_orders=max_orders, granularity=granularity,
                           encoding="temporal" if temporal else "classical",
                           anticipate_switches=config in ANTICIPATE)
        compile_ms.append((time.perf_counter() - t0) * 1000)
        planner = TEMPORAL.get(config, "fast-downward")
        result = solve(compiled.problem, planner, timeout=timeout, use_val=temporal)
        statuses[result.status] += 1
        if result.status != "solved":
            continue
        solve_s.append(result.planning_time)
        validated += bool(result.validated)
        lengths.append(result.plan_length)
        if temporal:  # anticipated switches are modelled up to the episode's end only
            rep = replay_temporal(compiled, result.plan, state, freeze_layout=freeze,
                                  until_horizon=config in ANTICIPATE)
        else:
            rep = replay(compiled, result.plan, state, freeze_layout=freeze)
        replayed += 1
        faithful += rep.ok
        outlasted += rep.outlasted
        if not rep.ok:
            categories[rep.category] += 1
            if verbose:
                print(json.dumps({"config": config, "state": index, "t": state.t,
                                  "category": rep.category, "mismatch": rep.mismatch}))
    return {
        "bench": "fidelity", "config": config, "preset": preset, "granularity": granularity,
        "overrides": overrides, "states": n, "seed": seed,
        "max_orders": max_orders, "freeze_layout": freeze, "statuses": dict(statuses),
        "validated": validated, "replayed": replayed, "faithful": faithful,
        "outlasting_the_episode": outlasted,
        "fidelity": round(faithful / replayed, 4) if replayed else None,
        "mismatch_categories": dict(categories),
        "compile_ms_median": round(statistics.median(compile_ms), 2),
        "solve_s_median": round(statistics.median(solve_s), 3) if solve_s else None,
        "plan_length_median": statistics.median(lengths) if lengths else None,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--states", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=30.0)
    parser.add_argument("--presets", nargs="+", default=["easy", "medium", "hard", "hard-frozen"],
                        choices=list(CONFIGS), help="configurations to run")
    parser.add_argument("--verbose", action="store_true", help="one line per mismatch")
    args = parser.parse_args()
    # Fast Downward writes output.sas into the working directory: a private one keeps
    # concurrent runs (other experiments, tests) from reading each other's task.
    os.chdir(tempfile.mkdtemp(prefix="ocplus-fidelity-"))
    for config in args.presets:
        print(json.dumps(run(config, args.states, args.seed, args.timeout, args.verbose)),
              flush=True)


if __name__ == "__main__":
    main()

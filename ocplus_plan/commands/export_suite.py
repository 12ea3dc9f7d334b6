"""``ocplus export-suite``: write an IPC-style instance set with reference plans.

For every preset x map x number of cooks, ``--states`` reachable states are sampled
(seeded random rollouts of up to ``--max-steps`` steps, the fidelity harness's sampler)
and each is written, per encoding, as a PDDL problem with its English version, its
reference plan (from a portfolio: lama-first, then BJOLP and weighted A*, each with
``--timeout`` CPU seconds, then any other registered planner when none solves it; the
best validated plan that the simulator replays faithfully),
the lower bound on plan quality and a manifest saying how the state was reached.
``--orders K`` above the preset's queue raises the queue (rule ``n_orders``): the state
holds K open orders drawn from the preset's recipes by the episode's seeded generator.
``--rules`` overrides rules (``dynamic=false`` puts hard's stations on a ``gen:``
kitchen). An instance no reference planner solves gets a goal-agenda witness (one order
at a time, ``--witness-timeout`` CPU s each; the concatenation validated) and is scored
``open``; one a complete search proves unsolvable goes to the ``-unsolvable`` track, one
with neither is dropped (the manifest's ``tracks`` say which).
Layout and formats: OUT/README.txt and ``ocplus_plan/eval/suite.py``. Same arguments,
same bytes (planning times are printed, never written into the set). Check a plan
against an instance with ``ocplus check-plan OUT/p01``.
"""

from __future__ import annotations

import argparse

from . import _types
from ._common import (
    HelpFormatter,
    add_compile_args,
    add_kitchen_args,
    add_output_args,
    check_limits,
    emit,
    parse_int_list,
    say,
    sweep_rules,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("export-suite", help="write an instance set (PDDL, English, reference "
                       "plans, bounds) for outside planners and language models",
                       description=__doc__, formatter_class=HelpFormatter)
    add_kitchen_args(p, sweep=True, grid=True, seeds=False, horizon=False, rules=True)
    p.add_argument("--states", type=_types.whole("--states", 1, 1000), default=1,
                   help="sampled states per preset, map and number of cooks")
    p.add_argument("--max-steps", type=_types.random_steps, default=120,
                   help="a sampled state is reached by 0..MAX_STEPS random joint actions")
    add_compile_args(p, many=True, switches=False, limits=60.0)
    p.add_argument("--planners", type=_types.name, default=None,
                   help="comma-separated reference planners, each used for the encoding it "
                        "is registered for (default: fast-downward,fast-downward-bjolp,"
                        "fast-downward-wastar for classical, kairos for temporal)")
    p.add_argument("--no-fallback", action="store_true",
                   help="when the reference planners solve nothing, leave the instance "
                        "without a reference instead of trying every registered planner")
    p.add_argument("--witness-timeout", type=_types.seconds, default=20.0,
                   help="CPU seconds per goal order of the goal-agenda witness, tried when "
                        "no reference planner solves an instance and none proves it "
                        "unsolvable (0: no witness; the instance is then dropped)")
    add_output_args(p, out=True, writes="the instance set (a new or empty folder)")
    p.set_defaults(func=run)


def _planners(text: str | None) -> dict[str, tuple[str, ...]] | None:
    if text is None:
        return None
    from ..eval.runner import parse_list
    from ..planning.engines import get_planner

    out: dict[str, list[str]] = {}
    for name in parse_list(text, "planners"):
        out.setdefault(get_planner(name).encoding, []).append(name)
    return {k: tuple(v) for k, v in out.items()}


def run(args: argparse.Namespace) -> int:
    from ..eval.runner import parse_list
    from ..eval.suite import SuiteSpec, export_suite

    check_limits(args)
    spec = SuiteSpec(
        presets=tuple(parse_list(args.presets, "presets")),
        maps=tuple(parse_list(args.map, "maps")) if args.map else (None,),
        cooks=tuple(parse_int_list(args.n_agents, "--cooks")) if args.n_agents else (None,),
        states=args.states, encodings=tuple(parse_list(args.encoding, "encoding")),
        seed=args.seed, granularity=args.granularity, orders=args.orders,
        max_steps=args.max_steps, timeout=args.timeout, wall_limit=args.wall_limit,
        fallback=not args.no_fallback, witness_timeout=args.witness_timeout,
        rules=tuple(sorted(sweep_rules(args).items())),
        **({"planners": p} if (p := _planners(args.planners)) is not None else {}))
    rows = export_suite(spec, args.out, progress=lambda m: say(args, m))
    if args.json:
        emit({"out": args.out, "instances": rows}, args)
    else:
        for r in rows:
            value = r["cost"] if r["encoding"] == "classical" else r["makespan"]
            bound = r["bound"]["cost" if r["encoding"] == "classical" else "makespan"]
            times = ", ".join(f"{t['planner']} {t['status']} {t['cpu_time'] or 0:.1f} CPU s "
                              f"({t['planning_time']:.1f} s)" for t in r["tried"])
            print(f"{r['instance']} {r['encoding']:9s} {r['status']:10s} reference {r['planner']} value {value} "
                  f"(bound {bound}, faithful {r['faithful']}, optimal {r['optimal']}); "
                  f"tried: {times}")
    return 0

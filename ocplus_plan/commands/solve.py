"""``ocplus solve``: compile a simulator state and solve it with one named planner.

The state is the preset's initial state, or the one reached after ``--random-steps T``
random joint actions. The planner runs in its own process group, stopped when the group
has used ``--timeout`` CPU seconds (as the IPC counts them), or at the wall-clock safety
``--wall-limit``; its plan is validated with unified-planning's validator and VAL. A
timeout, an unsolvable problem or a missing planner is reported as a status
(exit code 0); an unknown planner or preset is bad input (exit code 2). SIGTERM or Ctrl-C
ends the command and every planner process within a second or two (exit 143 or 130),
and nothing the planner started, in a session of its own or not, outlives the command.

Reported times: ``compile_time_s`` is the compilation of the state alone;
``import_time_s`` the one-off import and set-up of unified-planning before it;
``cpu_time`` and ``wall_time`` the planner call's CPU and wall seconds.
"""

from __future__ import annotations

import argparse
import time
from typing import Any

from ..errors import ConfigError
from ..sim import new_state, transition
from . import _types
from ._common import (
    HelpFormatter,
    add_compile_args,
    add_deprecated_alias,
    add_kitchen_args,
    add_output_args,
    check_limits,
    emit,
    rules_from_args,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("solve", help="compile a state and solve it with a named planner",
                       description=__doc__, formatter_class=HelpFormatter)
    add_kitchen_args(p, step=True)
    p.add_argument("--planner", type=_types.name, default="fast-downward",
                   help="registry name (see --list), e.g. fast-downward, kairos")
    add_compile_args(p, auto_encoding=True, limits=None)
    p.add_argument("--no-val", action="store_true", help="validate with UP only, not VAL")
    p.add_argument("--show-plan", dest="plan", action="store_true",
                   help="include the plan steps in the output")
    add_deprecated_alias(p, "--plan", "--show-plan", takes_value=False, dest="plan")
    p.add_argument("--list", action="store_true",
                   help="list the planners and whether each is available, then exit")
    add_output_args(p)
    p.set_defaults(func=run)


def state_after_random_steps(rules: Any, seed: int, steps: int) -> Any:
    """The state after ``steps`` uniformly random joint actions (seeded by ``seed``)."""
    import numpy as np

    if steps < 0:
        raise ConfigError(f"--step must be >= 0, got {steps}")
    state = new_state(rules, seed)
    rng = np.random.default_rng([seed, 7919])
    for _ in range(steps):
        if state.done:
            break
        result = transition(state, [int(a) for a in rng.integers(0, 5, size=rules.n_agents)])
        if result.terminated or result.truncated:
            break
    return state


def compile_from_args(args: argparse.Namespace, encoding: str) -> tuple[Any, dict[str, Any]]:
    """Compile the state the kitchen options and ``--step`` name: the compiled problem, and
    what ``pddl`` and ``solve`` both report about it."""
    rules = rules_from_args(args)
    state = state_after_random_steps(rules, args.seed, args.step)
    t0 = time.perf_counter()
    import_planning()
    t1 = time.perf_counter()
    from ..planning import compile

    compiled = compile(state, encoding=encoding, granularity=args.granularity,
                       max_orders=args.orders, anticipate_switches=args.anticipate_switches)
    return compiled, {
        "preset": rules.preset, "map": rules.layout.name, "n_agents": rules.n_agents,
        "seed": args.seed, "step": state.t, "encoding": encoding,
        "granularity": args.granularity, "compile_time_s": round(time.perf_counter() - t1, 5),
        "import_time_s": round(t1 - t0, 5),
    }


def import_planning() -> None:
    """Import unified-planning and set up its environment (its engine factory imports
    every installed planner package): seconds once per process, which are no part of
    compiling a state and so are kept out of ``compile_time_s``."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from unified_planning.shortcuts import get_environment

        from ..planning import compile  # noqa: F401 - the package's own imports

        get_environment().factory  # noqa: B018 - built on first use


def run(args: argparse.Namespace) -> int:
    from ..planning._proc import reaping, sigterm_exits

    # SIGTERM runs the cleanup that kills the engine's process groups (exit 143), and
    # what the planner abandoned in a session of its own is killed at the end
    with sigterm_exits(), reaping():
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    from ..planning.engines import availability, get_planner, planner_names, solve

    if args.list:
        rows = []
        for name in planner_names():
            cfg, avail = get_planner(name), availability(name)
            rows.append({"planner": name, "engine": cfg.engine, "encoding": cfg.encoding,
                         "timeout": cfg.timeout, "available": avail.ok, "reason": avail.reason})
        if args.json:
            emit(rows, args)
        else:
            for r in rows:
                mark = "yes" if r["available"] else f"no: {r['reason']}"
                print(f"{r['planner']:18s} {r['encoding']:9s} {r['engine']:18s} {mark}")
        return 0

    config = get_planner(args.planner)  # unknown name -> PlannerError (exit 2)
    encoding = config.encoding if args.encoding == "auto" else args.encoding
    check_limits(args)
    compiled, out = compile_from_args(args, encoding)
    result = solve(compiled.problem, config, timeout=args.timeout, use_val=not args.no_val,
                   wall_limit=args.wall_limit)
    info = result.to_dict()
    steps = info.pop("steps")
    info.pop("pgid")
    out.update(info)
    if args.plan:
        out["plan"] = steps
    if args.json:
        emit(out, args)
    else:
        for key, value in out.items():
            if key == "plan":
                print("plan:")
                for s in value:
                    when = f"{s['start']:8.3f} " if "start" in s else "  "
                    dur = f" [{s['duration']:g}]" if s.get("duration") is not None else ""
                    print(f"  {when}{s['action']}({', '.join(map(str, s['args']))}){dur}")
            else:
                print(f"{key:18s} {value}")
    return 0

"""``ocplus check-plan``: check a plan made anywhere, against validators and the simulator.

Give an instance folder of a set written by ``ocplus export-suite`` (``OUT/p01``; the
plan defaults to its reference plan, ``--plan FILE`` checks yours), or ``--domain``,
``--problem`` and ``--plan`` files. The plan is an IPC plan file: sequential
(``(pick a0 tomato0 ...)`` or ``3: (pick ...)``) or time-stamped
(``0.000: (move a0 s_1_1 s_1_2) [1.000]``). It is parsed (never evaluated; a bad line is
reported with its number), validated with unified-planning's validator and VAL, and, for
an instance, replayed in the simulator from the instance's state; the first divergence
is printed in kitchen words. A plan that diverges is then judged as ``ocplus league``
judges it: its steps realised with collision-free routing, waits allowed; if the kitchen
still reaches the goal the plan is valid (``realised`` says how).

Exit codes: 0 valid (and, for an instance, faithful: the simulator did what the plan
says, or reaches the goal with waits); 4 invalid (unreadable, or rejected by a
validator); 5 unfaithful (valid, but the kitchen cannot carry it out to its goal); 2 bad
input: no such instance, an edited problem, or a plan, domain or problem path that is not
a readable regular file (missing, a directory, a device such as /dev/zero, unreadable), a
plan file over 4 MB or of more than 20,000 actions, a domain or problem file over 1 MB, or
a check that needs more than --cpu-limit CPU seconds (60 by default). A plan with a UTF-8
byte-order mark or CRLF line ends reads as the same plan without them.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from . import _types
from ._common import HelpFormatter, add_output_args, emit


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("check-plan", help="check a plan file: parse, validate (VAL and "
                       "unified-planning), replay in the simulator",
                       description=__doc__, formatter_class=HelpFormatter)
    p.add_argument("instance", nargs="?", default=None,
                   help="an instance folder (OUT/pNN) of an exported set")
    p.add_argument("--plan", default=None,
                   help="the plan file (default for an instance: its reference plan)")
    p.add_argument("--encoding", default=None,
                   help="which of the instance's encodings (default: the first, "
                        "alphabetically: classical)")
    p.add_argument("--domain", default=None, help="a PDDL domain file (without an instance)")
    p.add_argument("--problem", default=None, help="a PDDL problem file (without an instance)")
    p.add_argument("--no-val", action="store_true", help="validate with unified-planning only")
    p.add_argument("--cpu-limit", type=_types.seconds, default=None, metavar="SECONDS",
                   help="CPU seconds the check may use (default 60); past them it stops "
                        "with exit 2")
    add_output_args(p)
    p.set_defaults(func=run)


def _check_paths(args: argparse.Namespace) -> None:
    """Bad input (exit 2), before any reading: a path that is not a readable regular file,
    or a plan file over the size limit."""
    from ..errors import ConfigError
    from ..planning.plan_io import MAX_PLAN_BYTES, plan_file_problem

    from ..eval.check import MAX_PDDL_BYTES

    problem = None if args.plan is None else plan_file_problem(args.plan, MAX_PLAN_BYTES)
    for path in (args.domain, args.problem):
        if problem is None and path is not None:
            problem = plan_file_problem(path, None)
            if problem is None and Path(path).stat().st_size > MAX_PDDL_BYTES:
                problem = (f"{path}: {Path(path).stat().st_size} bytes; a PDDL domain or "
                           f"problem file has at most {MAX_PDDL_BYTES} here")
    if problem is not None:
        raise ConfigError(problem)


def run(args: argparse.Namespace) -> int:
    from ..eval.check import DEFAULT_CPU_LIMIT, cpu_budget

    _check_paths(args)
    with cpu_budget(args.cpu_limit or DEFAULT_CPU_LIMIT):
        result = _check(args)
    out = result.to_dict()
    if args.json:
        emit(out, args)
    else:
        emit({k: v for k, v in out.items() if v not in (None, "", [])}, args, width=15)
    return result.exit_code


def _check(args: argparse.Namespace) -> Any:
    from ..errors import ConfigError
    from ..eval.check import check_files, check_instance_plan

    if args.instance is not None:
        if args.domain or args.problem:
            raise ConfigError("give an instance folder or --domain/--problem files, not both")
        result = check_instance_plan(args.instance, args.encoding, args.plan,
                                     use_val=not args.no_val)
    else:
        if not (args.domain and args.problem and args.plan):
            raise ConfigError("give an instance folder (OUT/pNN), or all of --domain, "
                              "--problem and --plan")
        result = check_files(args.domain, args.problem, args.plan, use_val=not args.no_val)
    return result

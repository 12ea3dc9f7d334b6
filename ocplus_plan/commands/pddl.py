"""``ocplus pddl``: write the PDDL domain and problem of a simulator state.

The state is the preset's initial state, or the one reached after ``--random-steps T``
random joint actions (the same state ``ocplus solve`` compiles for the same
``--seed`` and ``--random-steps``). Writes ``DIR/domain.pddl`` and ``DIR/problem.pddl``
and prints what it wrote.
"""

from __future__ import annotations

import argparse

from ._common import HelpFormatter, add_compile_args, add_kitchen_args, add_output_args, emit


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("pddl", help="write domain.pddl and problem.pddl for a state",
                       description=__doc__, formatter_class=HelpFormatter)
    add_kitchen_args(p, step=True)
    add_compile_args(p)
    add_output_args(p, out=True, writes="domain.pddl and problem.pddl (created if missing)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..planning.pddl import write_pddl
    from .solve import compile_from_args

    compiled, out = compile_from_args(args, args.encoding)
    domain, problem = write_pddl(compiled, args.out)
    out.update(orders=list(compiled.goal_orders), objects=len(compiled.problem.all_objects),
               domain=str(domain), problem=str(problem))
    emit(out, args)
    return 0

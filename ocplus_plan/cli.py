"""The ``ocplus`` command. Each subcommand lives in ``ocplus_plan/commands/<name>.py``
and exposes ``register(subparsers)`` (adds its parser, sets ``func``); this module
only dispatches, maps errors to exit codes and keeps heavy imports lazy.

Exit codes, grouped by meaning (as Fast Downward's driver does):
  0   success (also when the reader of the output goes away: `ocplus ... | head`)
  1   unexpected internal error (a bug: please report it with the traceback)
  2   bad input: unknown preset / map / planner / agent, malformed map, a bad option or
      value (one line on stderr says what is wrong and what is allowed)
  3   an optional dependency is missing (the message names the extra to install)
  4   check-plan: the plan is invalid (a line cannot be read, or VAL / unified-planning
      reject it)
  5   check-plan: the plan is valid but unfaithful (the simulator diverges from it)
  130 interrupted (Ctrl-C); results written so far are kept
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

from .errors import DependencyNotInstalled, OcplusError

#: subcommand name -> module in ocplus_plan.commands (imported only when listed in help
#: or run, so `ocplus check-map` never loads unified_planning or torch).
COMMANDS: dict[str, str] = {
    "check-map": "check_map",
    "rollout": "rollout",
    "demo": "demo",
    "train": "train",
    "eval": "eval",
    "report": "report",
    "play": "play",
    "replay": "replay",
    "solve": "solve",
    "pddl": "pddl",
    "export-suite": "export_suite",
    "check-plan": "check_plan",
    "league": "league",
    "generate": "generate",
}

#: Printed by --help and replayed by tests/test_cli.py (each must exit 0, quickly) in a
#: fresh directory with the checkout's ``maps/``: outputs go to relative paths (``runs/``).
EXAMPLES: list[str] = [
    "ocplus check-map mapC",
    "ocplus check-map maps/hard_switch.yaml",
    "ocplus check-map mapC --json",
    "ocplus check-map gen:split:test:0",
    "ocplus generate --family corridor --split test --n 2 --no-prove --out runs/kitchens",
    "ocplus rollout --preset hard --n-agents 2 --horizon 200 --seed 0 --json",
    "ocplus solve --list",
    "ocplus pddl --preset medium --seed 0 --random-steps 20 --encoding temporal --out runs/pddl",
    "ocplus pddl --preset hard --seed 0 --encoding temporal --anticipate-switches --out runs/pddl-switches",
    "ocplus export-suite --presets easy --states 1 --encoding classical "
    "--planners fast-downward-wastar --timeout 20 --out runs/suite",
    "ocplus check-plan runs/suite/p01",
    "ocplus eval --preset easy --agents greedy,random --seeds 2 --horizon 50 --quiet "
    "--out runs/eval-example --resume",
]

EXIT_OK, EXIT_BUG, EXIT_INPUT, EXIT_DEPENDENCY, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


def build_parser() -> argparse.ArgumentParser:
    from .commands._common import Parser

    parser = Parser(
        prog="ocplus",
        description="ocplus-plan: planning and learning in an Overcooked-style kitchen.",
        epilog="examples:\n" + "".join(f"  {e}\n" for e in EXAMPLES)
        + "\nexit codes" + (__doc__ or "").split("Exit codes", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in COMMANDS.values():
        importlib.import_module(f"ocplus_plan.commands.{module}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run one ``ocplus`` command line and return its exit code (it never raises
    SystemExit: ``--help`` returns 0, a bad option 2)."""
    try:
        code = _run(argv)
        sys.stdout.flush()  # here, not at exit, so that a closed pipe is caught below
        return code
    except BrokenPipeError:  # the reader went away (`ocplus ... | head`): nothing to say
        _silence_stdout()
        return EXIT_OK


def _run(argv: Sequence[str] | None) -> int:
    from .commands._common import finish_args

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help (0) or a bad option, already said in one line (2)
        return exc.code if isinstance(exc.code, int) else EXIT_INPUT
    if not getattr(args, "func", None):
        parser.print_help()
        return EXIT_INPUT
    try:
        finish_args(args)
        return int(args.func(args) or 0)
    except DependencyNotInstalled as exc:
        print(f"ocplus: {exc}", file=sys.stderr)
        return EXIT_DEPENDENCY
    except OcplusError as exc:
        print(f"ocplus: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("ocplus: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's last flush of a closed pipe
    prints no second error."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # stdout is no file (a test's capture)
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

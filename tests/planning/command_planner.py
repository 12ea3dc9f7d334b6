"""A planner binary for the tests of ``command:`` planners (tests/planning/test_command.py).

Usage: ``command_planner.py MODE DOMAIN PROBLEM PLAN [ARG]``. It reads the PDDL files as any
outside planner would; MODE says what it does next:

* ``solve``: parses them with unified-planning and solves them with Fast Downward (classical)
  or Kairos (temporal) in-process, then writes the plan in IPC format;
* ``copy``: writes the text of file ARG as its plan (a fixed plan, valid or not);
* ``numbered``: writes garbage to ``PLAN.1`` and the text of ARG to ``PLAN.2``, as an
  anytime planner writes improving plans (only the last is read);
* ``sleep``: starts a child ``sleep 60`` and sleeps (for the wall safety and the group kill);
* ``spin``: computes forever (for the CPU limit);
* ``setsid``: starts ``sleep ARG`` in a session of its own (``setsid``), which it abandons,
  and exits without a plan (nothing it starts may outlive the solve);
* ``argv``: writes its own arguments, one per line, to ARG (how the command reached it),
  then the value of the environment variable ``TOY_PLANNER_ENV``;
* ``none``: exits with code ARG (default 0) without a plan.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path


def main() -> int:
    mode, domain, problem, plan = sys.argv[1:5]
    extra = sys.argv[5] if len(sys.argv) > 5 else ""
    if "(:goal" not in Path(problem).read_text(encoding="utf-8"):
        return 9
    Path(domain).read_text(encoding="utf-8")
    if mode == "copy":
        Path(plan).write_text(Path(extra).read_text(encoding="utf-8"), encoding="utf-8")
    elif mode == "numbered":
        text = Path(extra).read_text(encoding="utf-8")
        Path(plan + ".1").write_text("(garbage\n", encoding="utf-8")
        Path(plan + ".2").write_text(text, encoding="utf-8")
    elif mode == "sleep":
        subprocess.Popen(["sleep", "60"])
        time.sleep(60)
    elif mode == "setsid":
        subprocess.Popen(["setsid", "sleep", extra or "60"], start_new_session=True)
    elif mode == "spin":
        while True:
            pass
    elif mode == "argv":
        lines = [*sys.argv[1:], os.environ.get("TOY_PLANNER_ENV", "")]
        Path(extra).write_text("\n".join(lines), encoding="utf-8")
    elif mode == "none":
        return int(extra or 0)
    elif mode == "solve":
        return solve(domain, problem, plan)
    return 0


def solve(domain: str, problem: str, plan: str) -> int:
    from unified_planning.io import PDDLReader, PDDLWriter
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    get_environment().credits_stream = None
    parsed = PDDLReader().parse_problem(domain, problem)
    temporal = any(type(a).__name__ == "DurativeAction" for a in parsed.actions)
    if temporal:
        import up_kairos

        up_kairos.register()
    name = "kairos" if temporal else "fast-downward"
    with OneshotPlanner(name=name, params={"anytime": False} if temporal else None) as engine:
        result = engine.solve(parsed, timeout=300)
    if result.plan is None:
        return 1
    Path(plan).write_text(PDDLWriter(parsed).get_plan(result.plan), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())

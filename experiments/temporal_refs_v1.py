"""Offline anytime search for the temporal references of ``suites/v1``, frozen as files.

    nice -n 10 .venv/bin/python experiments/temporal_refs_v1.py --budget 300
    nice -n 10 .venv/bin/python experiments/temporal_refs_v1.py --adopt-build

kairos-anytime improves its plan until a budget of wall seconds runs out, so what it
finds depends on the machine's load; this command runs it apart from the build, and
writes what it finds to ``experiments/suite_v1_temporal_refs/`` (``pNN.plan`` and
``refs.json``: planner, engine, budget, makespan, the problem's SHA-256, commit, machine
and load). A plan replaces the one there only when it validates (UP and VAL) with a
shorter makespan, so rerunning never makes a reference worse. ``experiments/
build_suite_v1.py`` reads these files, validates and replays them, and keeps the best
faithful plan among them and its own (deterministic) planners' (``eval/suite_offline``).

``--adopt-build`` takes, instead of searching, the kairos-anytime plans of the set's
current references (found by the build's portfolio with its budget, recorded as such).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

from ocplus_plan.eval.suite import load_instance
from ocplus_plan.eval.suite_offline import FORMAT, problem_digest, read_refs

OUT = "experiments/suite_v1_temporal_refs"
PLANNER = "kairos-anytime"
#: the budget of the build's portfolio the adopted plans were found with (wall seconds)
BUILD_BUDGET = 10.0


def _commit() -> str:
    return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=False).stdout.strip()


def _search(inst, budget: float) -> tuple[object, float | None, str]:
    """(plan or None, makespan, what happened) of one kairos-anytime run."""
    from ocplus_plan.planning.engines import solve

    compiled = inst.compiled("temporal")
    result = solve(compiled.problem, PLANNER, timeout=budget)
    if not (result.solved and result.validated is True):
        return None, None, f"{result.status} {result.reason[:80]}"
    return result.plan, result.makespan, f"solved, {result.cpu_time} CPU s"


def _adopted(inst) -> tuple[object, float | None, str]:
    """The build's kairos-anytime reference plan of an instance, if it has one."""
    from ocplus_plan.planning.plan_io import read_plan

    ref = inst.manifest["encodings"]["temporal"]["reference"]
    if ref.get("planner") != PLANNER:
        return None, None, f"the build's reference is {ref.get('planner')}'s"
    plan = read_plan(inst.folder / "temporal.plan", inst.compiled("temporal").problem)
    return plan, ref["makespan"], "adopted from the build"


def main(argv: list[str] | None = None) -> int:
    from ocplus_plan.planning.plan_io import format_plan
    from ocplus_plan.planning.pddl import pddl_texts
    from ocplus_plan.planning.validate import plan_quality, validate_plan

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--suite", default="suites/v1/temporal")
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--budget", type=float, default=300.0,
                    help="kairos-anytime's improvement budget per instance (wall seconds)")
    ap.add_argument("--instances", default=None, help="comma-separated, e.g. p01,p05")
    ap.add_argument("--adopt-build", action="store_true",
                    help="take the set's kairos-anytime references instead of searching")
    args = ap.parse_args(argv)
    suite, out = Path(args.suite), Path(args.out)
    names = json.loads((suite / "manifest.json").read_text(encoding="utf-8"))["instances"]
    if args.instances:
        names = [n for n in names if n in args.instances.split(",")]
    refs = read_refs(out)
    out.mkdir(parents=True, exist_ok=True)
    for name in names:
        inst = load_instance(suite / name)
        compiled = inst.compiled("temporal")
        plan, makespan, note = _adopted(inst) if args.adopt_build else _search(inst, args.budget)
        old = refs["instances"].get(name)
        if plan is not None:
            check = validate_plan(compiled.problem, plan)
            makespan = plan_quality(compiled.problem, plan).makespan
            if check.ok is not True:
                plan, note = None, f"not valid: {check.detail[:80]}"
        if plan is not None and (old is None or makespan < old["makespan"] - 1e-9):
            budget = BUILD_BUDGET if args.adopt_build else args.budget
            (out / f"{name}.plan").write_text(format_plan(
                plan, f"{name} of {suite}: {PLANNER}, budget {budget:g} wall s"),
                encoding="utf-8")
            refs["instances"][name] = {
                "planner": PLANNER, "engine": "kairos", "plan": f"{name}.plan",
                "makespan": makespan, "budget_wall_s": budget,
                "problem_sha256": problem_digest(pddl_texts(compiled.problem)[1]),
                "found_by": "the v1 build's portfolio" if args.adopt_build else
                "experiments/temporal_refs_v1.py", "commit": _commit(),
                "machine": f"{platform.machine()}, {os.cpu_count()} shared cores",
                "load": round(os.getloadavg()[0], 2)}
            note += f", makespan {makespan} kept"
        elif plan is not None:
            note += f", makespan {makespan} not better than {old['makespan']}"
        print(f"{name}: {note}", flush=True)
    refs["format"] = FORMAT
    (out / "refs.json").write_text(json.dumps(refs, indent=1, sort_keys=True) + "\n",
                                   encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())

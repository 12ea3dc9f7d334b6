"""Planner binaries: a planner YAML with ``command:`` instead of a unified-planning engine.

The command is an argument list (a YAML list, or one string split like a shell would
split it, with :func:`shlex.split`, but never run by a shell) whose arguments may hold
these placeholders, replaced as whole values, never interpreted:

``{domain}`` ``{problem}``
    the PDDL files written for the problem (required);
``{plan}``
    where the planner must write its plan in IPC format (required); a planner that
    writes improving plans as ``plan.1``, ``plan.2``... (Fast Downward's anytime
    style) is read from the highest-numbered one;
``{timeout}``
    the CPU limit in whole seconds, for planners that take one;
``{config_dir}``
    the folder of the YAML file (for scripts and data kept next to it).

A relative program path (``./my_planner.sh``, ``bin/plan``) is taken relative to the
YAML file's folder; a bare name (``optic``) is looked up on ``PATH``. The planner runs
in a private working directory, as a grandchild of :func:`._proc.run_isolated`, in the
same process group as every UP engine, so the same CPU limit (the group's CPU seconds),
wall-clock safety and group kill apply to it and to whatever it starts. Its plan file
is read with :mod:`.plan_io` (parsed, never evaluated; size-limited).
"""

from __future__ import annotations

import os
import re
import resource
import shlex
import shutil
import subprocess
from pathlib import Path
from typing import Any

from ..errors import PlannerError, UnreadableText
from . import _proc

PLACEHOLDERS = ("domain", "problem", "plan", "timeout", "config_dir")
REQUIRED = ("domain", "problem", "plan")
_FIELD = re.compile(r"\{([^{}]*)\}")
#: wall seconds the isolated child gets past the command's own wall limit to report
_GRACE = 2.0


def parse_command(value: Any, source: str) -> tuple[str, ...]:
    """The argument list of a ``command:`` value, checked; ``{config_dir}`` filled in."""
    if isinstance(value, str):
        try:
            args = shlex.split(value)
        except ValueError as exc:
            raise PlannerError(f"{source}: command {value!r} cannot be split into arguments "
                               f"({exc}); give it as a YAML list") from None
    elif isinstance(value, list) and all(isinstance(a, (str, int, float)) for a in value):
        args = [str(a) for a in value]
    else:
        raise PlannerError(f"{source}: 'command' must be a list of arguments (or one string), "
                           f"got {value!r}")
    if not args:
        raise PlannerError(f"{source}: 'command' is empty; give the planner's program and "
                           "its arguments")
    used = {f for a in args for f in _FIELD.findall(a)}
    unknown = sorted(used - set(PLACEHOLDERS))
    if unknown:
        raise PlannerError(f"{source}: unknown placeholder(s) {unknown} in 'command'; known: "
                           + ", ".join("{" + p + "}" for p in PLACEHOLDERS))
    missing = [p for p in REQUIRED if p not in used]
    if missing:
        raise PlannerError(f"{source}: 'command' must pass the planner "
                           + ", ".join("{" + p + "}" for p in missing)
                           + " (the PDDL files it reads and the plan file it writes)")
    here = str(Path(source).resolve().parent) if source.endswith((".yaml", ".yml")) else None
    if here is not None:
        args = [a.replace("{config_dir}", here) for a in args]
        if "/" in args[0] and not os.path.isabs(args[0]):
            args[0] = str(Path(here) / args[0])
    elif "{config_dir}" in " ".join(args):
        raise PlannerError(f"{source}: '{{config_dir}}' needs a config read from a YAML file")
    return tuple(args)


def program_problem(command: tuple[str, ...]) -> str:
    """Why the command's program cannot run here ('' when it can)."""
    program = command[0]
    if "/" in program:
        if not os.path.isfile(program):
            return f"the planner program {program} does not exist"
        if not os.access(program, os.X_OK):
            return f"the planner program {program} is not executable (chmod +x it)"
        return ""
    if shutil.which(program) is None:
        return f"the planner program {program!r} is not on PATH"
    return ""


def render(command: tuple[str, ...], values: dict[str, str]) -> list[str]:
    """The argument list with each placeholder replaced by its value, as text."""
    return [_FIELD.sub(lambda m: values[m.group(1)], a) for a in command]


#: what planners print when they run out of memory (Python, C++, Java, Fast Downward, libc)
_MEMORY_WORDS = ("MemoryError", "std::bad_alloc", "OutOfMemoryError", "out of memory",
                 "Cannot allocate memory", "memory limit", "insufficient memory",
                 "Not enough space")


def out_of_memory(text: str) -> bool:
    """Whether a planner's message or output says it ran out of memory."""
    return any(word.lower() in text.lower() for word in _MEMORY_WORDS)


def limit_memory(megabytes: float | None) -> None:
    """Cap this process's address space (and that of what it starts) at ``megabytes`` MiB."""
    if megabytes:
        size = int(megabytes * 1024 * 1024)
        resource.setrlimit(resource.RLIMIT_AS, (size, size))


def _run_in_child(argv: list[str], workdir: str, wall: float,
                  env: dict[str, str], memory: float | None = None) -> dict[str, Any]:
    """In the isolated child: run the planner (same process group), report how it ended.
    ``wall`` is the wall-clock safety; the CPU limit is watched by the parent."""
    limit_memory(memory)
    try:
        run = subprocess.run(argv, cwd=workdir, stdin=subprocess.DEVNULL, timeout=wall,
                             check=False, shell=False, env={**os.environ, **env})
        code: int | None = run.returncode
    except subprocess.TimeoutExpired:
        code = None
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"returncode": code, "cpu_time": round(usage.ru_utime + usage.ru_stime, 4)}


def plan_file(path: Path) -> Path | None:
    """``path`` if the planner wrote it, else its highest-numbered ``path.N``, else None."""
    if path.is_file():
        return path
    numbered = [(int(p.name.rsplit(".", 1)[1]), p) for p in path.parent.glob(path.name + ".*")
                if p.name.rsplit(".", 1)[1].isdigit()]
    return max(numbered)[1] if numbered else None


def run_command(problem: Any, command: tuple[str, ...], limit: float, workdir: str,
                wall: float, env: dict[str, str] | None = None,
                memory: float | None = None) -> _proc.Outcome:
    """Write the problem's PDDL into ``workdir``, run the planner command on it in an
    isolated process group (with ``env`` added to its environment) and read its plan.
    The group is stopped when it has used ``limit`` CPU seconds, or after ``wall`` seconds
    of wall time (a safety).

    Returns an :class:`._proc.Outcome` whose value (when ``ok``) is the same report the
    UP engines give (``up_status``, ``steps``, ``temporal``, ``log``, ``cpu_time``, and
    ``status``/``reason`` for a plan file that cannot be read)."""
    from .pddl import pddl_texts
    from .plan_io import is_temporal, read_plan
    from .validate import plan_to_steps

    domain_text, problem_text = pddl_texts(problem)
    work = Path(workdir)
    (work / "domain.pddl").write_text(domain_text, encoding="utf-8")
    (work / "problem.pddl").write_text(problem_text, encoding="utf-8")
    values = {"domain": str(work / "domain.pddl"), "problem": str(work / "problem.pddl"),
              "plan": str(work / "plan"), "timeout": str(max(1, int(limit)))}
    argv = render(command, values)
    outcome = _proc.run_isolated(_run_in_child, (argv, workdir, wall, dict(env or {}), memory),
                                 hard_limit=wall + _GRACE, cpu_limit=limit)
    if outcome.kind != _proc.OK:
        return outcome
    code = outcome.value["returncode"]
    report: dict[str, Any] = {"notes": [], "steps": None, "log": outcome.log_tail[-2000:],
                              "temporal": is_temporal(problem), "up_status": "INTERNAL_ERROR",
                              "cpu_time": outcome.value["cpu_time"]}
    outcome.value = report
    if code is None:
        report["up_status"] = "TIMEOUT"
        report["limit_hit"] = "wall"
        report["reason"] = (f"the planner command did not finish within the wall-clock "
                            f"safety limit of {wall:g} s")
        return outcome
    found = plan_file(work / "plan")
    if found is None:
        # exit 0 without a plan: the planner's claim that there is none
        report["up_status"] = "UNSOLVABLE_PROVEN" if code == 0 else "INTERNAL_ERROR"
        report["reason"] = (f"the planner command exited with code {code} and wrote no plan"
                            + (" (reported as unsolvable)" if code == 0 else ""))
        if code != 0 and out_of_memory(report["log"]):
            report["status"] = "memout"
        return outcome
    try:
        plan = read_plan(found, problem)
    except UnreadableText as exc:
        report["status"] = "invalid"
        report["reason"] = f"the planner's plan file cannot be read: {exc}".replace(
            str(work) + os.sep, "")
        return outcome
    report["up_status"] = "SOLVED_SATISFICING"
    report["steps"] = plan_to_steps(plan)
    if code != 0:
        report["notes"].append(f"the planner command exited with code {code} after writing "
                               "a plan")
    return outcome


__all__ = ["PLACEHOLDERS", "parse_command", "plan_file", "program_problem", "render",
           "run_command"]

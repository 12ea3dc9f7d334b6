"""Check a plan made anywhere: read it, validate it, replay it in the simulator.

:func:`check_plan` takes a plan file (IPC format, sequential or time-stamped) for an
instance of an exported set (:mod:`.suite`) or for any domain and problem files:

1. **read**: :mod:`~ocplus_plan.planning.plan_io` parses it against the problem
   (unknown action, wrong arity, unknown object, bad number, garbage line, oversized
   file: the verdict is ``invalid`` and the error names the line);
2. **validate**: unified-planning's validator and VAL (``validate_plan``); either
   rejecting it makes it ``invalid``;
3. **replay** (instances only: domain and problem files alone name no simulator
   state): the fidelity harness runs it in the simulator from the instance's state and
   compares the two worlds after every action; the first divergence is reported in
   kitchen words (:func:`~ocplus_plan.planning.language.kitchen_words`);
4. **judge**: a plan whose strict replay diverges is judged as the league judges it
   (:func:`~ocplus_plan.planning.fidelity_judge.judge`: its steps realised with
   collision-free routing, waits allowed); if the kitchen still reaches the goal it is
   ``valid`` (``realised`` says how, ``divergence`` keeps the strict replay's words), else
   ``unfaithful`` with the step the judge could not realise.

Verdicts and the exit codes of ``ocplus check-plan``: ``valid`` 0, ``invalid`` 4,
``unfaithful`` 5 (see ``ocplus_plan/cli.py``).
"""

from __future__ import annotations

import contextlib
import math
import re
import threading
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..errors import ConfigError, UnreadableText

VERDICT_EXIT = {"valid": 0, "invalid": 4, "unfaithful": 5}
#: a ``--domain`` or ``--problem`` file (the generated domains are under 40 kB, a hard
#: kitchen's problem about 30 kB)
MAX_PDDL_BYTES = 1_000_000
#: actions in one plan (a reference plan of a hard kitchen has a few hundred)
MAX_PLAN_ACTIONS = 20_000
#: CPU seconds one check may use (``--cpu-limit``); reading, validating and replaying a
#: reference plan takes a few
DEFAULT_CPU_LIMIT = 60.0
_ACTION_LINE = re.compile(rb"(?m)^(?:\xef\xbb\xbf)?[ \t]*(?:[0-9.]+[ \t]*:[ \t]*)?\(")


class WorkLimit(ConfigError):
    """A check that used up its CPU seconds."""


def count_plan_actions(path: str | Path) -> int:
    """The action lines of a plan file (read within its size limit), before any parsing;
    a plan of more than :data:`MAX_PLAN_ACTIONS` is refused (``ConfigError``)."""
    from ..planning.plan_io import MAX_PLAN_BYTES

    with open(path, "rb") as fh:
        data = fh.read(MAX_PLAN_BYTES + 1)
    n = len(_ACTION_LINE.findall(data))
    if n > MAX_PLAN_ACTIONS:
        raise ConfigError(f"{path}: {n} actions; check-plan reads plans of at most "
                          f"{MAX_PLAN_ACTIONS} actions")
    return n


@contextlib.contextmanager
def cpu_budget(seconds: float) -> Iterator[None]:
    """Stop the work inside after ``seconds`` more CPU seconds of this process with a
    :class:`WorkLimit`: the profiling timer (``ITIMER_PROF``, user + system time) sends
    SIGPROF at that point. Child processes (VAL) get the same budget on their own CPU
    through ``RLIMIT_CPU`` (whole seconds, rounded up; only the soft limit is set)."""
    import resource
    import signal

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_CPU)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    limit = math.ceil(usage.ru_utime + usage.ru_stime + seconds) + 1
    for cap in (hard, soft):
        if cap != resource.RLIM_INFINITY:
            limit = min(limit, cap)

    def over(signum: int, frame: Any) -> None:
        raise WorkLimit(f"the check used more than {seconds:g} CPU seconds (--cpu-limit); "
                        "the plan or problem is too large to check within it")

    previous = {sig: signal.signal(sig, over) for sig in (signal.SIGPROF, signal.SIGXCPU)}
    resource.setrlimit(resource.RLIMIT_CPU, (limit, hard))
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@dataclass
class PlanCheck:
    """The outcome of :func:`check_plan`; ``verdict`` is valid, invalid or unfaithful."""

    verdict: str
    plan: str
    encoding: str | None = None
    actions: int | None = None
    cost: float | None = None
    makespan: float | None = None
    validation: str = ""
    replayed: bool = False
    simulator_steps: int | None = None
    served: list[int] | None = None
    divergence: str = ""
    realised: str = ""
    error: str = ""

    @property
    def exit_code(self) -> int:
        return VERDICT_EXIT[self.verdict]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _validate(problem: Any, plan: Any, out: PlanCheck, use_val: bool) -> bool:
    from ..planning.validate import plan_quality, validate_plan

    check = validate_plan(problem, plan, use_val=use_val)
    out.validation = check.detail
    quality = plan_quality(problem, plan, with_cost=check.cost is None)
    out.cost = check.cost if check.cost is not None else quality.cost
    out.makespan = quality.makespan
    if check.ok is False:
        out.verdict = "invalid"
        return False
    return True


def check_instance_plan(instance_dir: str | Path, encoding: str | None = None,
                        plan_path: str | Path | None = None, use_val: bool = True) -> PlanCheck:
    """Check a plan for an exported instance (default: its reference plan of ``encoding``,
    or of its only / first encoding)."""
    from ..planning.fidelity_judge import judge
    from ..planning.language import kitchen_words, step_words
    from ..planning.plan_io import read_plan
    from .suite import load_instance, replay_plan

    instance = load_instance(instance_dir)
    encodings = sorted(instance.manifest["encodings"])
    if encoding is None:
        encoding = encodings[0]
    compiled = instance.compiled(encoding)  # unknown encoding / edited problem: ConfigError
    entry = instance.manifest["encodings"][encoding]
    if plan_path is None:
        if "plan" not in entry:
            raise ConfigError(f"{instance.folder} has no {encoding} reference plan (no "
                              "planner solved it); give one with --plan")
        plan_path = instance.folder / entry["plan"]
        if not Path(plan_path).is_file():  # a damaged set, not an invalid plan
            raise ConfigError(f"{instance.folder}: its manifest names the reference plan "
                              f"{entry['plan']}, which is not there; export the set again "
                              "or give a plan with --plan")
    out = PlanCheck("valid", str(plan_path), encoding)
    count_plan_actions(plan_path)
    try:
        plan = read_plan(plan_path, compiled.problem)
    except UnreadableText as exc:
        out.verdict, out.error = "invalid", str(exc)
        return out
    out.actions = _length(plan)
    if not _validate(compiled.problem, plan, out, use_val):
        return out
    replay = replay_plan(compiled, plan, instance.state)
    out.replayed, out.simulator_steps, out.served = True, replay.steps, replay.served
    if not replay.ok:
        out.verdict = "unfaithful"
        where, mismatch = "", replay.mismatch
        if plan.kind.name == "SEQUENTIAL_PLAN" and replay.actions:
            ai = plan.actions[replay.actions - 1]
            args = [str(p.object()) for p in ai.actual_parameters]
            where = (f"at plan step {replay.actions - 1} "
                     f"({step_words(compiled, ai.action.name, args)}): ")
            mismatch = mismatch.removeprefix(f"{ai}: ")
        out.divergence = where + kitchen_words(mismatch, compiled) + (
            f" (kind: {replay.category})" if replay.category else "")
        verdict = judge(compiled, plan, instance.state)
        if verdict.faithful:
            out.verdict = "valid"
            out.realised = (f"{verdict.how}, the kitchen reaches the goal "
                            f"({verdict.waits} extra steps of waiting and walking around)")
        else:
            out.realised = (f"{verdict.how}: fails at plan step {verdict.failed_step}: "
                            if verdict.failed_step is not None else f"{verdict.how}: ") + \
                kitchen_words(verdict.reason, compiled)
    return out


def check_files(domain: str | Path, problem: str | Path, plan_path: str | Path,
                use_val: bool = True) -> PlanCheck:
    """Check a plan against PDDL files alone (validation only; no simulator state)."""
    from ..planning.pddl import read_pddl
    from ..planning.plan_io import read_plan

    for path in (domain, problem):
        if not Path(path).is_file():
            raise ConfigError(f"{path}: no such file")
    count_plan_actions(plan_path)  # before the PDDL is parsed
    try:
        parsed = read_pddl(domain, problem)
    except WorkLimit:
        raise
    except Exception as exc:  # noqa: BLE001 - UP's reader raises many kinds
        raise ConfigError(f"{domain} / {problem}: unified-planning cannot read them "
                          f"({type(exc).__name__}: {str(exc)[:300]})") from None
    out = PlanCheck("valid", str(plan_path))
    try:
        plan = read_plan(plan_path, parsed)
    except UnreadableText as exc:
        out.verdict, out.error = "invalid", str(exc)
        return out
    out.actions = _length(plan)
    _validate(parsed, plan, out, use_val)
    return out


def _length(plan: Any) -> int:
    return len(plan.timed_actions) if plan.kind.name == "TIME_TRIGGERED_PLAN" else len(
        plan.actions)


__all__ = ["DEFAULT_CPU_LIMIT", "MAX_PDDL_BYTES", "MAX_PLAN_ACTIONS", "VERDICT_EXIT", "PlanCheck",
           "WorkLimit", "check_files", "check_instance_plan", "count_plan_actions",
           "cpu_budget"]

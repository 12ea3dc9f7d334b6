"""Sound restrictions of a problem for engines that cannot take it as it is.

Each transformation only removes freedom, so every plan of the restricted problem
is a plan of the original (and :func:`~.engines.solve` validates it against the
original anyway):

* :func:`without_quality_metrics`: drop the action-cost / makespan metric (and the
  numeric fluents only it used), for pyperplan, LPG and TAMER, which do not
  optimise it. The plan is still a plan; only its quality is not optimised.
* :func:`with_fixed_durations`: a duration range ``[lo, hi]`` becomes ``lo``
  (or ``hi`` if the lower bound is open), for LPG, which has no duration
  inequalities. Every fixed duration lies in the range, so this is sound, not
  complete: a problem that needs another duration becomes unsolvable.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def adapt_for_engine(problem: Any, supports: Callable[[Any], bool], supported_kind: Any,
                     engine_name: str, notes: list[str]) -> tuple[Any, str]:
    """The least restricted variant of ``problem`` that ``supports`` accepts.

    Returns ``(problem_or_variant, "")``, appending what was changed to ``notes``,
    or ``(None, reason)`` naming the features the engine still lacks.
    """
    if supports(problem.kind):
        return problem, ""
    steps: list[tuple[str, Callable[[Any], Any]]] = []
    if problem.quality_metrics:
        metrics = ", ".join(type(m).__name__ for m in problem.quality_metrics)
        note = (f"{engine_name} does not optimise {metrics}: solved without it; "
                "cost/makespan are measured on the original problem")
        steps.append((note, without_quality_metrics))
    if "DURATION_INEQUALITIES" in problem.kind.features:
        note = (f"{engine_name} has no duration ranges: each range was fixed to its "
                "lower bound (sound, not complete)")
        steps.append((note, with_fixed_durations))
    target, done = problem, []
    for note, transform in steps:
        candidate = transform(target)
        if candidate is None:
            continue
        target = candidate
        done.append(note)
        if supports(target.kind):
            notes.extend(done)
            return target, ""
    lacking = sorted(set(target.kind.features) - set(supported_kind.features))
    return None, (f"{engine_name} does not support this problem "
                  f"(features it lacks: {', '.join(lacking) or 'unknown'})")


def with_fixed_durations(problem: Any) -> Any | None:
    """A copy whose durative actions have fixed durations (see the module docstring)."""
    out = problem.clone()
    changed = False
    for action in out.actions:
        duration = getattr(action, "duration", None)
        if duration is None or duration.lower == duration.upper:
            continue
        if not duration.is_left_open():
            action.set_fixed_duration(duration.lower)
        elif not duration.is_right_open():
            action.set_fixed_duration(duration.upper)
        else:
            return None
        changed = True
    return out if changed else None


def without_quality_metrics(problem: Any) -> Any:
    """A copy of ``problem`` with no quality metric and no fluent used only by the metric.

    Lets a planner that cannot optimise action costs or makespan (pyperplan,
    TAMER) still solve the problem; numeric fluents that only fed the cost
    expressions would otherwise make the problem numeric for it.
    """
    from unified_planning.model import Problem

    env = problem.environment
    used: set[Any] = set()

    def note(expr: Any) -> None:
        for fexp in env.free_vars_extractor.get(env.expression_manager.auto_promote(expr)[0]):
            used.add(fexp.fluent())

    for action in problem.actions:
        for cond in getattr(action, "preconditions", []):
            note(cond)
        for conds in getattr(action, "conditions", {}).values():
            for cond in conds:
                note(cond)
        duration = getattr(action, "duration", None)
        if duration is not None:
            note(duration.lower)
            note(duration.upper)
        effs = getattr(action, "effects", [])
        effects = [e for group in effs.values() for e in group] if isinstance(effs, dict) \
            else list(effs)
        for eff in effects:
            if hasattr(eff, "fluent"):
                note(eff.fluent)
                note(eff.value)
                note(eff.condition)
    for goal in problem.goals:
        note(goal)
    for goals in problem.timed_goals.values():
        for goal in goals:
            note(goal)
    for effs in problem.timed_effects.values():
        for eff in effs:
            note(eff.fluent)
            note(eff.value)

    out = Problem(problem.name, env)
    for fluent in problem.fluents:
        if fluent in used:
            out.add_fluent(fluent, default_initial_value=problem.fluents_defaults.get(fluent))
    out.add_objects(problem.all_objects)
    out.add_actions(problem.actions)
    for fexp, value in problem.explicit_initial_values.items():
        if fexp.fluent() in used:
            out.set_initial_value(fexp, value)
    for goal in problem.goals:
        out.add_goal(goal)
    for timing, goals in problem.timed_goals.items():
        for goal in goals:
            out.add_timed_goal(timing, goal)
    for timing, effs in problem.timed_effects.items():
        for eff in effs:
            out.add_timed_effect(timing, eff.fluent, eff.value, eff.condition)
    return out



"""Sound restrictions of a problem for engines that cannot take it as it is.

Each transformation only removes freedom, so every plan of the restricted problem
is a plan of the original (and :func:`~.engines.solve` validates it against the
original anyway):

* :func:`without_quality_metrics`: drop the action-cost / makespan metric (and the
  numeric fluents only it used), for pyperplan, LPG and TAMER, which do not
  optimise it. The plan is still a plan; only its quality is not optimised.
* :func:`without_unusable_actions`: drop the actions that can never apply in this
  problem (a precondition on a fact no action changes and no initial fact makes true:
  washing where there is no sink), for readers and language models that take the
  domain as text. Nothing a plan can do is lost.
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




def _action_effects(action: Any) -> list[Any]:
    effects = getattr(action, "effects", [])
    return [e for group in effects.values() for e in group] if isinstance(effects, dict) \
        else list(effects)


def _action_conditions(action: Any) -> list[Any]:
    if hasattr(action, "preconditions"):
        return list(action.preconditions)
    return [c for group in action.conditions.values() for c in group]


def unusable_actions(problem: Any) -> list[str]:
    """Names of the actions of ``problem`` that can never apply: one of their conditions is
    a (positive) fact of a fluent that no action and no timed effect changes and that holds
    for no objects at the start."""
    changed = {e.fluent.fluent() for a in problem.actions for e in _action_effects(a)}
    changed |= {e.fluent.fluent() for effs in problem.timed_effects.values() for e in effs}
    holding = {fexp.fluent() for fexp, value in problem.explicit_initial_values.items()
               if value.is_bool_constant() and value.bool_constant_value()}
    out = []
    for action in problem.actions:
        for cond in _action_conditions(action):
            if cond.is_fluent_exp() and cond.fluent() not in changed \
                    and cond.fluent() not in holding:
                out.append(action.name)
                break
    return out


def without_unusable_actions(problem: Any) -> tuple[Any, list[str]]:
    """``(problem without the actions of :func:`unusable_actions`, their names)``; the
    action-cost metric keeps the costs of the actions that stay."""
    from unified_planning.model.metrics import MinimizeActionCosts

    dropped = set(unusable_actions(problem))
    if not dropped:
        return problem, []
    out = problem.clone()
    out.clear_actions()
    out.add_actions([a for a in problem.actions if a.name not in dropped])
    metrics = list(out.quality_metrics)
    out.clear_quality_metrics()
    for metric in metrics:
        if isinstance(metric, MinimizeActionCosts):
            kept = {a: c for a, c in metric.costs.items() if a.name not in dropped}
            metric = MinimizeActionCosts(kept, environment=problem.environment)
        out.add_quality_metric(metric)
    return out, sorted(dropped)

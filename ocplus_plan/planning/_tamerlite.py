"""TamerLite (FBK's heuristic-search temporal planner) through unified-planning 1.3.0.

``tamerlite`` 0.1.1 grounds every problem before searching, in two steps that do not
work here as shipped:

* it first asks UP's factory for an ``UNDEFINED_INITIAL_NUMERIC_REMOVING`` compiler,
  which unified-planning 1.3.0 (the newest release) does not have, so every solve
  fails at once. The step only matters for problems whose numeric fluents have no
  initial value; the kitchen's always have one (the compiler gives every numeric
  fluent a default), so :class:`GroundedTamerLite` skips it for such problems (and
  keeps it, i.e. fails as before, for the others);
* UP 1.3.0's grounder then crashes on the kitchen's actions (``list.remove`` of an
  object two static conditions both pruned; fixed in UP's development versions) and,
  with that fixed, still builds every combination its per-parameter pruning leaves:
  18.5 s for the easy preset's 268 actions. :func:`static_groundings` instead joins each action's
  static conditions (facts no action changes), which keeps exactly the combinations
  UP's pruning would keep (268 on easy) in well under a second, and hands them to UP's
  grounder as its ``grounding_actions_map``.

Grounding is sound either way: an action instance whose static conditions are false
in the initial state is never applicable. :func:`register` adds the engine to UP's
factory as ``ocplus-tamerlite``. Importing this module imports ``tamerlite``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from tamerlite.engine import SearchParams, TamerLite

ENGINE_NAME = "ocplus-tamerlite"


def static_groundings(problem: Any) -> dict[Any, list[tuple[Any, ...]]]:
    """Per action, the parameter tuples (object expressions) that satisfy all of its
    positive static boolean conditions in ``problem``'s initial state."""
    statics = problem.get_static_fluents()
    em = problem.environment.expression_manager
    true: dict[Any, set[tuple[Any, ...]]] = {}
    for fexp, value in problem.explicit_initial_values.items():
        fluent = fexp.fluent()
        if fluent in statics and fluent.type.is_bool_type() and value.is_true():
            true.setdefault(fluent, set()).add(tuple(a.object() for a in fexp.args))
    out: dict[Any, list[tuple[Any, ...]]] = {}
    for action in problem.actions:
        params = list(action.parameters)
        position = {p: k for k, p in enumerate(params)}
        # each static condition is checked as soon as its last parameter is bound
        checks: list[list[tuple[Any, list[tuple[bool, Any]]]]] = [[] for _ in params]
        impossible = False
        for cond in _conditions(action):
            fluent = cond.fluent() if cond.is_fluent_exp() else None
            if fluent is None or fluent not in statics or not fluent.type.is_bool_type():
                continue
            if not all(a.is_parameter_exp() or a.is_object_exp() for a in cond.args):
                continue
            args = [(True, a.parameter()) if a.is_parameter_exp() else (False, a.object())
                    for a in cond.args]
            bound = [position[x] for is_param, x in args if is_param]
            if bound:
                checks[max(bound)].append((fluent, args))
            elif tuple(x for _, x in args) not in true.get(fluent, ()):
                impossible = True
        out[action] = [] if impossible else _join(problem, params, checks, true, em)
    return out


def _conditions(action: Any) -> list[Any]:
    if hasattr(action, "preconditions"):
        conds = list(action.preconditions)
    else:
        conds = [c for group in action.conditions.values() for c in group]
    flat = []
    for cond in conds:
        flat.extend(cond.args if cond.is_and() else [cond])
    return flat


def _join(problem: Any, params: list[Any], checks: list[list[Any]],
          true: dict[Any, set[tuple[Any, ...]]], em: Any) -> list[tuple[Any, ...]]:
    domains = [list(problem.objects(p.type)) for p in params]
    found: list[tuple[Any, ...]] = []
    binding: dict[Any, Any] = {}

    def extend(k: int) -> None:
        if k == len(params):
            found.append(tuple(em.ObjectExp(binding[p]) for p in params))
            return
        for obj in domains[k]:
            binding[params[k]] = obj
            if all(tuple(binding[x] if is_param else x for is_param, x in args)
                   in true.get(fluent, ()) for fluent, args in checks[k]):
                extend(k + 1)
        binding.pop(params[k], None)

    extend(0)
    return found


class GroundedTamerLite(TamerLite):  # type: ignore[misc]
    """TamerLite grounded by :func:`static_groundings` (see the module docstring).

    Parameters are plain values (YAML-friendly): ``search`` (wastar, astar, gbfs, ehc,
    dfs, bfs), ``heuristic`` (hff, hadd, hmax, ...) and ``weight``; unset ones keep
    TamerLite's defaults (weighted A* with hff, weight 0.8).
    """

    def __init__(self, search: str | None = None, heuristic: str | None = None,
                 weight: float | None = None) -> None:
        super().__init__(SearchParams(search=search, heuristic=heuristic, weight=weight))

    @property
    def name(self) -> str:
        return ENGINE_NAME

    def _compile_problem(self, problem: Any) -> tuple[Any, Any, Callable[[Any], Any]]:
        if "UNDEFINED_INITIAL_NUMERIC" in problem.kind.features:
            return super()._compile_problem(problem)
        from unified_planning.engines import CompilationKind
        from unified_planning.engines.compilers.grounder import Grounder

        grounder = Grounder(grounding_actions_map=static_groundings(problem))
        result = grounder.compile(problem, CompilationKind.GROUNDING)
        return problem, result.problem, result.map_back_action_instance


def register(env: Any = None) -> None:
    """Add ``ocplus-tamerlite`` to the factory of ``env`` (UP's global environment by default)."""
    from unified_planning.shortcuts import get_environment

    factory = (env or get_environment()).factory
    if ENGINE_NAME not in factory.engines:
        factory.add_engine(ENGINE_NAME, __name__, "GroundedTamerLite")

"""Filling a UP problem fast: the objects and initial facts of one compiled state.

The fast path (the default) fills the problem's containers directly: the objects
and facts are correct by construction (names are unique, argument types follow
the fluent signatures), while UP's public setters re-check every one of them at
~50 us each, which was most of the compile time. ``tests/planning/test_compile.py``
checks that both paths build equal problems. Any UP version without these
containers falls back to the public API.
"""

from __future__ import annotations

from typing import Any

from ..errors import CompileError


class Builder:
    """Collects objects and initial values, then sets them on the problem in one go.

    The fast path (the default) fills the problem's containers directly: the objects
    and facts are correct by construction (names are unique, argument types follow
    the fluent signatures), and UP's public setters re-check every one of them at
    ~50 us each, which is most of the compile time. ``tests/planning/test_compile.py``
    checks that both paths build equal problems.
    """

    def __init__(self, problem: Any, dom: Any, comp: Any, fast: bool = True) -> None:
        self.problem, self.dom, self.comp = problem, dom, comp
        self.fast = fast and _has_internals(problem)
        self.objects: dict[str, Any] = {}
        self.facts: list[tuple[str, tuple[str, ...], Any]] = []

    def obj(self, table: str, name: str, value: Any, typ: Any) -> str:
        if name in self.objects:
            raise CompileError(f"two objects named {name!r}")
        self.comp.names.add(table, name, value)
        self.objects[name] = _object(name, typ)
        if not self.fast:
            self.problem.add_object(self.objects[name])
        return name

    def true(self, fluent: str, *args: str) -> None:
        self.facts.append((fluent, args, True))

    def num(self, fluent: str, value: int, *args: str) -> None:
        self.facts.append((fluent, args, int(value)))
        self.comp.numbers[(fluent, args)] = int(value)

    def flush(self) -> None:
        from unified_planning.model.operators import OperatorKind

        problem = self.problem
        em = problem.environment.expression_manager
        fl = self.dom.fluents
        if not self.fast:
            objs = self.objects
            for fluent, args, value in self.facts:
                problem.set_initial_value(fl[fluent](*(objs[a] for a in args)),
                                          em.TRUE() if value is True else em.Int(value))
            return
        problem._objects.extend(self.objects.values())
        node = em.create_node
        cache = _FLUENT_EXPS.setdefault(id(self.dom), {})
        objects = self.objects
        true = em.TRUE()
        init = problem._initial_value
        ints: dict[int, Any] = {}
        for fluent, args, value in self.facts:
            key = (fluent, args)
            fexp = cache.get(key)
            if fexp is None:
                fexp = cache[key] = node(
                    OperatorKind.FLUENT_EXP,
                    tuple(node(OperatorKind.OBJECT_EXP, (), payload=objects[a]) for a in args),
                    payload=fl[fluent])
            init[fexp] = true if value is True else (ints.get(value) or ints.setdefault(value, em.Int(value)))


#: per domain: (fluent name, object names) -> the FNode (objects are cached by name and
#: type, so the same ground fluent is the same FNode in every compiled problem)
_FLUENT_EXPS: dict[int, dict[tuple[str, tuple[str, ...]], Any]] = {}
_OBJECTS: dict[tuple[str, Any], Any] = {}


def _object(name: str, typ: Any) -> Any:
    """UP objects are immutable values: make each (name, type) once."""
    key = (name, typ)
    obj = _OBJECTS.get(key)
    if obj is None:
        from unified_planning.model import Object

        obj = _OBJECTS[key] = Object(name, typ)
    return obj


_BASES: dict[int, Any] = {}


def _has_internals(problem: Any) -> bool:
    return all(hasattr(problem, a) for a in (
        "_objects", "_initial_value", "_fluents", "_fluents_defaults", "_actions",
        "_user_types", "_user_types_hierarchy"))


def new_problem(name: str, dom: Any, fast: bool = True) -> Any:
    """An empty problem with the domain's fluents (with defaults) and actions."""
    from unified_planning.model import Problem

    def public() -> Any:
        problem = Problem(name)
        for fl in dom.fluents.values():
            problem.add_fluent(fl, default_initial_value=0 if fl.type.is_int_type() else False)
        problem.add_actions(dom.actions.values())
        return problem

    if not fast:
        return public()
    base = _BASES.get(id(dom))
    if base is None:
        base = _BASES[id(dom)] = (dom, public())
    problem = Problem(name)
    if not _has_internals(problem):
        return public()
    template = base[1]
    problem._fluents = list(template._fluents)
    problem._fluents_defaults = dict(template._fluents_defaults)
    problem._actions = list(template._actions)
    problem._user_types = list(template._user_types)
    problem._user_types_hierarchy = {k: list(v) for k, v in
                                     template._user_types_hierarchy.items()}
    return problem

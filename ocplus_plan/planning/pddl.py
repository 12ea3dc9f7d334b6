"""PDDL text out (the checked-in ``domains/`` are generated here) and back in.

``write_pddl(compiled, out_dir)`` writes ``domain.pddl`` and ``problem.pddl`` with
unified-planning's PDDLWriter; ``domain_text(encoding, granularity)`` is the
canonical domain of ``domains/<encoding>_<granularity>.pddl`` (generated from the
easy preset's initial state: the domain itself holds no rule numbers, and
problem-specific objects never appear in it); ``read_pddl`` parses files back
with UP's PDDLReader.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from .compile import Compiled, compile

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable


def problem_texts(compiled: Compiled) -> tuple[str, str]:
    """(domain text, problem text) of a compiled state (see :func:`pddl_texts`)."""
    return pddl_texts(compiled.problem)


def pddl_texts(problem: Any) -> tuple[str, str]:
    """(domain text, problem text) of a UP problem of the kitchen model.

    Requirements: classical files declare ``:action-costs`` for the static functions that
    feed the costs (distances, steps left), as the IPC action-cost domains do and as Fast
    Downward requires (it rejects ``:numeric-fluents``). In temporal files the same
    functions give the durations, which PDDL 2.1 calls numeric fluents: UP's writer does
    not say so, and VAL's ``Parser`` warns ``Undeclared requirement :number-fluents`` at
    every use, so they declare ``:numeric-fluents`` (Kairos, LPG and UP's reader take it).
    """
    from unified_planning.io import PDDLWriter

    from .plan_io import is_temporal

    writer = PDDLWriter(problem, needs_requirements=True, rewrite_bool_assignments=False)
    domain = writer.get_domain()
    if is_temporal(problem):
        domain = declare_numeric_fluents(domain)
    return domain, writer.get_problem()


def declare_numeric_fluents(domain: str) -> str:
    """The domain text with ``:numeric-fluents`` added when it declares functions."""
    head, sep, rest = domain.partition("(:requirements")
    if not sep or "(:functions" not in rest:
        return domain
    reqs, close, tail = rest.partition(")")
    if ":numeric-fluents" in reqs:
        return domain
    return f"{head}{sep}{reqs} :numeric-fluents{close}{tail}"


def write_pddl(compiled: Compiled, out_dir: str | Path) -> tuple[Path, Path]:
    """Write ``domain.pddl`` and ``problem.pddl`` into ``out_dir`` (created if missing)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    domain, problem = problem_texts(compiled)
    dpath, ppath = out / "domain.pddl", out / "problem.pddl"
    dpath.write_text(domain)
    ppath.write_text(problem)
    return dpath, ppath


def canonical_state() -> Any:
    """The state the checked-in domains are generated from (easy preset, seed 0)."""
    from ..sim import make_rules, new_state

    return new_state(make_rules("easy"), 0)


def domain_text(encoding: str, granularity: str, switches: bool = False) -> str:
    """The canonical domain of one encoding and granularity (what ``domains/`` holds);
    ``switches``: with anticipated layout switches (temporal only)."""
    compiled = compile(canonical_state(), encoding=encoding, granularity=granularity,
                       anticipate_switches=switches)
    return problem_texts(compiled)[0]


def domain_path(encoding: str, granularity: str, switches: bool = False) -> Traversable:
    """The checked-in domain of one variant (package data built from ``domains/``)."""
    from ..data import data_files

    return data_files("domains") / f"{encoding}_{granularity}{'_switches' if switches else ''}.pddl"


def read_pddl(domain: str | Path, problem: str | Path) -> Any:
    """Parse PDDL files back into a UP problem with UP's PDDLReader."""
    from unified_planning.io import PDDLReader

    return PDDLReader().parse_problem(str(domain), str(problem))


__all__ = ["declare_numeric_fluents", "domain_path", "domain_text", "pddl_texts", "problem_texts",
           "read_pddl", "write_pddl"]

"""Planner portfolios: registry entries that run other entries in turn within one CPU budget.

A portfolio's YAML names its members in order, each with the share of the CPU limit it may
use (the last member gets whatever the others left)::

    name: fast-downward-portfolio
    encoding: classical
    portfolio:
      - {planner: fast-downward-bjolp, share: 0.3}   # optimal, if it is quick
      - {planner: fast-downward}                      # else lama-first with the rest

:func:`run` asks each member in turn with its budget (CPU seconds, as every planner call
here) and returns the first plan found. A member that proves the problem unsolvable ends the
portfolio (the planners registered are complete); a member that times out, errs or is
unavailable passes to the next. The result is the winning member's, named after the
portfolio, with the CPU and wall seconds of every member added and one note per member.
Because each budget is CPU seconds, which member answers does not depend on machine load.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

from ..errors import PlannerError

#: statuses that end a portfolio: a plan, or a proof that there is none
FINAL_STATUSES = frozenset({"solved", "unsolvable"})


def parse_members(data: Any, source: str) -> tuple[tuple[str, float | None], ...]:
    """The ``portfolio`` list of a planner YAML: ((planner, share or None), ...)."""
    if not isinstance(data, list) or not data:
        raise PlannerError(f"{source}: 'portfolio' must be a non-empty list of "
                           "{planner: NAME, share: FRACTION} mappings")
    members = []
    for i, item in enumerate(data):
        if not isinstance(item, dict) or not isinstance(item.get("planner"), str) \
                or set(item) - {"planner", "share"}:
            raise PlannerError(f"{source}: portfolio member {i} must be a mapping with "
                               f"'planner' (a registry name) and optionally 'share', got {item!r}")
        share = item.get("share")
        last = i == len(data) - 1
        if share is None and not last:
            raise PlannerError(f"{source}: portfolio member {i} ({item['planner']}) needs a "
                               "'share' of the CPU limit (only the last member takes the rest)")
        if share is not None and (isinstance(share, bool) or not isinstance(share, (int, float))
                                  or not 0 < share <= 1):
            raise PlannerError(f"{source}: portfolio member {i} ({item['planner']}): share "
                               f"must be a fraction in (0, 1], got {share!r}")
        members.append((item["planner"], None if share is None else float(share)))
    return tuple(members)


def member_problem(name: str, encoding: str, member: Any) -> str:
    """Why ``member`` (a PlannerConfig) cannot be in portfolio ``name`` ("" if it can)."""
    if member.portfolio:
        return f"portfolio {name!r}: member {member.name!r} is itself a portfolio"
    if member.encoding != encoding:
        return (f"portfolio {name!r}: member {member.name!r} solves the {member.encoding} "
                f"encoding, the portfolio the {encoding} one")
    return ""


def run(config: Any, limit: float, solve_member: Callable[[str, float], Any],
        empty: Any) -> Any:
    """Ask the members of ``config`` in turn within ``limit`` CPU seconds.

    ``solve_member(name, cpu_seconds)`` solves with one member; ``empty`` is the
    PlanResult to return (status ``timeout``) when no member got an answer."""
    remaining, cpu, wall = limit, 0.0, 0.0
    notes: list[str] = []
    result = None
    for i, (member, share) in enumerate(config.portfolio):
        last = i == len(config.portfolio) - 1
        budget = remaining if last or share is None else min(remaining, limit * share)
        if budget <= 0:
            notes.append(f"{member}: not run (no CPU seconds left)")
            continue
        result = solve_member(member, budget)
        used = float(result.cpu_time or 0.0)
        cpu, wall = cpu + used, wall + float(result.planning_time or 0.0)
        remaining = max(0.0, remaining - max(used, budget if result.status == "timeout" else 0))
        notes.append(f"{member}: {result.status} in {used:.2f} CPU s of {budget:.2f}")
        if result.status in FINAL_STATUSES:
            break
    if result is None:
        result = empty
    elif result.status not in FINAL_STATUSES:
        result = replace(empty, reason="; ".join(notes), limit_hit="cpu")
    return replace(result, planner=config.name, cpu_time=round(cpu, 4),
                   planning_time=round(wall, 4), cpu_limit=limit,
                   wall_limit=empty.wall_limit, notes=[*notes, *result.notes])


__all__ = ["FINAL_STATUSES", "member_problem", "parse_members", "run"]

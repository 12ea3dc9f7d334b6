"""LPG through unified-planning, with a plan reader that accepts LPG-td's output.

``up-lpg`` 0.1.3 cannot read the temporal plans LPG-td 1.4 writes: each line ends
with a stray ``)`` after the duration (``0.0003:   (MOVE L0 L1) [2.0000])``), so
its regular expression fails and every temporal solve ends in
``UPException: Error parsing plan``. :class:`FixedLPGEngine` is the same engine
with its own line reader; :func:`register` adds it to UP's factory as
``ocplus-lpg``. Importing this module imports ``up_lpg`` (which needs
``pkg_resources``, i.e. ``setuptools<81``).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from fractions import Fraction
from typing import Any

import unified_planning as up

with warnings.catch_warnings():  # up_lpg imports pkg_resources, which warns on import
    warnings.filterwarnings("ignore", message="pkg_resources is deprecated")
    warnings.simplefilter("ignore", UserWarning)
    from up_lpg.lpg_planner import LPGEngine

ENGINE_NAME = "ocplus-lpg"

# "<start>: (<name> <args...>) [<duration>]" with optional stray ")" and ";" comment.
_STEP = re.compile(
    r"^\s*(?P<start>\d+(?:\.\d+)?)\s*:\s*\(\s*(?P<name>[^()\s]+)(?P<args>(?:\s+[^()\s]+)*)\s*\)"
    r"\s*(?:\[\s*(?:D:)?(?P<dur>\d+(?:\.\d+)?)[^\]]*\])?\s*\)?\s*(?:;.*)?$"
)


def parse_lpg_line(line: str) -> tuple[Fraction, str, list[str], Fraction | None] | None:
    """One LPG plan line -> (start, action, args, duration); None for blank/comment lines.

    Raises ValueError for a line that is neither.
    """
    if re.match(r"^\s*(;.*)?$", line):
        return None
    match = _STEP.match(line)
    if not match:
        raise ValueError(f"unreadable LPG plan line: {line.strip()!r}")
    dur = match.group("dur")
    return (Fraction(match.group("start")), match.group("name").lower(),
            [a.lower() for a in match.group("args").split()],
            Fraction(dur) if dur is not None else None)


class FixedLPGEngine(LPGEngine):  # type: ignore[misc]
    """``up_lpg``'s LPG engine with a plan reader that tolerates LPG-td's stray ``)``."""

    @property
    def name(self) -> str:
        return ENGINE_NAME

    def _plan_from_file(self, problem: Any, plan_filename: str,
                        get_item_named: Callable[[str], Any]) -> Any:
        temporal = "CONTINUOUS_TIME" in problem.kind.features
        em = problem.environment.expression_manager
        timed: list[tuple[Fraction, Any, Fraction | None]] = []
        with open(plan_filename, encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if "no solution" in line.lower():
                    return None
                step = parse_lpg_line(line)
                if step is None:
                    continue
                start, name, args, dur = step
                params = tuple(em.ObjectExp(get_item_named(a)) for a in args)
                timed.append((start, up.plans.ActionInstance(get_item_named(name), params), dur))
        if temporal:
            return up.plans.TimeTriggeredPlan(sorted(timed, key=lambda s: s[0]))
        return up.plans.SequentialPlan([ai for _, ai, _ in sorted(timed, key=lambda s: s[0])])


def register(env: Any = None) -> None:
    """Add ``ocplus-lpg`` to the factory of ``env`` (UP's global environment by default)."""
    from unified_planning.shortcuts import get_environment

    factory = (env or get_environment()).factory
    if ENGINE_NAME not in factory.engines:
        factory.add_engine(ENGINE_NAME, __name__, "FixedLPGEngine")

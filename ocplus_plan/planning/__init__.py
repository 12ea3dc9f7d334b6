"""Planning: the simulator's states as unified-planning problems (PDDL 2.1, classical or
temporal), and their plans mapped back to simulator objects.

This package imports unified_planning; ``ocplus_plan.sim`` and ``ocplus_plan.env``
never import it. Typical use::

    from ocplus_plan.planning import compile
    compiled = compile(state, encoding="classical", granularity="stations")
    compiled.problem          # a unified_planning Problem
    compiled.map_back(ai)     # MappedAction(agent, kind, items, place, spot, duration, ...)
"""

from __future__ import annotations

from .compile import Compiled, compile
from .model import ENCODINGS, GRANULARITIES, build_domain
from .names import MappedAction, Names

__all__ = ["ENCODINGS", "GRANULARITIES", "Compiled", "MappedAction", "Names", "build_domain",
           "compile"]

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

import warnings

# up_lpg imports pkg_resources, which warns (UserWarning or DeprecationWarning, by
# setuptools version) the first time; UP's factory imports it as soon as any planning
# module touches UP. Filtered here, before the first such import, so that every command's
# one-line refusal stays one line.
warnings.filterwarnings("ignore", message="pkg_resources is deprecated")

from .compile import Compiled, compile  # noqa: E402
from .model import ENCODINGS, GRANULARITIES, build_domain  # noqa: E402
from .names import MappedAction, Names  # noqa: E402

__all__ = ["ENCODINGS", "GRANULARITIES", "Compiled", "MappedAction", "Names", "build_domain",
           "compile"]

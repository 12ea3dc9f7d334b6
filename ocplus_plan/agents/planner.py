"""A planner-backed controller: compile the state, solve it, and let the executive run the plan.

``PlannerAgent("fast-downward", encoding="classical", granularity="stations",
policy="on_event")`` plans with any registered planner (``planning.engines``) on the
compiled problem (``planning.compile``), maps every plan action back to a simulator
interaction (:class:`~ocplus_plan.execution.executive.PlanStep`) and hands the plan
to an :class:`~ocplus_plan.execution.executive.Executive`, which routes the agents,
monitors the world and replans. A planner failure is never an exception here: the
executive keeps the last valid plan and agents without work keep out of the way.

Registered as ``planner`` in :data:`ocplus_plan.agents.FACTORIES`: ``planner:fast-downward``,
``planner:kairos`` (temporal), or ``planner:NAME:GRANULARITY:POLICY`` for the rest.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from ..errors import ConfigError
from ..execution.executive import Executive, PlanFunction, PlanOutcome, PlanStep, Policy
from ..sim.state import State
from .base import Controller

#: map-back kinds -> the executive's step kinds (anything not listed is a move or a no-op)
_KIND_ALIASES = {
    "pickup": "pickup", "pick": "pickup", "pick_up": "pickup", "take": "pickup",
    "take_from_pan": "pickup", "uncook": "pickup", "cook_end": "pickup", "collect": "pickup",
    "putdown": "putdown", "put": "putdown", "put_down": "putdown", "drop": "putdown",
    "place": "putdown", "cook": "putdown", "cook_start": "putdown", "start_cook": "putdown",
    "chop": "chop", "wash": "wash",
    "plate": "plate", "plate_add": "plate", "add_to_plate": "plate", "assemble": "plate",
    "deliver": "deliver", "serve": "deliver", "trash": "trash", "bin": "trash",
    "bump": "bump", "interact": "bump",
}
_SKIP = ("move", "walk", "go", "wait", "noop", "idle")


def _field(record: Any, *names: str, default: Any = None) -> Any:
    for n in names:
        if isinstance(record, dict) and n in record:
            return record[n]
        if hasattr(record, n):
            return getattr(record, n)
    return default


def step_from_record(record: Any, state: State, index: int, start: float | None = None) -> PlanStep | None:
    """One map-back record of the planning layer -> a :class:`PlanStep` (None for moves)."""
    raw = _field(record, "kind", "action", "action_kind", default="")
    raw = getattr(raw, "value", raw)  # an Enum member
    base = str(raw).lower().split(".")[-1]
    if any(base.startswith(s) for s in _SKIP):
        return None
    norm = _KIND_ALIASES.get(base)
    if norm is None:
        norm = next((v for k, v in _KIND_ALIASES.items() if base.startswith(k)), "bump")
    agent = _field(record, "agent", "agent_index")
    if agent is None:
        return None
    target = _field(record, "target", "cell", "target_cell", "station_cell", "station")
    if isinstance(target, (tuple, list)) and len(target) == 2:
        target = state.geo.flat(int(target[0]), int(target[1]))
    if target is None or isinstance(target, str):
        return None
    items = _field(record, "items", default=()) or ()
    if isinstance(items, int):
        items = (items,)
    items = tuple(int(i) for i in items if isinstance(i, int))
    start = _field(record, "start", default=start)
    duration = _field(record, "duration", default=None)
    return PlanStep(index, int(agent), norm, int(target), items,
                    None if start is None else float(start),
                    None if duration is None else float(duration))


def compile_and_solve(
    planner: str, encoding: str = "classical", granularity: str = "stations",
    anticipate_switches: bool = False, timeout: float = 20.0,
) -> PlanFunction:
    """A :data:`PlanFunction` that compiles the state and solves it with a named planner."""

    def plan(state: State, agents: tuple[int, ...]) -> PlanOutcome:
        from ..planning import compile as compile_mod  # optional layer: imported lazily
        from ..planning.engines import solve

        t0 = time.perf_counter()
        compiled = compile_mod.compile(state, None, encoding=encoding, granularity=granularity,
                                       anticipate_switches=anticipate_switches)
        result = solve(compiled.problem, planner, timeout=timeout)
        elapsed = time.perf_counter() - t0
        if result.status != "solved" or result.plan is None:
            return PlanOutcome(result.status, [], elapsed, result.reason)
        return PlanOutcome("solved", plan_steps(compiled, result.plan, state), elapsed)

    return plan


def plan_steps(compiled: Any, plan: Any, state: State) -> list[PlanStep]:
    """Map a UP sequential or time-triggered plan back to executive steps."""
    if hasattr(plan, "timed_actions"):
        entries = [(float(start), ai) for start, ai, _dur in plan.timed_actions]
    else:
        entries = [(None, ai) for ai in plan.actions]
    steps = []
    for k, (start, ai) in enumerate(entries):
        step = step_from_record(compiled.map_back(ai), state, k, start)
        if step is not None:
            steps.append(step)
    return steps


class PlannerAgent(Controller):
    """A controller that plans with a named planner and executes with the executive."""

    name = "planner"

    def __init__(
        self, planner: str | PlanFunction = "fast-downward", encoding: str = "classical",
        granularity: str = "stations", policy: str | Policy = "on_event", *,
        anticipate_switches: bool = False, timeout: float = 20.0, **executive_options: Any,
    ) -> None:
        if encoding not in ("classical", "temporal"):
            raise ConfigError(f"encoding must be 'classical' or 'temporal', got {encoding!r}")
        if granularity not in ("stations", "cells"):
            raise ConfigError(f"granularity must be 'stations' or 'cells', got {granularity!r}")
        self.planner_name = planner if isinstance(planner, str) else getattr(planner, "__name__", "custom")
        fn = planner if callable(planner) else compile_and_solve(
            planner, encoding, granularity, anticipate_switches, timeout)
        self.encoding, self.granularity = encoding, granularity
        self.executive = Executive(fn, Policy.parse(policy),
                                   anticipate_switches=anticipate_switches, **executive_options)

    def _reset(self, state: State) -> None:
        self.executive.reset(state, self.agent_ids)

    def act(self, state: State) -> list[int]:
        return self.executive.act(state)

    def observe(self, state: State, events: Sequence[object]) -> None:
        self.executive.observe(state, events)

    def info(self) -> dict[str, object]:
        return {"planner": self.planner_name, "encoding": self.encoding,
                "granularity": self.granularity, **self.executive.info()}


def make_planner_agent(arg: str | None, seed: int = 0) -> PlannerAgent:
    """Factory for ``planner:NAME[:GRANULARITY[:POLICY]]`` (the encoding follows the planner)."""
    parts = (arg or "fast-downward").split(":")
    name = parts[0] or "fast-downward"
    granularity = parts[1] if len(parts) > 1 and parts[1] else "stations"
    policy = parts[2] if len(parts) > 2 and parts[2] else "on_event"
    encoding = "classical"
    try:
        from ..planning.engines import get_planner

        encoding = get_planner(name).encoding
    except ImportError:  # pragma: no cover - planning layer missing
        pass
    return PlannerAgent(name, encoding, granularity, policy)


__all__ = ["PlannerAgent", "compile_and_solve", "make_planner_agent", "plan_steps",
           "step_from_record"]

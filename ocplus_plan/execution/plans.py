"""What the executive consumes: plan steps in simulator terms, planner outcomes, policies.

Kept apart from :mod:`.executive` so that the planning glue (``agents.planner``) and
tests can build plans without the execution machinery.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from ..errors import ConfigError
from ..sim.state import State

#: step kinds the executive understands; anything else is a generic "bump until something changes"
STEP_KINDS = ("pickup", "putdown", "chop", "wash", "plate", "deliver", "trash", "bump", "goto")


@dataclass(frozen=True)
class PlanStep:
    """One interaction of a plan in simulator terms (what the planning layer maps back to)."""

    index: int
    agent: int
    kind: str
    target: int  # flat cell to bump
    items: tuple[int, ...] = ()
    start: float | None = None  # planned start (steps after planning), for time-triggered plans
    duration: float | None = None
    #: for a ``goto`` step (a cell-level move of the plan): the cell it leaves
    via: int | None = None


@dataclass
class PlanOutcome:
    """What a planner call returns to the executive (a failure is data, not an exception)."""

    status: str  # "solved" or anything else (timeout, unsolvable, error, ...)
    steps: list[PlanStep] = field(default_factory=list)
    planning_time: float = 0.0
    message: str = ""
    #: planned on a kitchen with every switching cell open (``planning.spots.relaxed_state``):
    #: the plan already assumes the ways a layout switch opens and closes, so the executive
    #: waits for switches instead of replanning on them
    relaxed: bool = False
    #: the plan's work was scheduled with walks timed over the coming layout switches
    #: (``execution.schedule.schedule(switches=True)``): every switch on time is expected
    over_switches: bool = False
    #: the open orders the plan serves when it leaves some out on purpose (a chain of
    #: plans cut short; None: it stands for every open order): a cook that runs out of
    #: work while one is left out asks for a plan that takes it in
    orders: tuple[int, ...] | None = None

    @property
    def ok(self) -> bool:
        return self.status == "solved"


#: planner(state, driven agent ids, reason for planning) -> PlanOutcome
PlanFunction = Callable[[State, tuple[int, ...], str], PlanOutcome]


@dataclass(frozen=True)
class Policy:
    """When to ask for a new plan: ``on_event`` (any trigger), ``periodic(k)`` (every k
    steps), ``never`` (open loop: a new plan only once the current one is used up)."""

    kind: str = "on_event"
    period: int = 0

    @classmethod
    def parse(cls, spec: str | Policy) -> Policy:
        if isinstance(spec, Policy):
            return spec
        text = str(spec).strip().lower()
        if text in ("on_event", "never"):
            return cls(text)
        if text.startswith("periodic"):
            arg = text[len("periodic"):].strip("()= ")
            if arg.isdigit() and int(arg) > 0:
                return cls("periodic", int(arg))
        raise ConfigError(
            f"unknown replanning policy {spec!r}; use on_event, never or periodic(K) with K >= 1"
        )

    def __str__(self) -> str:
        return f"periodic({self.period})" if self.kind == "periodic" else self.kind


def touched(s: PlanStep, only_spot: Mapping[int, int] | None = None) -> set[tuple[str, int]]:
    """The cells (``("c", cell)``) and items (``("i", item)``) a step touches, and with
    ``only_spot`` the single floor cell its station is worked from (``("s", cell)``)."""
    out = {("c", s.target), *(("i", i) for i in s.items)}
    if s.via is not None:
        out.add(("c", s.via))
    elif only_spot and s.target in only_spot:
        out.add(("s", only_spot[s.target]))
    return out


def causal_dependencies(steps: Sequence[PlanStep],
                        only_spot: Mapping[int, int] | None = None) -> dict[int, frozenset[int]]:
    """For each step, the latest earlier step of every *other* agent that touches the same
    cell or item: the order a sequential plan relies on between agents. ``only_spot``
    (station cell -> the one floor cell it is worked from): two steps at stations worked
    from the same single cell touch that cell too (one cook stands there at a time: a cook
    chopping at a board holds the only way to the counter beside it)."""
    deps: dict[int, frozenset[int]] = {}
    for k, s in enumerate(steps):
        mine = touched(s, only_spot)
        need: dict[int, int] = {}
        for prev in steps[:k]:
            if prev.agent != s.agent and mine & touched(prev, only_spot):
                need[prev.agent] = prev.index
        deps[s.index] = frozenset(need.values())
    return deps


__all__ = ["STEP_KINDS", "PlanFunction", "PlanOutcome", "PlanStep", "Policy", "causal_dependencies", "touched"]

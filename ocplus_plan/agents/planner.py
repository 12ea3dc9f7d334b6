"""A planner-backed controller: compile the state, solve it, and let the executive run the plan.

``PlannerAgent("fast-downward", encoding="classical", granularity="stations",
policy="on_event")`` plans with any registered planner (``planning.engines``) on the
compiled problem (``planning.compile``), maps every plan action back to a simulator
interaction (:class:`~ocplus_plan.execution.executive.PlanStep`), schedules that work over
the driven cooks (:mod:`ocplus_plan.execution.schedule`) and hands the plan to an
:class:`~ocplus_plan.execution.executive.Executive`, which routes the agents,
monitors the world and replans. A planner failure is never an exception here: the
executive keeps the last valid plan and agents without work keep out of the way.

The plan function is :func:`~ocplus_plan.execution.planning_step.compile_and_solve`; the
spec is parsed once by :class:`~ocplus_plan.execution.spec.PlannerSpec`. Registered as
``planner`` in :data:`ocplus_plan.agents.FACTORIES`: ``planner:`` (the default planner,
:data:`~ocplus_plan.execution.spec.DEFAULT_PLANNER`), ``planner:fast-downward``,
``planner:kairos`` (temporal), or ``planner:NAME:GRANULARITY:POLICY:OPTIONS`` for the rest
(OPTIONS joined by ``+``: ``anticipate``, ``one-cook``, ``chainK``, ``no-schedule``,
``over-switches``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..errors import ConfigError
from ..execution.executive import Executive, PlanFunction, Policy
from ..execution.planning_step import (
    compile_and_solve,
    hand_effects,
    orders_to_plan,
    plan_entries,
    renumber,
    steps_from_record,
)
from ..execution.spec import DEFAULT_PLANNER, PLANNER_OPTIONS, PlannerSpec, parse_options
from ..sim.state import State
from .base import Controller
from .partner_model import PartnerModel


class PlannerAgent(Controller):
    """A controller that plans with a named planner and executes with the executive."""

    name = "planner"

    def __init__(
        self, planner: str | PlanFunction = DEFAULT_PLANNER, encoding: str = "classical",
        granularity: str = "stations", policy: str | Policy = "on_event", *,
        anticipate_switches: bool = False, timeout: float = 10.0,
        orders_per_plan: int | str | None = "auto", schedule_cooks: bool = True,
        plan_cooks: str = "all", chain_orders: int = 1, over_switches: bool | None = None,
        model_partners: bool = True, **executive_options: Any,
    ) -> None:
        from ..planning.model import ENCODINGS, GRANULARITIES

        if encoding not in ENCODINGS:
            raise ConfigError(f"encoding must be one of {ENCODINGS}, got {encoding!r}")
        if granularity not in GRANULARITIES:
            raise ConfigError(f"granularity must be one of {GRANULARITIES}, got {granularity!r}")
        self.planner_name = planner if isinstance(planner, str) else getattr(planner, "__name__", "custom")
        fn = planner if callable(planner) else compile_and_solve(
            planner, encoding, granularity, anticipate_switches, timeout,
            orders_per_plan=orders_per_plan, schedule_cooks=schedule_cooks,
            plan_cooks=plan_cooks, chain_orders=chain_orders, over_switches=over_switches)
        self.encoding, self.granularity = encoding, granularity
        self.executive = Executive(fn, Policy.parse(policy),
                                   anticipate_switches=anticipate_switches, **executive_options)
        self.model_partners = model_partners
        self.known_partner: Controller | None = None

    def model_partner(self, partner: Controller | None) -> None:
        """The controller that plays the cooks this one does not drive, when it is known
        (``with_partner`` says): the partner model then predicts it by its own policy."""
        self.known_partner = partner

    def _reset(self, state: State) -> None:
        self.executive.reset(state, self.agent_ids)
        self.executive.partner_model = None
        if self.model_partners and len(self.agent_ids) < state.n_agents:
            model = PartnerModel(self.known_partner)
            model.reset(state, self.agent_ids)
            self.executive.partner_model = model

    def act(self, state: State) -> list[int]:
        return self.executive.act(state)

    def observe(self, state: State, events: Sequence[object]) -> None:
        self.executive.observe(state, events)

    def info(self) -> dict[str, object]:
        cpu = getattr(self.executive.planner, "cpu_seconds", None)
        proven = getattr(self.executive.planner, "proven", None)
        return {"planner": self.planner_name, "encoding": self.encoding,
                "granularity": self.granularity, **self.executive.info(),
                **({"planning_cpu_s": round(cpu[0], 4)} if cpu else {}),
                **(proven.info() if proven is not None else {})}


def parse_planner_options(text: str, spec: str) -> dict[str, Any]:
    """``anticipate+one-cook+chain2`` -> PlannerAgent keywords (see :data:`PLANNER_OPTIONS`)."""
    return parse_options(text, spec)


def planner_name(arg: str | None) -> str:
    """The planner a ``planner:NAME[:GRANULARITY[:POLICY[:OPTIONS]]]`` argument names."""
    return PlannerSpec.parse(arg).name


def make_planner_agent(arg: str | None | PlannerSpec, seed: int = 0,
                       **options: Any) -> PlannerAgent:
    """Factory for ``planner:NAME[:GRANULARITY[:POLICY[:OPTIONS]]]`` (the encoding follows the
    planner; OPTIONS joined by '+': ``anticipate`` plans around the coming layout switches,
    temporal only; ``one-cook``, ``chainK``, ``no-schedule``: see :func:`compile_and_solve`).
    ``options`` go to :class:`PlannerAgent` (e.g. ``timeout``, CPU seconds per call)."""
    spec = arg if isinstance(arg, PlannerSpec) else PlannerSpec.parse(arg)
    encoding = "classical"
    try:
        from ..planning.engines import get_planner

        encoding = get_planner(spec.name).encoding
    except ImportError:  # pragma: no cover - planning layer missing
        pass
    if spec.anticipate_switches and encoding != "temporal":
        raise ConfigError(f"planner:{spec.text}: anticipating layout switches needs a temporal "
                          f"planner (timed initial literals); {spec.name} is {encoding}")
    return PlannerAgent(spec.name, encoding, spec.granularity, spec.policy,
                        **spec.agent_keywords(), **options)


__all__ = ["PLANNER_OPTIONS", "PlannerAgent", "PlannerSpec", "compile_and_solve", "hand_effects",
           "make_planner_agent", "orders_to_plan", "plan_entries", "planner_name", "renumber",
           "steps_from_record"]

"""The planner spec ``planner:NAME[:GRANULARITY[:POLICY[:OPTIONS]]]``, parsed once.

:meth:`PlannerSpec.parse` reads the text after ``planner:`` into a frozen record; the agent
factory, the evaluation runner's availability check and the benchmarks all use it, so a
spec is read the same way everywhere. OPTIONS are joined by ``+`` (:data:`PLANNER_OPTIONS`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from ..errors import ConfigError

#: the planner a spec with an empty NAME field names
DEFAULT_PLANNER = "fast-downward-wastar"
#: the fourth field of ``planner:NAME:GRANULARITY:POLICY:OPTIONS`` (options joined by '+')
PLANNER_OPTIONS = ("anticipate", "one-cook", "chainK", "no-schedule", "over-switches",
                   "no-over-switches", "no-partner-model")

_HELP = ("options, joined by '+': anticipate (temporal: plan around the coming layout "
         "switches), one-cook (model one cook, schedule its plan over all), chainK (plan up "
         "to K orders one after the other), no-schedule (keep the cooks the planner chose), "
         "over-switches / no-over-switches (schedule walks over the coming layout switches "
         "or not; default: on for a chained plan on a switching map), no-partner-model (cooks "
         "the controller does not drive are obstacles that stand still, not predicted)")


@dataclass(frozen=True)
class PlannerSpec:
    """One planner configuration: which planner, at which granularity, replanning policy and
    options. ``over_switches=None`` is the default (see :meth:`over_switches_for`)."""

    name: str = DEFAULT_PLANNER
    granularity: str = "stations"
    policy: str = "on_event"
    anticipate_switches: bool = False
    plan_cooks: str = "all"
    chain_orders: int = 1
    schedule_cooks: bool = True
    over_switches: bool | None = None
    model_partners: bool = True
    text: str = field(default="", compare=False)

    @classmethod
    def parse(cls, text: str | None) -> PlannerSpec:
        """``NAME[:GRANULARITY[:POLICY[:OPTIONS]]]`` (the text after ``planner:``)."""
        raw = text or ""
        parts = raw.split(":")
        if len(parts) > 4:
            raise ConfigError(f"planner:{raw}: at most four fields "
                              "(planner:NAME:GRANULARITY:POLICY:OPTIONS)")
        parts += [""] * (4 - len(parts))
        options = parse_options(parts[3], raw)
        return cls(name=parts[0] or DEFAULT_PLANNER, granularity=parts[1] or "stations",
                   policy=parts[2] or "on_event", text=raw, **options)

    def with_options(self, **changes: Any) -> PlannerSpec:
        """The same spec with some fields changed (its text rewritten to match)."""
        out = replace(self, **changes)
        return replace(out, text=out.spec_text())

    def options_text(self) -> str:
        """The OPTIONS field that gives this spec's options (empty for the defaults)."""
        flags = (("anticipate", self.anticipate_switches), ("one-cook", self.plan_cooks == "one"),
                 (f"chain{self.chain_orders}", self.chain_orders > 1),
                 ("over-switches", self.over_switches is True),
                 ("no-over-switches", self.over_switches is False),
                 ("no-schedule", not self.schedule_cooks),
                 ("no-partner-model", not self.model_partners))
        return "+".join(name for name, on in flags if on)

    def spec_text(self) -> str:
        """``NAME:GRANULARITY:POLICY[:OPTIONS]`` for this spec."""
        opts = self.options_text()
        return f"{self.name}:{self.granularity}:{self.policy}" + (f":{opts}" if opts else "")

    def over_switches_for(self, dynamic: bool) -> bool:
        """Are walks scheduled over the coming switches on a map that does (not) switch?"""
        return walks_over_switches(self.over_switches, self.chain_orders, dynamic)

    def agent_keywords(self) -> dict[str, Any]:
        """Keyword arguments of :class:`~ocplus_plan.agents.planner.PlannerAgent` beyond the
        planner, encoding, granularity and policy."""
        return {"anticipate_switches": self.anticipate_switches, "plan_cooks": self.plan_cooks,
                "chain_orders": self.chain_orders, "schedule_cooks": self.schedule_cooks,
                "over_switches": self.over_switches, "model_partners": self.model_partners}


def walks_over_switches(option: bool | None, chain_orders: int, dynamic: bool) -> bool:
    """``over-switches`` on a map that does (not) switch: as the option says, and by default
    (None) on for a chained plan (chain2 and more), where it pays, off for a one-order plan,
    where it costs (hard, 2 cooks, 3 seeds: 1.67 dishes against 2.33 without; chain2 with it
    2.67; docs/executive.md)."""
    if not dynamic:
        return False
    return chain_orders > 1 if option is None else option


def parse_options(text: str, spec: str = "") -> dict[str, Any]:
    """``anticipate+one-cook+chain2`` -> :class:`PlannerSpec` fields (see
    :data:`PLANNER_OPTIONS`); only the options named are returned."""
    out: dict[str, Any] = {}
    for token in filter(None, text.split("+")):
        if token == "anticipate":
            out["anticipate_switches"] = True
        elif token == "one-cook":
            out["plan_cooks"] = "one"
        elif token == "no-schedule":
            out["schedule_cooks"] = False
        elif token == "over-switches":
            out["over_switches"] = True
        elif token == "no-over-switches":
            out["over_switches"] = False
        elif token == "no-partner-model":
            out["model_partners"] = False
        elif token.startswith("chain") and token[5:].isdigit() and int(token[5:]) >= 1:
            out["chain_orders"] = int(token[5:])
        else:
            raise ConfigError(f"planner:{spec}: unknown option {token!r} in the fourth field; "
                              + _HELP)
    return out


__all__ = ["DEFAULT_PLANNER", "PLANNER_OPTIONS", "PlannerSpec", "parse_options",
           "walks_over_switches"]

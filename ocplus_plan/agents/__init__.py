"""Controllers with one interface (see :mod:`.base`) and a registry by name.

Names: ``random``, ``stay``, ``greedy``, ``nearest`` (the greedy cook's skills, each free cook
on its current or nearest subtask: :mod:`.task_choice` without a policy), ``planner:NAME``,
``ppo:PATH`` and
``llm:MODULE:FUNCTION[:MODE]`` (a language model given as a callable) in
:data:`FACTORIES` (``kind`` -> factory taking the text after the colon).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..errors import ConfigError
from .base import (
    PARTNER_ALIASES,
    Controller,
    Episode,
    RandomAgent,
    StayAgent,
    Team,
    run_episode,
)

#: agent kind -> factory(argument after ':' or None, seed) -> Controller
FACTORIES: dict[str, Callable[[str | None, int], Controller]] = {
    "random": lambda arg, seed: RandomAgent(seed),
    "stay": lambda arg, seed: StayAgent(),
    "planner": lambda arg, seed: __import__("ocplus_plan.agents.planner", fromlist=["x"]).make_planner_agent(arg, seed),
    "greedy": lambda arg, seed: __import__("ocplus_plan.agents.greedy", fromlist=["x"]).GreedyAgent(seed),
    "nearest": lambda arg, seed: __import__("ocplus_plan.agents.task_choice", fromlist=["x"]).TaskChoice(seed),
    "llm": lambda arg, seed: __import__("ocplus_plan.agents.llm", fromlist=["x"]).make_llm_agent(arg, seed),
    "ppo": lambda arg, seed: __import__("ocplus_plan.agents.ppo", fromlist=["x"]).make_ppo_agent(arg, seed),
}


def make_controller(spec: str, seed: int = 0) -> Controller:
    """Build a controller from a name such as ``random`` or ``planner:fast-downward``."""
    kind, _, arg = spec.partition(":")
    if kind not in FACTORIES:
        raise ConfigError(
            f"unknown agent {spec!r}; known agents: {', '.join(sorted(FACTORIES))} "
            "(planner:NAME, ppo:PATH and llm:MODULE:FUNCTION take an argument)"
        )
    return FACTORIES[kind](arg or None, seed)


def with_partner(controller: Controller, partner: str | Controller | None, n_agents: int,
                 seed: int = 0) -> Any:
    """``controller`` drives every cook but the last, which ``partner`` plays (a controller or
    an agent name: ``idle``, ``random``, ``greedy``, ``ppo:PATH``, ...); without a partner,
    ``controller`` drives them all. The controller does not drive the partner's cook: a
    planner-backed one plans around it as a moving obstacle (ad-hoc teamwork)."""
    if partner is None:
        return controller
    if n_agents < 2:
        raise ConfigError(f"a partner plays the last cook beside the agent's: the kitchen needs "
                          f"at least 2 cooks, it has {n_agents} (raise --n-agents)")
    if isinstance(partner, str):
        partner = make_controller(PARTNER_ALIASES.get(partner, partner), seed)
    if hasattr(controller, "model_partner"):
        controller.model_partner(partner)  # a planner-backed one predicts it by its policy
    return [(controller, list(range(n_agents - 1))), (partner, [n_agents - 1])]


__all__ = ["FACTORIES", "Controller", "Episode", "RandomAgent", "StayAgent", "Team", "make_controller",
           "run_episode", "with_partner"]

"""Small hand-drawn kitchens for one-behaviour rule tests."""

from __future__ import annotations

from typing import Any

import pytest

from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import Action

R, D, L, U, S = (int(a) for a in (Action.RIGHT, Action.DOWN, Action.LEFT, Action.UP, Action.STAY))


def kitchen(grid: list[list[int]], spawns: list[list[int]], *, preset: str = "easy",
            switch: list[list[int]] | None = None, switch_step: int = 15, seed: int = 0,
            **overrides: Any):
    """Rules + initial state for a map given inline (a dict, as a YAML file would load)."""
    spec: dict[str, Any] = {"name": "test", "game_map": grid, "agent_spawn_points": spawns}
    if switch is not None:
        spec.update(switch_map=switch, is_dynamic_map=True, map_switch_step=switch_step)
    overrides.setdefault("n_agents", len(spawns))
    rules = make_rules(preset, map=spec, **overrides)
    return rules, new_state(rules, seed)


@pytest.fixture
def make_kitchen():
    return kitchen

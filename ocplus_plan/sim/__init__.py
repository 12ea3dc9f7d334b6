"""The pure simulator core: stdlib + numpy (+ pyyaml when a map file is read).

Typical use::

    from ocplus_plan.sim import make_rules, new_state, transition
    rules = make_rules("hard", n_agents=2)
    state = new_state(rules, seed=0)
    result = transition(state, [0, 4])   # agent 0 right, agent 1 stays
"""

from __future__ import annotations

from .codes import Action, Cell, Item, ItemState, Where
from .kitchens import load_kitchen
from .maps import Layout, available_maps, load_map
from .rules import PRESETS, Rewards, Rules, make_rules, recipe_name
from .state import Event, Geometry, Order, State, conservation_problems, new_state
from .step import StepResult, transition

__all__ = [
    "PRESETS",
    "Action",
    "Cell",
    "Event",
    "Geometry",
    "Item",
    "ItemState",
    "Layout",
    "Order",
    "Rewards",
    "Rules",
    "State",
    "StepResult",
    "Where",
    "available_maps",
    "conservation_problems",
    "load_kitchen",
    "load_map",
    "make_rules",
    "new_state",
    "recipe_name",
    "transition",
]

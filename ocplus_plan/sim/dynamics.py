"""Layout switching (SPEC section 5, "Dynamic layout").

Every ``map_switch_step`` steps the layout alternates between the main and the
switch grid. A due switch waits, and is retried each step, while an agent stands
on a cell that would stop being walkable or an item lies on a counter that would
stop being a counter. After a switch happens at step ``t`` the next one is due at
``t + map_switch_step`` (so a wait delays the whole schedule, never shortens a phase).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .codes import Cell
from .records import Event

if TYPE_CHECKING:
    from .state import State


def switch_blockers(state: State) -> list[tuple[int, int]]:
    """Cells that prevent switching to the other layout right now."""
    geo = state.geo
    if len(geo.terrains) < 2:
        return []
    new = 1 - state.layout_index
    new_walk = geo.walkables[new]
    old_t, new_t = geo.terrains[state.layout_index], geo.terrains[new]
    out = []
    for f in geo.switch_cells:
        if not new_walk[f] and f in state.agent_pos:
            out.append(geo.rc(f))
        elif old_t[f] == Cell.COUNTER and new_t[f] != Cell.COUNTER and state.cell_item[f] >= 0:
            out.append(geo.rc(f))
    return out


def maybe_switch(state: State, events: list[Event], *, force: bool = False) -> bool:
    """Switch the layout if one is due (or ``force``) and nothing blocks it."""
    if not force and (not state.rules.dynamic or state.t < state.next_switch):
        return False
    if len(state.geo.terrains) < 2:
        return False
    blockers = switch_blockers(state)
    if blockers:
        events.append(Event("switch_waiting", -1, blockers[0], -1, len(blockers)))
        return False
    state.layout_index = 1 - state.layout_index
    state.next_switch = state.t + state.rules.map_switch_step
    state.stats["layout_switches"] += 1
    events.append(Event("layout_switch", -1, None, -1, state.layout_index))
    return True

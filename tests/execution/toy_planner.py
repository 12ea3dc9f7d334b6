"""A tiny hand-written planner for single-ingredient orders, so the executive can be tested
without the planning layer: it returns the same kind of steps the real map-back gives."""

from __future__ import annotations

from ocplus_plan.execution.executive import PlanOutcome, PlanStep
from ocplus_plan.sim.codes import Cell, Item, ItemState, Where
from ocplus_plan.sim.state import State


def _cells(state: State, code: Cell) -> list[int]:
    return [c for c, v in enumerate(state.geo.terrains[0]) if v == code]


def toy_planner(state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
    """Serve the first open order (one vegetable or one steak) with the first driven agent;
    first throw away a burnt steak if there is one."""
    geo = state.geo
    a = agents[0]
    seq: list[tuple[str, int, tuple[int, ...]]] = []
    held = state.agent_hand[a]
    if held >= 0:  # start empty-handed: a burnt thing goes to the trash, the rest to a counter
        trash = _cells(state, Cell.TRASH)
        if state.item_state[held] == ItemState.BURNT and trash:
            seq.append(("trash", trash[0], (held,)))
        else:
            walk = geo.walkables[state.layout_index]
            free = [c for c in _cells(state, Cell.COUNTER) if state.cell_item[c] < 0
                    and any(n >= 0 and walk[n] for n in geo.neighbors[c])]
            seq.append(("putdown", free[0], (held,)))
    for pan in geo.pans:
        it = state.cell_item[pan]
        if it >= 0 and state.item_state[it] == ItemState.BURNT:
            seq += [("pickup", pan, (it,)), ("trash", _cells(state, Cell.TRASH)[0], (it,))]
            steps = [PlanStep(i, a, k, c, it) for i, (k, c, it) in enumerate(seq)]
            return PlanOutcome("solved", steps, 0.001)  # the steak respawns: plan again then
    kind = int(state.orders[0].recipe[0])
    item = next((i for i, k in enumerate(geo.item_kind)
                 if k == kind and state.item_where[i] == Where.CELL
                 and state.item_state[i] != ItemState.BURNT), None)
    plate = next(i for i, k in enumerate(geo.item_kind) if k == Item.PLATE)
    deliver = _cells(state, Cell.DELIVERY)[0]
    if item is None:
        return PlanOutcome("unsolvable", [], 0.0, "no ingredient available")
    if kind == Item.STEAK:
        station = geo.pans[0]
    else:
        station = _cells(state, Cell.BOARD)[0]
    if state.item_loc[item] != station:
        seq += [("pickup", state.item_loc[item], (item,)), ("putdown", station, (item,))]
    if kind != Item.STEAK:
        seq.append(("chop", station, (item,)))
    seq += [("pickup", state.item_loc[plate], (plate,)), ("plate", station, (item, plate)),
            ("deliver", deliver, (plate,))]
    steps = [PlanStep(i, a, k, c, it) for i, (k, c, it) in enumerate(seq)]
    return PlanOutcome("solved", steps, 0.001)


def failing_planner(state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
    return PlanOutcome("timeout", [], 0.01, "gave up")


def crashing_planner(state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
    raise RuntimeError("planner process died")

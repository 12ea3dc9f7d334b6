"""Changes of strategy when the cooks get nowhere: one cook gives way, a stall's strategies,
and the cook that gave way brought back into the plans when its time is up.

The executive (:mod:`.executive`) calls these with itself; they read and change its task
queues, its give-ways (``yielding``: cook -> the step until which it is left out of the
plans) and its counts (docs/executive.md, "Livelock" and "Stalls").
"""

from __future__ import annotations

from typing import Any

from ..sim.state import State
from .stall import STALL_PATIENCE

#: steps a cook that gives way is left out of the plans, in units of ``block_patience``
GIVE_WAY_SPANS = 4


def give_way(ex: Any, state: State) -> bool:
    """After a livelock one cook gives way: it is left out of the plans for a while (it
    steps aside with nothing to do) and the others get the work. Cooks with a free hand
    give way first (nothing they carry is held up); a livelock that comes back makes the
    next cook give way instead. False when fewer than two of ours have work."""
    busy = [a for a in ex.agent_ids if ex.queues[a] and ex.yielding.get(a, -1) <= state.t]
    if len(busy) < 2:
        return False
    order = sorted(busy, key=lambda a: (state.agent_hand[a] >= 0, -a))
    cook = order[ex.gave_way % len(order)]
    ex.gave_way += 1
    ex.yielding[cook] = state.t + GIVE_WAY_SPANS * ex.block_patience
    return True


def stall_strategy(ex: Any, state: State, stalled: int) -> str:
    """A stall of ``stalled`` steps changes strategy, a new one each time it lasts on:
    give way (a lone cook beside partners hands off what it holds; with a free hand it has
    nothing to hand off), model every cook with one order at a time on cells
    (``stall_all``), re-allocate. Returns the reason the next planner call is made for."""
    turn = stalled // STALL_PATIENCE - 1
    if turn % 3 == 0 and give_way(ex, state):
        ex.stall_strategies["give_way"] += 1
        return "stall"
    if turn % 3 == 0 and len(ex.agent_ids) == 1 < state.n_agents \
            and state.agent_hand[ex.agent_ids[0]] >= 0:
        ex.stall_strategies["hand_off"] += 1
        return "livelock"  # one cook of ours beside partners: hand off and wait
    if turn % 3 <= 1:
        ex.stall_strategies["every_cook"] += 1
        return "stall_all"
    ex.stall_strategies["reallocate"] += 1
    for a in ex.agent_ids:
        ex.queues[a].clear()
    ex.yielding.clear()
    return "stall_all"


def rejoining(ex: Any, state: State) -> bool:
    """Does a cook's give-way end now while it has nothing to do and another of ours still
    has work? Then it is planned for again (``rejoin``): the plan made while it stood aside
    gave it nothing, and no other trigger would give it work before that plan is done."""
    back = [a for a, until in ex.yielding.items() if until == state.t and not ex.queues[a]]
    return bool(back) and any(ex.queues[b] for b in ex.agent_ids if b not in back)


__all__ = ["GIVE_WAY_SPANS", "give_way", "rejoining", "stall_strategy"]

"""The transition function (SPEC sections 3-6).

``transition(state, joint_action)`` updates ``state`` in place and returns a
:class:`StepResult` with the step's events and per-agent rewards. Order of a
step: bumps in agent-index order (then waiting items respawn on freed tiles),
simultaneous moves, pans tick, the layout switch is considered, orders expire,
the horizon is checked.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

from ..errors import InvalidActionError
from .codes import Action, Item, ItemState, Where
from .dynamics import maybe_switch
from .orders import draw_order, expire_orders, matching_order, plate_recipe
from .queries import Bump, bump_effect
from .state import Event, State

_CELL, _HAND, _PLATE, _WAITING = int(Where.CELL), int(Where.HAND), int(Where.PLATE), int(Where.WAITING)
_FRESH, _CLEAN, _DIRTY = int(ItemState.FRESH), int(ItemState.CLEAN), int(ItemState.DIRTY)
_PLATE_KIND = int(Item.PLATE)
_STAY = int(Action.STAY)


class StepResult(NamedTuple):
    events: list[Event]
    rewards: list[float]
    terminated: bool
    truncated: bool


def transition(state: State, joint_action: Sequence[int]) -> StepResult:
    """Apply one joint action (one action index per agent) to ``state`` in place."""
    n = len(state.agent_pos)
    if len(joint_action) != n:
        raise InvalidActionError(
            f"joint action has {len(joint_action)} entries but there are {n} agents"
        )
    rules = state.rules
    geo = state.geo
    rewards = [rules.rewards.step_penalty] * n
    events: list[Event] = []
    pos = state.agent_pos
    walk = geo.walkables[state.layout_index]
    nbrs = geo.neighbors
    targets = [-1] * n
    moving = False
    for a in range(n):
        act = int(joint_action[a])
        if act == _STAY:
            continue
        if not 0 <= act < 4:
            raise InvalidActionError(
                f"agent {a}: action {joint_action[a]!r} is not one of 0 right, 1 down, 2 left, "
                "3 up, 4 stay"
            )
        tgt = nbrs[pos[a]][act]
        if tgt < 0:
            continue
        if walk[tgt]:
            targets[a] = tgt
            moving = True
        else:
            _interact(state, a, tgt, rewards, events)

    if _WAITING in state.item_where:
        _respawn_waiting(state, events)
    if moving:
        _resolve_moves(state, targets, events)

    for p in geo.timed:
        it = state.cell_item[p]
        if it >= 0:
            _tick(state, it, p, rewards, events)

    state.t += 1
    if rules.dynamic:
        maybe_switch(state, events)
    if rules.order_time_limit is not None:
        expire_orders(state, rewards, events)

    if rules.reward_mode == "shared":
        total = sum(rewards)
        rewards = [total] * n
    terminated = (
        rules.stop_after_orders is not None
        and state.stats["orders_completed"] >= rules.stop_after_orders
    )
    truncated = not terminated and state.t >= rules.horizon
    return StepResult(events, rewards, terminated, truncated)


# ---------------------------------------------------------------- moves
def _resolve_moves(state: State, targets: list[int], events: list[Event]) -> None:
    """Simultaneous moves: contested cells, swaps and cycles block everyone involved; a
    mover may follow an agent that leaves its cell. Independent of agent order."""
    pos = state.agent_pos
    n = len(pos)
    occupant = {pos[a]: a for a in range(n)}
    count: dict[int, int] = {}
    for t in targets:
        if t >= 0:
            count[t] = count.get(t, 0) + 1
    # status: 0 undecided, 1 moves, 2 stays (or not a mover)
    status = [0 if targets[a] >= 0 and count[targets[a]] == 1 else 2 for a in range(n)]
    contested = [a for a in range(n) if targets[a] >= 0 and status[a] == 2]
    for a in range(n):
        if status[a] != 0:
            continue
        chain = [a]
        b = occupant.get(targets[a], -1)
        while b >= 0 and status[b] == 0 and b not in chain:
            chain.append(b)
            b = occupant.get(targets[b], -1)
        ok = b < 0 or status[b] == 1
        for c in chain:
            status[c] = 1 if ok else 2
    for a in range(n):
        if status[a] == 1:
            pos[a] = targets[a]
        elif targets[a] >= 0:
            why = "contested" if a in contested else "occupied"
            events.append(Event("move_blocked", a, state.geo.rc(targets[a]), -1, why))


# ---------------------------------------------------------------- interactions
def apply_bump(state: State, a: int, cell: int) -> list[Event]:
    """Cook ``a`` bumps the non-walkable ``cell`` as a step's interaction would (no move, no
    tick, no switch): what a model of the cook uses to apply its predicted next bump to a
    copy of the state with the simulator's own rules. The events it made."""
    events: list[Event] = []
    _interact(state, a, cell, [0.0] * state.n_agents, events)
    return events


def _interact(state: State, a: int, cell: int, rewards: list[float], events: list[Event]) -> None:
    """Agent ``a`` bumps the non-walkable ``cell``: do what :func:`bump_effect` says."""
    held = state.agent_hand[a]
    effect = bump_effect(state, held, cell)
    if effect == Bump.NOTHING:
        return
    here = state.cell_item[cell]
    if effect == Bump.PICK_UP:
        _pick(state, a, cell, here, events)
    elif effect == Bump.PUT_DOWN:
        _put(state, a, cell, held, events)
    elif effect == Bump.ONTO_PLATE:
        state.agent_hand[a] = -1
        state.item_where[held] = _PLATE
        state.item_loc[held] = here
        events.append(Event("plate_add", a, state.geo.rc(cell), held, here))
    elif effect == Bump.TAKE_ONTO_PLATE:
        state.cell_item[cell] = -1
        state.item_where[here] = _PLATE
        state.item_loc[here] = held
        state.item_agent[here] = a
        events.append(Event("plate_add", a, state.geo.rc(cell), here, held))
    elif effect == Bump.CHOP or effect == Bump.WASH or effect == Bump.WORK:
        _advance(state, a, cell, here, rewards, events)
    elif effect == Bump.DELIVER:
        _deliver(state, a, cell, held, rewards, events)
    elif effect == Bump.TRASH:
        _trash(state, a, cell, held, events)


def _pick(state: State, a: int, cell: int, item: int, events: list[Event]) -> None:
    state.cell_item[cell] = -1
    state.agent_hand[a] = item
    state.item_where[item] = _HAND
    state.item_loc[item] = a
    state.item_agent[item] = a
    events.append(Event("pickup", a, state.geo.rc(cell), item))


def _put(state: State, a: int, cell: int, item: int, events: list[Event]) -> None:
    state.agent_hand[a] = -1
    state.cell_item[cell] = item
    state.item_where[item] = _CELL
    state.item_loc[item] = cell
    events.append(Event("putdown", a, state.geo.rc(cell), item))


def _advance(state: State, a: int, cell: int, item: int, rewards: list[float],
             events: list[Event]) -> None:
    """One unit of work of the bump-driven process of ``cell``'s station; its record's
    duration of them finishes it."""
    tables = state.rules.tables
    p = tables.by_code[state.geo.terrains[state.layout_index][cell]]
    process = tables.processes[p]
    state.item_progress[item] += 1
    state.item_agent[item] = a
    if state.item_progress[item] >= tables.duration[p]:
        state.item_state[item] = tables.done_state[p]
        state.item_progress[item] = 0
        state.stats[process.stat] += 1
        rewards[a] += state.rules.rewards.subtask_finished
        events.append(Event(process.verb + "_done", a, state.geo.rc(cell), item))
    else:
        events.append(Event(process.verb, a, state.geo.rc(cell), item, state.item_progress[item]))


def _tick(state: State, item: int, cell: int, rewards: list[float], events: list[Event]) -> None:
    """One tick of the time-driven process of ``cell``'s station (the pan): done after its
    duration, overrun (burnt) on the tick that takes it past its overrun time."""
    tables = state.rules.tables
    p = tables.by_code[state.geo.terrains[0][cell]]
    process = tables.processes[p]
    r = state.rules.rewards
    ticks = state.item_progress[item] + 1
    state.item_progress[item] = ticks
    st = state.item_state[item]
    owner = state.item_agent[item]
    if st == process.takes_state and ticks >= tables.duration[p]:
        st = state.item_state[item] = tables.done_state[p]
        state.stats[process.stat] += 1
        if owner >= 0:
            rewards[owner] += r.subtask_finished
        events.append(Event(process.verb + "_done", owner, state.geo.rc(cell), item))
    over = tables.overrun_state[p]
    if over >= 0 and st != over and ticks > tables.overrun[p]:
        state.item_state[item] = over
        state.stats[process.overrun_stat] += 1
        if owner >= 0:
            rewards[owner] += r.burned_penalty
        events.append(Event("burnt", owner, state.geo.rc(cell), item))


def _send_home(state: State, item: int, item_state: int, events: list[Event]) -> None:
    """Respawn an item fresh (or a plate clean/dirty) at its spawn tile, or queue it."""
    home = state.geo.item_home[item]
    state.item_state[item] = item_state
    state.item_progress[item] = 0
    state.item_agent[item] = -1
    if state.cell_item[home] < 0:
        state.cell_item[home] = item
        state.item_where[item] = _CELL
        state.item_loc[item] = home
        events.append(Event("respawn", -1, state.geo.rc(home), item))
    else:
        state.item_where[item] = _WAITING
        state.item_loc[item] = home
        events.append(Event("respawn_waiting", -1, state.geo.rc(home), item))


def _respawn_waiting(state: State, events: list[Event]) -> None:
    where, loc = state.item_where, state.item_loc
    for i in range(len(where)):
        if where[i] == _WAITING and state.cell_item[loc[i]] < 0:
            state.cell_item[loc[i]] = i
            where[i] = _CELL
            events.append(Event("respawn", -1, state.geo.rc(loc[i]), i))


def _trash(state: State, a: int, cell: int, held: int, events: list[Event]) -> None:
    """A held ingredient goes back fresh to its spawn tile; a held plate is emptied (an
    empty one is never trashed: :func:`bump_effect`)."""
    if state.geo.item_kind[held] == _PLATE_KIND:
        contents = state.plate_contents(held)
        for i in contents:
            _send_home(state, i, _FRESH, events)
        events.append(Event("trash", a, state.geo.rc(cell), held, len(contents)))
        return
    state.agent_hand[a] = -1
    events.append(Event("trash", a, state.geo.rc(cell), held, 1))
    _send_home(state, held, _FRESH, events)


def _deliver(
    state: State, a: int, cell: int, held: int, rewards: list[float], events: list[Event]
) -> None:
    r = state.rules.rewards
    idx = -1
    if state.geo.item_kind[held] == _PLATE_KIND:
        idx = matching_order(state, plate_recipe(state, held))
    if idx < 0:
        state.stats["wrong_deliveries"] += 1
        rewards[a] += r.wrong_delivery
        events.append(Event("wrong_delivery", a, state.geo.rc(cell), held))
        return
    order = state.orders.pop(idx)
    state.stats["dishes_served"] += 1
    state.stats["orders_completed"] += 1
    rewards[a] += state.rules.reward_of.get(order.recipe, r.correct_delivery)  # the dish's
    events.append(Event("delivery", a, state.geo.rc(cell), held, order.order_id))
    for i in state.plate_contents(held):
        _send_home(state, i, _FRESH, events)
    state.agent_hand[a] = -1
    _send_home(state, held, _DIRTY if state.rules.dirty_plates else _CLEAN, events)
    draw_order(state, order)
    events.append(Event("order_new", -1, None, -1, state.orders[-1].order_id))


__all__ = ["StepResult", "apply_bump", "transition"]

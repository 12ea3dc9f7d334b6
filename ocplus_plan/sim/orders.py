"""Orders (SPEC section 4): drawing from the seeded RNG, matching plates, expiry."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .codes import Item, ItemState, Where
from .records import Event
from .state import draw_order

if TYPE_CHECKING:
    from .state import State


def plate_recipe(state: State, plate: int) -> tuple[Item, ...] | None:
    """The recipe a plate would serve, or None when it cannot serve any (dirty, empty,
    or holding an ingredient that is not in its ready state)."""
    if state.item_state[plate] != ItemState.CLEAN:
        return None
    kinds, ready = state.geo.item_kind, state.rules.tables.plateable_list
    where, loc, st = state.item_where, state.item_loc, state.item_state
    contents = []
    for i in range(len(where)):
        if where[i] == Where.PLATE and loc[i] == plate:
            kind = Item(kinds[i])
            if not ready[kind][st[i]]:
                return None
            contents.append(kind)
    return tuple(sorted(contents)) if contents else None


def matching_order(state: State, recipe: tuple[Item, ...] | None) -> int:
    """Index in ``state.orders`` of the oldest order with exactly this recipe, or -1."""
    if recipe is None:
        return -1
    for idx, order in enumerate(state.orders):
        if order.recipe == recipe:
            return idx
    return -1


def expire_orders(state: State, rewards: list[float], events: list[Event]) -> None:
    """Replace every order whose deadline has come; the penalty is split over the team."""
    t = state.t
    expired = [o for o in state.orders if 0 <= o.deadline <= t]
    if not expired:
        return
    n = len(rewards)
    share = state.rules.rewards.order_expired / n
    for order in expired:
        state.orders.remove(order)
        state.stats["orders_expired"] += 1
        for a in range(n):
            rewards[a] += share
        events.append(Event("order_expired", -1, None, -1, order.order_id))
        draw_order(state, order)
        events.append(Event("order_new", -1, None, -1, state.orders[-1].order_id))

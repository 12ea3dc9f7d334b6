"""Orders (SPEC section 4): drawing from the seeded RNG, matching plates, expiry."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .codes import Item, ItemState, Where
from .records import Event, Order

if TYPE_CHECKING:
    from .state import State


def draw_order(state: State, replaces: Order | None = None) -> None:
    """Append one order drawn uniformly from the recipe pool with the episode's RNG.

    With fixed orders (``rules.fixed_orders``) nothing is drawn: the order that
    ``replaces`` a served or expired one has its recipe, and otherwise the fixed
    recipes come in turn."""
    fixed = state.rules.fixed_orders
    if fixed is not None:
        recipe = replaces.recipe if replaces is not None else \
            fixed[state.next_order_id % len(fixed)]
    else:
        recipes = state.rules.recipes
        recipe = recipes[int(state.rng.integers(len(recipes)))]
    limit = state.rules.order_time_limit
    deadline = state.t + limit if limit is not None else -1
    state.orders.append(Order(state.next_order_id, recipe, state.t, deadline))
    state.next_order_id += 1


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

"""Small immutable records of the kitchen: an order and an event.

They sit below :mod:`.state`, :mod:`.orders` and :mod:`.words` so that those modules
import one another in one direction only (state -> orders, words -> records).
"""

from __future__ import annotations

from typing import Any, NamedTuple

from .rules import Recipe


class Order(NamedTuple):
    order_id: int
    recipe: Recipe
    created: int  # step at which it was drawn
    deadline: int  # step at which it expires; -1 = never


class Event(NamedTuple):
    """Something that happened in a step: what, to whom (agent index or -1), where, which item."""

    kind: str
    agent: int = -1
    cell: tuple[int, int] | None = None
    item: int = -1
    value: Any = None


__all__ = ["Event", "Order"]

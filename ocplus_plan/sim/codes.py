"""Integer codes of SPEC section 1: cells, items, item states and actions.

The cell codes are those of the published Overcooked-Plus map format; item kinds
reuse the code of their spawn tile, so ``Item(Cell.TOMATO) is Item.TOMATO``.
"""

from __future__ import annotations

from enum import IntEnum


class Cell(IntEnum):
    BLOCK = -1
    FLOOR = 0
    COUNTER = 1
    SPAWN = 2
    TOMATO = 3
    LETTUCE = 4
    PLATE = 5
    BOARD = 6
    DELIVERY = 7
    ONION = 8
    PAN = 9
    STEAK = 10
    SINK = 11
    TRASH = 12
    OVEN = 13


class Item(IntEnum):
    """Kinds of movable things. Values equal the code of their spawn tile."""

    TOMATO = 3
    LETTUCE = 4
    PLATE = 5
    ONION = 8
    STEAK = 10


class ItemState(IntEnum):
    """Processing state of an item. A raw steak is ``FRESH`` (alias ``RAW``)."""

    FRESH = 0
    RAW = 0
    CHOPPED = 1
    COOKED = 2
    BURNT = 3
    CLEAN = 4
    DIRTY = 5


class Action(IntEnum):
    """Per-agent actions, with the published indices."""

    RIGHT = 0
    DOWN = 1
    LEFT = 2
    UP = 3
    STAY = 4


class Where(IntEnum):
    """Where an item is: the meaning of its ``loc`` number."""

    CELL = 0  # loc = flat cell index of the counter / board / pan / sink holding it
    HAND = 1  # loc = agent index
    PLATE = 2  # loc = item id of the plate it lies on
    WAITING = 3  # loc = its spawn tile, occupied; it appears when the tile is free


#: (row delta, col delta) of each action.
ACTION_DELTAS: dict[Action, tuple[int, int]] = {
    Action.RIGHT: (0, 1),
    Action.DOWN: (1, 0),
    Action.LEFT: (0, -1),
    Action.UP: (-1, 0),
    Action.STAY: (0, 0),
}

VEGETABLES: frozenset[Item] = frozenset({Item.TOMATO, Item.LETTUCE, Item.ONION})
INGREDIENTS: frozenset[Item] = VEGETABLES | {Item.STEAK}
SPAWN_TILES: frozenset[Cell] = frozenset(
    {Cell.TOMATO, Cell.LETTUCE, Cell.ONION, Cell.STEAK, Cell.PLATE}
)
#: Cells an agent can stand on.
WALKABLE: frozenset[Cell] = frozenset({Cell.FLOOR, Cell.SPAWN})
#: Cells that hold at most one item and behave as a counter (spawn tiles are counters).
COUNTERS: frozenset[Cell] = frozenset({Cell.COUNTER}) | SPAWN_TILES
#: Stations: fixed interaction cells that a switch layout may never move.
STATIONS: frozenset[Cell] = frozenset(
    {Cell.BOARD, Cell.DELIVERY, Cell.PAN, Cell.SINK, Cell.TRASH, Cell.OVEN}
) | SPAWN_TILES
#: The only codes a switch layout may change between.
SWITCHABLE: frozenset[Cell] = frozenset({Cell.BLOCK, Cell.FLOOR, Cell.COUNTER})

ITEM_NAMES: dict[str, Item] = {i.name.lower(): i for i in Item}
VALID_CODES: frozenset[int] = frozenset(int(c) for c in Cell)

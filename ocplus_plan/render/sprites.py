"""Tile sprites drawn in code with numpy (no image files, no pygame).

Every sprite is ``TILE_SIZE x TILE_SIZE``: terrain tiles are opaque RGB ``uint8`` arrays,
item and agent sprites are ``(rgb, mask)`` pairs pasted where ``mask`` is true. The
shapes are deliberately simple (disks, bars, crosses) and distinct in colour, so that a
small CNN can tell every kind and state apart at 16 pixels.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ..sim.codes import Cell, Item, ItemState
from ..sim.stations import KIND_OF, item_colour

#: pixels per grid cell in every frame this package draws
TILE_SIZE = 16

Sprite = tuple[np.ndarray, np.ndarray]  # (rgb (T, T, 3) uint8, mask (T, T) bool)

UNKNOWN = (0, 0, 0)
#: each item kind's colour: its spawn tile's (``sim/stations.py``)
ITEM_COLOURS: dict[int, tuple[int, int, int]] = {int(k): item_colour(k) for k in Item}
AGENT_COLOURS: tuple[tuple[int, int, int], ...] = (
    (40, 90, 220), (240, 150, 20), (150, 40, 170), (20, 170, 170), (120, 120, 120),
)
_STEAK_STATE = {
    int(ItemState.RAW): (235, 120, 135),
    int(ItemState.COOKED): (140, 80, 40),
    int(ItemState.BURNT): (35, 30, 30),
}

_YY, _XX = np.mgrid[0:TILE_SIZE, 0:TILE_SIZE] + 0.5


def _disk(cy: float, cx: float, radius: float) -> np.ndarray:
    return (_YY - cy) ** 2 + (_XX - cx) ** 2 <= radius**2


def _tile(colour: tuple[int, int, int]) -> np.ndarray:
    return np.broadcast_to(np.array(colour, np.uint8), (TILE_SIZE, TILE_SIZE, 3)).copy()


def _paint(img: np.ndarray, mask: np.ndarray, colour: tuple[int, int, int]) -> None:
    img[mask] = colour


def _counter(colour: tuple[int, int, int]) -> np.ndarray:
    img = _tile(colour)
    img[:2] = (180, 132, 84)  # lit top edge
    img[-1] = (110, 74, 42)
    return img


_COUNTER = KIND_OF[int(Cell.COUNTER)].colour  # what stations stand on


def _floor(colour: tuple[int, int, int]) -> np.ndarray:
    img = _tile(colour)
    img[-1] = img[:, -1] = (206, 194, 166)
    return img


def _wall(colour: tuple[int, int, int]) -> np.ndarray:
    img = _tile(colour)
    diag = ((_YY.astype(int) + _XX.astype(int)) % 6) == 0
    img[diag] = (90, 90, 98)
    return img


def _crate(colour: tuple[int, int, int]) -> np.ndarray:
    img = _counter(_COUNTER)  # a crate marked with its item's colour in the corner
    img[2:6, 1:5] = colour
    img[2:6, 1] = img[2:6, 4] = (90, 60, 30)
    return img


def _board(colour: tuple[int, int, int]) -> np.ndarray:
    t = TILE_SIZE
    img = _counter(_COUNTER)
    img[3 : t - 3, 2 : t - 2] = colour
    img[3 : t - 3 : 3, 2 : t - 2] = (186, 146, 92)
    return img


def _window(colour: tuple[int, int, int]) -> np.ndarray:
    t = TILE_SIZE
    img = _tile(colour)
    img[t // 2 - 1 : t // 2 + 1, 3 : t - 3] = (240, 240, 240)
    img[t // 2 - 3 : t // 2 + 3, t - 5 : t - 3] = (240, 240, 240)
    return img


def _pan(colour: tuple[int, int, int]) -> np.ndarray:
    t = TILE_SIZE
    img = _counter(_COUNTER)
    _paint(img, _disk(t / 2, t / 2, t * 0.42), colour)
    img[t // 2 - 1 : t // 2 + 1, 0:2] = colour
    return img


def _sink(colour: tuple[int, int, int]) -> np.ndarray:
    t = TILE_SIZE
    img = _counter(_COUNTER)
    img[3 : t - 3, 2 : t - 2] = (180, 180, 190)
    img[5 : t - 5, 4 : t - 4] = colour
    return img


def _trash(colour: tuple[int, int, int]) -> np.ndarray:
    t = TILE_SIZE
    img = _counter(_COUNTER)
    _paint(img, _disk(t / 2, t / 2, t * 0.4), colour)
    cross = (np.abs(_YY - _XX) < 1.2) | (np.abs(_YY + _XX - t) < 1.2)
    _paint(img, cross & _disk(t / 2, t / 2, t * 0.3), (200, 200, 200))
    return img


def _station(colour: tuple[int, int, int]) -> np.ndarray:
    """Any other station: a counter with a square of its colour."""
    t = TILE_SIZE
    img = _counter(_COUNTER)
    img[3 : t - 3, 3 : t - 3] = colour
    return img


#: how each ``sprite`` style of ``sim/stations.py`` is drawn, in the record's colour
_STYLES = {"floor": _floor, "wall": _wall, "counter": _counter, "crate": _crate,
           "board": _board, "window": _window, "pan": _pan, "sink": _sink, "trash": _trash,
           "station": _station}


@cache
def terrain_tile(code: int) -> np.ndarray:
    """The opaque tile of a cell code (read-only), drawn as its record says."""
    kind = KIND_OF.get(int(code))
    if kind is None:  # pragma: no cover - every valid code has a record
        raise ValueError(f"no tile for cell code {code}")
    img = _STYLES[kind.sprite](kind.colour)
    img.setflags(write=False)
    return img


@cache
def item_sprite(kind: int, state: int, scale: float = 1.0) -> Sprite:
    """Sprite of an item of ``kind`` in ``state`` (``scale`` < 1 for held / plated items)."""
    t = TILE_SIZE
    img = np.zeros((t, t, 3), np.uint8)
    c = t / 2
    kind, state = int(kind), int(state)
    if kind == Item.PLATE:
        mask = _disk(c, c, t * 0.45 * scale)
        img[mask] = (150, 150, 160)
        img[_disk(c, c, t * 0.37 * scale)] = ITEM_COLOURS[kind]
        if state == ItemState.DIRTY:
            for dy, dx in ((-2, -2), (1, 2), (3, -1)):
                img[_disk(c + dy * scale, c + dx * scale, 1.3 * scale)] = (120, 90, 50)
    elif kind == Item.STEAK:
        colour = _STEAK_STATE.get(state, _STEAK_STATE[int(ItemState.RAW)])
        mask = ((_YY - c) / (t * 0.28 * scale)) ** 2 + ((_XX - c) / (t * 0.4 * scale)) ** 2 <= 1
        img[mask] = colour
        img[mask & (np.abs(_YY - c) < 0.6)] = (250, 230, 230)  # fat stripe
    else:
        colour = ITEM_COLOURS[kind]
        if state == ItemState.CHOPPED:  # three pieces
            mask = np.zeros((t, t), bool)
            for dy, dx in ((-3, -3), (-3, 3), (3, 0)):
                mask |= _disk(c + dy * scale, c + dx * scale, t * 0.17 * scale)
        else:
            mask = _disk(c, c, t * 0.34 * scale)
        img[mask] = colour
    img.setflags(write=False)
    mask.setflags(write=False)
    return img, mask


@cache
def agent_sprite(index: int) -> Sprite:
    """A cook: a body disk in the agent's colour under a white hat."""
    t = TILE_SIZE
    img = np.zeros((t, t, 3), np.uint8)
    body = _disk(t * 0.58, t / 2, t * 0.36)
    hat = (_YY < t * 0.34) & (_YY > t * 0.08) & (np.abs(_XX - t / 2) < t * 0.24)
    img[body] = AGENT_COLOURS[index % len(AGENT_COLOURS)]
    img[hat] = (250, 250, 250)
    mask = body | hat
    img.setflags(write=False)
    mask.setflags(write=False)
    return img, mask


__all__ = [
    "AGENT_COLOURS",
    "ITEM_COLOURS",
    "TILE_SIZE",
    "UNKNOWN",
    "agent_sprite",
    "item_sprite",
    "terrain_tile",
]

"""RGB frames of a kitchen, drawn with numpy from the sprites in :mod:`.sprites`.

``render_frame(state)`` is the whole map; ``render_frame(state, window=r, agent=a)`` the
``(2r+1) x (2r+1)``-cell window centred on agent ``a`` (cells outside the map are black).
Frames are ``(rows * TILE_SIZE, cols * TILE_SIZE, 3)`` ``uint8``. The pygame window (a
separate, optional module) displays these frames; nothing here needs a display.

Drawing order per cell: terrain, item (a plate first, then its contents, smaller),
progress bar (chop / wash count or pan ticks), agent, then the agent's held item at the
agent's lower-right corner.
"""

from __future__ import annotations

import weakref

import numpy as np

from ..errors import ConfigError
from ..sim.codes import Item, Where
from ..sim.rules import Rules
from ..sim.state import Geometry, State
from .sprites import TILE_SIZE, UNKNOWN, agent_sprite, item_sprite, terrain_tile

_CELL, _HAND, _PLATE = int(Where.CELL), int(Where.HAND), int(Where.PLATE)
_PLATE_KIND, _STEAK = int(Item.PLATE), int(Item.STEAK)
_HELD_SCALE = 0.6
_PLATED_SCALE = 0.45


class RgbEncoder:
    """Draws frames of one :class:`Rules`' kitchens; the ``rgb`` observation encoder.

    ``obs_radius`` r > 0 gives each agent the window centred on it, r = 0 the whole map.
    """

    def __init__(self, rules: Rules, obs_radius: int = 0) -> None:
        if isinstance(obs_radius, bool) or not isinstance(obs_radius, int) or obs_radius < 0:
            raise ConfigError(f"obs_radius must be an integer >= 0 (0 = whole map), got {obs_radius!r}")
        self.rules = rules
        self.radius = r = obs_radius
        rows, cols = rules.layout.shape
        self.rows, self.cols = rows, cols
        t = TILE_SIZE
        self.shape = ((2 * r + 1) * t, (2 * r + 1) * t, 3) if r else (rows * t, cols * t, 3)
        # backgrounds padded by r cells of "unknown" on every side, one per layout
        self._bg = []
        for grid in rules.layout.grids():
            img = np.empty(((rows + 2 * r) * t, (cols + 2 * r) * t, 3), np.uint8)
            img[:] = UNKNOWN
            for (row, col), code in np.ndenumerate(grid):
                y, x = (row + r) * t, (col + r) * t
                img[y : y + t, x : x + t] = terrain_tile(int(code))
            img.setflags(write=False)
            self._bg.append(img)
        scale = rules.tables.progress_scale  # the records' durations (an oven's for steak)
        self._progress_den = {
            _STEAK: float(scale(_STEAK)), _PLATE_KIND: float(scale(_PLATE_KIND)),
        }
        self._chop_den = float(scale(int(Item.TOMATO)))
        self._tiles: dict[tuple, np.ndarray] = {}

    def draw(self, state: State) -> np.ndarray:
        """The padded frame of ``state`` (whole map plus an r-cell unknown margin).

        Every cell that shows something dynamic is one cached composite tile (terrain +
        item + plated contents + progress bar, or floor + cook + held item), pasted as a
        plain slice: masks are applied once per distinct tile, not once per step."""
        t, r, cols = TILE_SIZE, self.radius, self.cols
        img = self._bg[state.layout_index].copy()
        terrain = state.geo.terrains[state.layout_index]
        kinds = state.geo.item_kind
        where, loc, st, prog = state.item_where, state.item_loc, state.item_state, state.item_progress
        plated: dict[int, list[int]] = {}
        for i, w in enumerate(where):
            if w == _PLATE:
                plated.setdefault(loc[i], []).append(i)

        def describe(i: int) -> tuple:
            return (kinds[i], st[i], tuple((kinds[j], st[j]) for j in plated.get(i, ())))

        for i, w in enumerate(where):
            if w != _CELL:
                continue
            cell = loc[i]
            bar = -1
            if prog[i]:
                den = self._progress_den.get(kinds[i], self._chop_den)
                bar = round((t - 2) * min(1.0, prog[i] / den))
            row, col = divmod(cell, cols)
            y, x = (row + r) * t, (col + r) * t
            img[y : y + t, x : x + t] = self._tile((terrain[cell], describe(i), bar, -1, None))
        for a, cell in enumerate(state.agent_pos):
            held = state.agent_hand[a]
            key = (terrain[cell], None, -1, a, describe(held) if held >= 0 else None)
            row, col = divmod(cell, cols)
            y, x = (row + r) * t, (col + r) * t
            img[y : y + t, x : x + t] = self._tile(key)
        return img

    def _tile(self, key: tuple) -> np.ndarray:
        tile = self._tiles.get(key)
        if tile is None:
            if len(self._tiles) > 4096:
                self._tiles.clear()
            tile = self._tiles[key] = _compose(*key)
        return tile

    def frame(self, state: State, window: int | None = None, agent: int | None = None) -> np.ndarray:
        """The whole map, or the ``window``-cell radius around ``agent`` (a new array)."""
        img = self.draw(state)
        return self._crop(img, state, window, agent)

    def encode(self, state: State) -> np.ndarray:
        """``(n_agents, *shape)`` uint8 observations (the same frame for all when r = 0)."""
        img = self.draw(state)
        n = state.n_agents
        if self.radius == 0:
            return np.broadcast_to(img, (n, *img.shape)).copy()
        return np.stack([self._crop(img, state, self.radius, a) for a in range(n)])

    def _crop(self, img: np.ndarray, state: State, window: int | None,
              agent: int | None) -> np.ndarray:
        r, t = self.radius, TILE_SIZE
        if not window:
            return img[r * t : (r + self.rows) * t, r * t : (r + self.cols) * t].copy()
        if agent is None or not 0 <= agent < state.n_agents:
            raise ConfigError(
                f"a window of radius {window} needs agent= one of 0..{state.n_agents - 1}, "
                f"got {agent!r}"
            )
        if window > r:  # this encoder's margin is too small: draw with a wider one
            return RgbEncoder(self.rules, window).frame(state, window, agent)
        row, col = divmod(state.agent_pos[agent], self.cols)
        y0, x0 = (row + r - window) * t, (col + r - window) * t
        size = (2 * window + 1) * t
        return img[y0 : y0 + size, x0 : x0 + size].copy()


def _paste(img: np.ndarray, sprite: tuple[np.ndarray, np.ndarray], dy: int = 0,
           dx: int = 0) -> None:
    """Paste a sprite onto a tile, shifted by (dy, dx) pixels and clipped to the tile."""
    t = TILE_SIZE
    rgb, mask = sprite
    h, w = t - abs(dy), t - abs(dx)
    ys, xs, sy, sx = max(dy, 0), max(dx, 0), max(-dy, 0), max(-dx, 0)
    np.copyto(img[ys : ys + h, xs : xs + w], rgb[sy : sy + h, sx : sx + w],
              where=mask[sy : sy + h, sx : sx + w, None])


def _draw_item(img: np.ndarray, desc: tuple, scale: float, dy: int = 0, dx: int = 0) -> None:
    """An item (kind, state, plated contents) at ``scale``; contents smaller, side by side."""
    kind, state, contents = desc
    _paste(img, item_sprite(kind, state, scale), dy, dx)
    for k, (ck, cs) in enumerate(contents):
        off = (-3 + 3 * k) if scale == 1.0 else (-2 + 2 * k)
        _paste(img, item_sprite(ck, cs, _PLATED_SCALE * scale), dy + off // 2, dx + off)


def _compose(code: int, item: tuple | None, bar: int, agent: int, held: tuple | None) -> np.ndarray:
    """One cell's picture: terrain, then an item with its progress bar (``bar`` pixels,
    -1 = none), or a cook (``agent`` >= 0) with what it holds."""
    t = TILE_SIZE
    img = terrain_tile(code).copy()
    if item is not None:
        _draw_item(img, item, 1.0)
    if bar >= 0:
        img[t - 3 : t - 1, 1 : t - 1] = (40, 40, 40)
        img[t - 3 : t - 1, 1 : 1 + bar] = (250, 220, 0)
    if agent >= 0:
        _paste(img, agent_sprite(agent))
        if held is not None:
            _draw_item(img, held, _HELD_SCALE, t // 4, t // 4)
    img.setflags(write=False)
    return img


_ENCODERS: weakref.WeakKeyDictionary[Geometry, RgbEncoder] = weakref.WeakKeyDictionary()


def render_frame(
    state: State, window: int | None = None, agent: int | None = None, *, tile: int | None = None
) -> np.ndarray:
    """An ``(H, W, 3)`` uint8 picture of ``state``: the whole map (``window`` None or 0), or
    the ``(2 * window + 1)``-cell square centred on ``agent`` (outside the map is black).
    ``H = rows * TILE_SIZE`` for the whole map; ``tile`` (pixels per cell) rescales the
    frame by nearest neighbour (sprites are drawn at ``TILE_SIZE``)."""
    if tile is not None and (isinstance(tile, bool) or not isinstance(tile, int) or tile < 1):
        raise ConfigError(f"tile must be a positive number of pixels per cell, got {tile!r}")
    if window is not None and (isinstance(window, bool) or not isinstance(window, int)
                               or window < 0):
        raise ConfigError(f"window must be None or an integer radius >= 0, got {window!r}")
    enc = _ENCODERS.get(state.geo)
    if enc is None or enc.radius < (window or 0):
        enc = RgbEncoder(state.rules, window or 0)
        _ENCODERS[state.geo] = enc
    frame = enc.frame(state, window, agent)
    if tile is None or tile == TILE_SIZE:
        return frame
    ys = np.arange(frame.shape[0] * tile // TILE_SIZE) * TILE_SIZE // tile
    xs = np.arange(frame.shape[1] * tile // TILE_SIZE) * TILE_SIZE // tile
    return frame[ys[:, None], xs[None, :]]


__all__ = ["TILE_SIZE", "RgbEncoder", "render_frame"]

"""The pygame window: the rgb frame (one drawing code path) plus a side panel.

The kitchen picture is always :func:`ocplus_plan.render.rgb.render_frame`, the same
numpy image the env returns for ``render_mode="rgb_array"``; this module only
scales it onto the window and draws a side panel next to it: score, step, the open
orders and their time left, the pans' cooking progress as bars, what each cook
holds, dirty plates, the countdown to the next layout switch and received messages.

pygame (the ``gui`` extra, pygame-ce) is imported only when a :class:`Window` is
made, so importing this module is cheap and the simulator never loads pygame.
What the panel says is computed by :func:`panel_lines` without pygame (testable).

Keyboard: :data:`KEYSETS` maps key names to ``(human, action)``; one human may use
WASD or the arrows (stay: space or enter); with two humans the first uses WASD +
space and the second the arrows + enter.
"""

from __future__ import annotations

import os
import sys
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, DependencyNotInstalled, DisplayUnavailable
from ..sim.codes import Action, Item, ItemState, Where
from ..sim.queries import ticks_until_burnt, ticks_until_cooked
from ..sim.rules import recipe_name
from ..sim.state import State
from ..sim.stations import KIND_OF
from ..sim.words import state_word

PANEL_WIDTH = 320
MIN_MAP_HEIGHT = 420
BACKGROUND = (30, 32, 38)
TEXT = (235, 235, 235)
DIM = (150, 155, 165)
ACCENT = (255, 205, 90)
BAR_BACK = (70, 74, 84)
GOOD, WARN, BAD = (90, 200, 110), (240, 170, 60), (220, 70, 60)
#: the outline and label that mark the cooks a person plays ("YOU", or "P1" / "P2")
HUMAN_MARK = (255, 40, 200)
#: SDL drivers that draw into memory only: a window opened with them is never seen
OFFSCREEN_DRIVERS = ("offscreen", "dummy")

#: key name (pygame.key.key_code spelling) -> action, per keyset
WASD: dict[str, Action] = {
    "d": Action.RIGHT, "s": Action.DOWN, "a": Action.LEFT, "w": Action.UP, "space": Action.STAY,
}
ARROWS: dict[str, Action] = {
    "right": Action.RIGHT, "down": Action.DOWN, "left": Action.LEFT, "up": Action.UP,
    "return": Action.STAY, "enter": Action.STAY,
}
#: keysets per number of humans: one human gets both, two humans get one each
KEYSETS: dict[int, tuple[dict[str, Action], ...]] = {
    1: ({**WASD, **ARROWS},),
    2: (WASD, ARROWS),
}
KEY_HELP: dict[int, tuple[str, ...]] = {
    1: ("move: WASD or arrows, stay: space/enter",),
    2: ("human 1: WASD, stay: space", "human 2: arrows, stay: enter"),
}


def require_pygame() -> Any:
    """Import pygame-ce, or raise :class:`DependencyNotInstalled` naming the ``gui`` extra."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame
    except ImportError as exc:
        raise DependencyNotInstalled(
            "the window needs pygame-ce: pip install 'ocplus-plan[gui]' "
            "(or use render_mode='rgb_array', which needs no window)"
        ) from exc
    return pygame


def display_problem() -> str | None:
    """Why no window can be seen here, or None. ``SDL_VIDEODRIVER`` set by the caller
    (``dummy`` in tests) is taken as meant; on Linux and the BSDs a window needs ``DISPLAY``
    (X11) or ``WAYLAND_DISPLAY`` (checked without starting SDL, which would fall back to an
    invisible off-screen driver and leave the program waiting for keys nobody can press)."""
    if os.environ.get("SDL_VIDEODRIVER"):
        return None
    if sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")) and not (
            os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return "no display to open a window on (neither DISPLAY nor WAYLAND_DISPLAY is set)"
    return None


def require_display(alternatives: str) -> None:
    """Raise :class:`DisplayUnavailable` at once when no window can be seen, naming the
    ``alternatives`` that work without one."""
    problem = display_problem()
    if problem is not None:
        raise DisplayUnavailable(f"{problem}; {alternatives}")


def key_map(n_humans: int) -> dict[str, tuple[int, Action]]:
    """``{key name: (human index, action)}`` for ``n_humans`` keyboard players (1 or 2)."""
    if n_humans not in KEYSETS:
        raise ConfigError(
            f"{n_humans} human players: the keyboard has keysets for 1 or 2 (WASD and arrows)"
        )
    return {key: (h, act) for h, keys in enumerate(KEYSETS[n_humans]) for key, act in keys.items()}


# ------------------------------------------------------------------ panel content
@dataclass(frozen=True)
class PanelLine:
    """One line of the side panel: text, and optionally a progress bar under it."""

    text: str
    color: tuple[int, int, int] = TEXT
    bar: float | None = None  # fraction in [0, 1]
    bar_color: tuple[int, int, int] = GOOD
    heading: bool = False


def describe_item(state: State, item: int) -> str:
    """``"tomato (chopped)"``, ``"plate [lettuce]"``, ``"plate (dirty)"`` (state words from
    :mod:`ocplus_plan.sim.words`)."""
    kind = state.geo.item_kind[item]
    st = state.item_state[item]
    name = Item(kind).name.lower()
    if kind == Item.PLATE:
        inside = [Item(state.geo.item_kind[i]).name.lower() for i in state.plate_contents(item)]
        if st == ItemState.DIRTY:
            return "plate (dirty)"
        return f"plate [{', '.join(sorted(inside))}]" if inside else "plate (empty)"
    return f"{name} ({state_word(kind, st)})"


def panel_lines(
    state: State,
    *,
    scores: Mapping[str, float] | None = None,
    messages: Sequence[str] = (),
    agent_labels: Mapping[int, str] | None = None,
    status: str = "",
    key_help: Sequence[str] = (),
) -> list[PanelLine]:
    """Everything the side panel shows, as plain data (no pygame needed)."""
    rules = state.rules
    geo = state.geo
    labels = dict(agent_labels or {})
    out: list[PanelLine] = [
        PanelLine(f"{rules.preset} / {rules.layout.name}", ACCENT, heading=True),
        PanelLine(f"step {state.t} / {rules.horizon}", bar=min(1.0, state.t / rules.horizon),
                  bar_color=DIM),
    ]
    for name, value in (scores or {}).items():
        out.append(PanelLine(f"{name}: {value:.1f}"))
    out.append(PanelLine(f"served {state.stats['dishes_served']}   "
                         f"expired {state.stats['orders_expired']}   burnt {state.stats['burns']}",
                         DIM))

    out.append(PanelLine("orders", ACCENT, heading=True))
    for order in state.orders:
        name = recipe_name(order.recipe)
        if order.deadline >= 0:
            left = max(0, order.deadline - state.t)
            span = max(1, order.deadline - order.created)
            frac = left / span
            color = GOOD if frac > 0.5 else WARN if frac > 0.2 else BAD
            out.append(PanelLine(f"{name}  ({left} steps left)", bar=frac, bar_color=color))
        else:
            out.append(PanelLine(f"{name}  (no time limit)"))

    heat = rules.tables.station_of(int(Item.STEAK))  # the pan; an oven where it takes steak
    word = KIND_OF[heat].word if heat >= 0 else "pan"
    if geo.pans:
        out.append(PanelLine(word + "s", ACCENT, heading=True))
    for pan in geo.pans:
        r, c = geo.rc(pan)
        item = state.cell_item[pan]
        if item < 0:
            out.append(PanelLine(f"{word} ({r},{c}): empty", DIM))
            continue
        ticks = state.item_progress[item]
        st = state.item_state[item]
        cook, burn = rules.tables.duration_at(heat), rules.tables.overrun_at(heat)
        if st == ItemState.BURNT:
            out.append(PanelLine(f"{word} ({r},{c}): burnt!", BAD, bar=1.0, bar_color=BAD))
        elif ticks_until_cooked(rules, ticks):
            out.append(PanelLine(f"{word} ({r},{c}): cooking {ticks}/{cook}",
                                 bar=ticks / cook, bar_color=WARN))
        else:
            left = ticks_until_burnt(rules, ticks)
            out.append(PanelLine(f"{word} ({r},{c}): cooked, burns in {left}", GOOD,
                                 bar=min(1.0, ticks / max(1, burn)), bar_color=BAD))

    out.append(PanelLine("cooks", ACCENT, heading=True))
    for a in range(state.n_agents):
        hand = state.agent_hand[a]
        held = describe_item(state, hand) if hand >= 0 else "empty-handed"
        label = labels.get(a, f"agent {a}")
        out.append(PanelLine(f"{label}: {held}"))

    if rules.dirty_plates:
        dirty = sum(1 for i, k in enumerate(geo.item_kind)
                    if k == Item.PLATE and state.item_state[i] == ItemState.DIRTY)
        waiting = sum(1 for i, k in enumerate(geo.item_kind)
                      if k == Item.PLATE and state.item_where[i] == Where.WAITING)
        text = f"dirty plates: {dirty}" + (f" ({waiting} waiting to respawn)" if waiting else "")
        out.append(PanelLine(text, WARN if dirty else TEXT))
    if rules.dynamic and len(geo.terrains) > 1:
        due = state.next_switch - state.t
        if due > 0:
            out.append(PanelLine(f"layout switch in {due} steps",
                                 bar=1.0 - due / rules.map_switch_step, bar_color=WARN))
        else:
            out.append(PanelLine("layout switch due: waiting for a clear kitchen", WARN))
    if messages:
        out.append(PanelLine("messages", ACCENT, heading=True))
        out.extend(PanelLine(str(m)) for m in list(messages)[-5:])
    if status:
        out.append(PanelLine(status, ACCENT))
    if key_help:
        out.append(PanelLine("keys", ACCENT, heading=True))
        out.extend(PanelLine(h, DIM) for h in key_help)
    return out


def _wrap(text: str, font: Any, width: int) -> list[str]:
    """Split ``text`` at spaces into lines no wider than ``width`` pixels (when possible)."""
    lines: list[str] = []
    current = ""
    for word in text.split(" "):
        trial = f"{current} {word}" if current else word
        if current and font.size(trial)[0] > width:
            lines.append(current)
            current = word
        else:
            current = trial
    return [*lines, current]


# ------------------------------------------------------------------ the window
class Window:
    """A pygame window showing a frame and the side panel.

    ``show(state, ...)`` draws (the frame is rendered with ``render_frame`` unless one is
    given; ``humans=`` marks the cooks people play), ``poll()`` returns the key names pressed since the last call and whether the
    window was closed, ``save(path)`` writes the window as PNG, ``close()`` closes it.
    Under ``SDL_VIDEODRIVER=dummy`` everything works without a display (tests, CI);
    without a display and without that choice it raises :class:`DisplayUnavailable` (with
    ``headless_hint``, what to do instead) rather than draw a window nobody sees.
    """

    def __init__(self, title: str = "ocplus-plan", *, panel_width: int = PANEL_WIDTH,
                 min_map_height: int = MIN_MAP_HEIGHT, tile: int | None = None,
                 headless_hint: str = "draw frames with render_mode='rgb_array' instead, or "
                                      "set SDL_VIDEODRIVER=dummy to run the window off-screen",
                 offscreen_ok: bool = False) -> None:
        self.pg = require_pygame()
        self._open_display(headless_hint, offscreen_ok)
        self.pg.font.init()
        self.title = title
        self.panel_width = panel_width
        self.min_map_height = min_map_height
        self.tile = tile
        self.screen: Any = None
        self.closed = False
        self._clock = self.pg.time.Clock()
        self._font = self.pg.font.Font(None, 22)
        self._bold = self.pg.font.Font(None, 24)
        self._bold.set_bold(True)
        self.pg.display.set_caption(title)

    def _open_display(self, headless_hint: str, offscreen_ok: bool) -> None:
        """Start SDL's video. Without a display: raise :class:`DisplayUnavailable` naming
        ``headless_hint``, or with ``offscreen_ok`` (an env's ``render_mode="human"``, as
        Gymnasium's ``check_env`` tries it) draw off-screen with one warning instead of
        letting SDL probe X11 / Wayland and print its errors."""
        problem = display_problem()
        if problem is not None and not offscreen_ok:
            raise DisplayUnavailable(f"{problem}; {headless_hint}")
        if problem is not None:
            warnings.warn(f"{problem}: the window is drawn off-screen (SDL's dummy driver); "
                          "use render_mode='rgb_array' for frames", stacklevel=3)
            os.environ["SDL_VIDEODRIVER"] = "dummy"  # read by SDL at init only
            try:
                self.pg.display.init()
            finally:
                del os.environ["SDL_VIDEODRIVER"]
            return
        self.pg.display.init()
        driver = self.pg.display.get_driver()
        if (driver in OFFSCREEN_DRIVERS and not os.environ.get("SDL_VIDEODRIVER")
                and not offscreen_ok):
            self.pg.display.quit()
            raise DisplayUnavailable(f"SDL found no display and fell back to its {driver!r} "
                                     f"driver, so nobody would see the window; {headless_hint}")

    # -- drawing
    def frame_for(self, state: State) -> np.ndarray:
        from .rgb import render_frame

        return render_frame(state) if self.tile is None else render_frame(state, tile=self.tile)

    def compose(self, state: State, frame: np.ndarray | None = None, *,
                humans: Sequence[int] = (), **panel: Any) -> Any:
        """Draw frame + panel onto the window surface (opening or resizing it) and return it.
        ``humans``: the cooks a person plays, outlined and labelled on the map."""
        pg = self.pg
        if frame is None:
            frame = self.frame_for(state)
        frame = np.ascontiguousarray(frame, dtype=np.uint8)
        if frame.ndim != 3 or frame.shape[2] != 3:
            raise ConfigError(f"a frame must be an (H, W, 3) uint8 array, got shape {frame.shape}")
        h, w = int(frame.shape[0]), int(frame.shape[1])
        scale = max(1, -(-self.min_map_height // h))
        map_w, map_h = w * scale, h * scale
        lines = panel_lines(state, **panel)
        panel_h = self._draw_panel(lines, map_w + 12, self.panel_width - 24, draw=False)
        size = (map_w + self.panel_width, max(map_h, panel_h))
        if self.screen is None or self.screen.get_size() != size:
            if not pg.display.get_init():
                pg.display.init()
                pg.display.set_caption(self.title)
            self.screen = pg.display.set_mode(size)
        self.screen.fill(BACKGROUND)
        image = pg.image.frombuffer(frame.tobytes(), (w, h), "RGB")
        if scale > 1:
            image = pg.transform.scale(image, (map_w, map_h))
        self.screen.blit(image, (0, 0))
        if humans and map_h % state.geo.rows == 0 and map_h // state.geo.rows * state.geo.cols == map_w:
            self._mark_humans(state, humans, map_h // state.geo.rows)
        self._draw_panel(lines, map_w + 12, self.panel_width - 24)
        return self.screen

    def _mark_humans(self, state: State, humans: Sequence[int], cell: int) -> None:
        """Outline each human's cook and label it "YOU" (one human) or "P1", "P2" (the frame
        is the whole map, ``cell`` pixels per cell)."""
        pg = self.pg
        for k, agent in enumerate(humans):
            r, c = state.agent_rc(agent)
            box = pg.Rect(c * cell, r * cell, cell, cell)
            pg.draw.rect(self.screen, HUMAN_MARK, box, width=max(2, cell // 12))
            label = self._bold.render("YOU" if len(humans) == 1 else f"P{k + 1}", True,
                                      BACKGROUND, HUMAN_MARK)
            # above the cook, or below it on the top row, kept inside the map
            x = min(max(0, box.centerx - label.get_width() // 2),
                    cell * state.geo.cols - label.get_width())
            y = box.top - label.get_height() if r > 0 else box.bottom
            self.screen.blit(label, (x, y))

    def _draw_panel(self, lines: list[PanelLine], x: int, width: int, draw: bool = True) -> int:
        """Draw the panel lines from the top at ``x``; return the height used (+ margin)."""
        pg = self.pg
        y = 10
        for line in lines:
            if line.heading:
                y += 6
            font = self._bold if line.heading else self._font
            for part in _wrap(line.text, font, width):
                if draw:
                    self.screen.blit(font.render(part, True, line.color), (x, y))
                y += 20
            if line.bar is not None:
                if draw:
                    frac = min(1.0, max(0.0, float(line.bar)))
                    pg.draw.rect(self.screen, BAR_BACK, (x, y, width, 6))
                    pg.draw.rect(self.screen, line.bar_color, (x, y, int(width * frac), 6))
                y += 10
        return y + 10

    def show(self, state: State, frame: np.ndarray | None = None, **panel: Any) -> None:
        """Draw ``state`` (``panel`` as for :func:`panel_lines`) and update the display."""
        self.compose(state, frame, **panel)
        self.pg.display.flip()
        self.pg.event.pump()

    def pixels(self) -> np.ndarray:
        """The window's current content as an ``(H, W, 3)`` uint8 array."""
        if self.screen is None:
            raise ConfigError("the window has drawn nothing yet: call show(state) first")
        return np.ascontiguousarray(self.pg.surfarray.array3d(self.screen).transpose(1, 0, 2))

    def save(self, path: str | Path) -> Path:
        """Write the window's content as a PNG."""
        if self.screen is None:
            raise ConfigError("the window has drawn nothing yet: call show(state) first")
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        self.pg.image.save(self.screen, str(path))
        return path

    # -- input
    def poll(self) -> list[str]:
        """Key names pressed since the last call; sets :attr:`closed` on quit or Escape."""
        pg = self.pg
        keys: list[str] = []
        for event in pg.event.get():
            if event.type == pg.QUIT:
                self.closed = True
            elif event.type == pg.KEYDOWN:
                name = pg.key.name(event.key)
                if name == "escape":
                    self.closed = True
                else:
                    keys.append(name)
        return keys

    def tick(self, fps: float) -> None:
        """Wait so that calls happen ``fps`` times per second."""
        self._clock.tick(fps)

    def close(self) -> None:
        if self.screen is not None:
            self.pg.display.quit()
            self.screen = None
        self.closed = True


__all__ = [
    "ARROWS",
    "HUMAN_MARK",
    "KEYSETS",
    "KEY_HELP",
    "WASD",
    "PanelLine",
    "Window",
    "describe_item",
    "display_problem",
    "key_map",
    "panel_lines",
    "require_display",
    "require_pygame",
]

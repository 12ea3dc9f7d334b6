"""One record per cell kind: its code, word, letter, colour, sprite and planning name.

Everything that shows or names a kind of cell reads it from :data:`CELL_KINDS`: the
kitchen words and the text observation's map picture (:mod:`.words`,
:mod:`.observe_text`), the heatmaps (``eval/plots.py``), the tiles and item colours
(``render/sprites.py``) and the planning model's place flags and object words
(``planning/compile.py``, ``planning/language.py``). Item kinds share the code of their
spawn tile (``Item(Cell.TOMATO) is Item.TOMATO``), so an item's colour is its crate's.

Adding a kind of station (say an oven) means: a code in :class:`~.codes.Cell`, one
record here (an existing ``sprite`` style, or ``"station"``: a counter marked with the
record's colour), and its rules (``step.py`` and the fast mirrors, the planning model).
"""

from __future__ import annotations

from dataclasses import dataclass

from .codes import Cell

#: what a cell kind is for, in the order the text observation lists the work places
ROLES = ("process", "serve", "dispose", "crate", "counter", "floor", "wall")
#: how ``render/sprites.py`` can draw a tile (each in the record's colour)
SPRITES = ("floor", "wall", "counter", "crate", "board", "window", "pan", "sink", "trash",
           "station")


@dataclass(frozen=True)
class CellKind:
    """Everything but the rules about one kind of cell."""

    code: Cell
    #: plain name, for texts, prompts and the planning problem's English
    word: str
    #: one character for pictures of the map (text observation, ``State.describe``) and
    #: heatmap labels; an item lying on a spawn tile upper-cases its letter
    letter: str
    #: RGB (0-255): the tile's main colour (a crate's: its item's colour)
    colour: tuple[int, int, int]
    #: how the tile is drawn (one of :data:`SPRITES`)
    sprite: str
    #: one of :data:`ROLES`
    role: str
    #: the planning model's fluent that marks a place of this kind ("" for none); a
    #: station may share a shipped station's flag when the model's schemas for that one
    #: cover its record (an oven that cooks steak is a place where steak heats: ``pan``)
    pddl: str = ""
    #: the kind whose terrain channel shows this one in the vector observation (None:
    #: its own). The observation's terrain channels are those of the shipped kinds, so a
    #: kind added later reads as the shipped kind it works like and no preset's
    #: observation layout changes
    observe_as: Cell | None = None

    @property
    def name(self) -> str:
        """The identifier: ``board``; planning objects of this kind are ``board_R_C``."""
        return self.code.name.lower()


#: every cell kind, in the order of the text observation's map legend
CELL_KINDS: tuple[CellKind, ...] = (
    CellKind(Cell.BLOCK, "wall", "#", (58, 58, 64), "wall", "wall"),
    CellKind(Cell.FLOOR, "floor", ".", (226, 214, 186), "floor", "floor"),
    CellKind(Cell.SPAWN, "floor", ".", (226, 214, 186), "floor", "floor"),
    CellKind(Cell.COUNTER, "counter", "-", (150, 104, 62), "counter", "counter"),
    CellKind(Cell.TOMATO, "tomato counter", "t", (220, 40, 40), "crate", "crate"),
    CellKind(Cell.LETTUCE, "lettuce counter", "l", (60, 180, 60), "crate", "crate"),
    CellKind(Cell.ONION, "onion counter", "o", (190, 120, 210), "crate", "crate"),
    CellKind(Cell.STEAK, "steak counter", "s", (235, 120, 135), "crate", "crate"),
    CellKind(Cell.PLATE, "plate counter", "p", (245, 245, 245), "crate", "crate"),
    CellKind(Cell.BOARD, "cutting board", "B", (214, 176, 118), "board", "process", "board"),
    CellKind(Cell.DELIVERY, "serving window", "D", (70, 160, 80), "window", "serve", "serving"),
    CellKind(Cell.PAN, "pan", "P", (45, 45, 50), "pan", "process", "pan"),
    CellKind(Cell.SINK, "sink", "S", (90, 150, 220), "sink", "process", "sink"),
    CellKind(Cell.TRASH, "trash can", "T", (40, 40, 40), "trash", "dispose", "trash"),
    CellKind(Cell.OVEN, "oven", "V", (170, 70, 40), "station", "process", "pan",
             observe_as=Cell.PAN),
)
#: code -> record
KIND_OF: dict[int, CellKind] = {int(k.code): k for k in CELL_KINDS}
#: the kinds a cook works at or fetches from, in the order the text observation lists them
WORK_PLACES: tuple[CellKind, ...] = tuple(
    k for role in ROLES[:4] for k in CELL_KINDS if k.role == role)
#: the planning model's place flag of each kind that has one
PLACE_FLAGS: dict[int, str] = {int(k.code): k.pddl for k in CELL_KINDS if k.pddl}


def item_colour(kind: int) -> tuple[int, int, int]:
    """An item kind's colour: its spawn tile's."""
    return KIND_OF[int(kind)].colour


__all__ = ["CELL_KINDS", "KIND_OF", "PLACE_FLAGS", "ROLES", "SPRITES", "WORK_PLACES",
           "CellKind", "item_colour"]

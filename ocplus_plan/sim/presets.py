"""The presets of SPEC section 7, one record each: default map, cooks, recipe rule and the
stations a preset's kitchens need.

The one list of which stations each preset needs: :func:`.rules.make_rules` checks a map
against it and the generator (:mod:`.generate_families`) places them. It sits below both
(codes only), so neither keeps a copy.
"""

from __future__ import annotations

from dataclasses import dataclass

from .codes import Cell


@dataclass(frozen=True)
class Preset:
    """A preset of SPEC section 7: a default map, agent count, and recipe rule."""

    name: str
    map: str
    n_agents: int
    recipe_sizes: tuple[int, ...]
    steak: str  # "never" | "required" | "allowed"
    stations: tuple[Cell, ...]
    dirty_plates: bool
    dynamic: bool
    description: str


PRESETS: dict[str, Preset] = {
    "easy": Preset(
        "easy", "easy_open", 1, (1,), "never", (Cell.BOARD,), False, False,
        "one chopped vegetable; cutting boards; plates stay clean; static layout",
    ),
    "medium": Preset(
        "medium", "medium_kitchen", 1, (2, 3), "required", (Cell.BOARD, Cell.PAN, Cell.TRASH),
        False, False,
        "one steak + 1-2 chopped vegetables; boards, pan, trash; plates stay clean; static layout",
    ),
    "hard": Preset(
        "hard", "mapC", 2, (3,), "allowed",
        (Cell.BOARD, Cell.PAN, Cell.TRASH, Cell.SINK), True, True,
        "at least three ingredients, steak allowed; boards, pan, trash, sink; "
        "plates dirty after delivery; dynamic layout",
    ),
}


__all__ = ["PRESETS", "Preset"]

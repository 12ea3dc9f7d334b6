"""Kitchen words: the one place where cells, items, orders and actions get their plain names.

The ``text`` observation (:mod:`.observe_text`), the GUI's side panel and any natural-language
rendering of the planning problem read their words from here, so a cook described to a
language model, to a person at the window and in a PDDL problem's English version is the
same cook. Pure functions of a :class:`~.state.State`; stdlib only.

Small API: :data:`CELL_WORDS`, :data:`CELL_GLYPHS`, :data:`ACTION_WORDS` / :data:`ACTION_BY_WORD`,
:func:`state_word`, :func:`item_words`, :func:`recipe_words`, :func:`at`, :func:`cell_words`,
:func:`where_words`, :func:`action_words`, :func:`map_rows`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from .codes import Action, Item, ItemState, Where
from .orders import matching_order, plate_recipe
from .processes import ProcessTables, process_tables
from .queries import Bump, bump_effect
from .state import map_rows
from .stations import CELL_KINDS

if TYPE_CHECKING:
    from .state import State

#: what each cell code is called (from its record, :mod:`.stations`)
CELL_WORDS: dict[int, str] = {k.code: k.word for k in CELL_KINDS}
#: one character per cell code for a picture of the map (``State.describe``, the text
#: observation); an item lying on a spawn tile upper-cases its letter, on a plain counter it reads ``*``
CELL_GLYPHS: dict[int, str] = {k.code: k.letter for k in CELL_KINDS}
#: the word of each action, and back (a reply may also give the action's number)
ACTION_WORDS: dict[int, str] = {a: a.name.lower() for a in Action}
ACTION_BY_WORD: dict[str, int] = {w: a for a, w in ACTION_WORDS.items()}


def state_word(kind: int, item_state: int) -> str:
    """``"chopped"``, ``"raw"`` (a fresh steak), ``"clean"`` ..."""
    if kind == Item.STEAK and item_state == ItemState.FRESH:
        return "raw"
    return ItemState(item_state).name.lower()


def _kind_word(kind: int) -> str:
    return Item(kind).name.lower()


def _and(words: Sequence[str]) -> str:
    if len(words) <= 1:
        return "".join(words)
    return ", ".join(words[:-1]) + " and " + words[-1]


def item_words(state: State, item: int) -> str:
    """``"chopped tomato"``, ``"raw steak"``, ``"clean plate with chopped lettuce and cooked
    steak"``, ``"empty clean plate"``, ``"dirty plate"``."""
    kind = state.geo.item_kind[item]
    st = state.item_state[item]
    if kind != Item.PLATE:
        return f"{state_word(kind, st)} {_kind_word(kind)}"
    if st == ItemState.DIRTY:
        return "dirty plate"
    inside = sorted(item_words(state, i) for i in state.plate_contents(item))
    return f"clean plate with {_and(inside)}" if inside else "empty clean plate"


def recipe_words(recipe: Sequence[int], tables: ProcessTables | None = None) -> str:
    """``"chopped tomato + cooked steak"``: the ingredients a dish needs, ready to serve, in
    the states the rule set's process records make (``tables``; None: the shipped ones)."""
    tables = process_tables() if tables is None else tables
    return " + ".join(f"{state_word(k, tables.ready_of(k))} {_kind_word(k)}" for k in recipe)


def at(state: State, cell: int) -> str:
    """``"(row 2, col 3)"``."""
    r, c = state.geo.rc(cell)
    return f"(row {r}, col {c})"


def cell_words(state: State, cell: int) -> str:
    """``"the cutting board at (row 1, col 6)"`` (the current layout's cell)."""
    code = state.geo.terrains[state.layout_index][cell]
    return f"the {CELL_WORDS[code]} at {at(state, cell)}"


def where_words(state: State, item: int) -> str:
    """Where an item is: ``"on the pan at (row 8, col 5)"``, ``"held by cook 1"``,
    ``"on plate0"``, ``"waiting to reappear on the tomato counter at ..."``."""
    where, loc = state.item_where[item], state.item_loc[item]
    if where == Where.HAND:
        return f"held by cook {loc}"
    if where == Where.PLATE:
        return f"on {state.geo.item_names[loc]}"
    if where == Where.WAITING:
        return f"waiting to reappear on {cell_words(state, loc)} (it is occupied)"
    return f"on {cell_words(state, loc)}"


def _bump_words(state: State, effect: Bump, held: int, cell: int) -> str:
    here = state.cell_item[cell]
    place = cell_words(state, cell)
    if effect == Bump.PICK_UP:
        return f"pick up the {item_words(state, here)} from {place}"
    if effect == Bump.PUT_DOWN:
        return f"put your {item_words(state, held)} on {place}"
    if effect == Bump.ONTO_PLATE:
        return f"put your {item_words(state, held)} onto the {item_words(state, here)} on {place}"
    if effect == Bump.TAKE_ONTO_PLATE:
        return f"take the {item_words(state, here)} from {place} onto your plate"
    if effect in (Bump.CHOP, Bump.WASH, Bump.WORK):  # the station's record: verb, duration
        tables = state.rules.tables
        j = tables.by_code[state.geo.terrains[state.layout_index][cell]]
        done, need, verb = state.item_progress[here], tables.duration[j], tables.processes[j].verb
        if effect == Bump.WASH:
            return f"wash the dirty plate in {place} (wash {done + 1} of {need})"
        return f"{verb} the {item_words(state, here)} on {place} ({verb} {done + 1} of {need})"
    if effect == Bump.DELIVER:
        dish = item_words(state, held)
        idx = matching_order(state, plate_recipe(state, held)
                             if state.geo.item_kind[held] == Item.PLATE else None)
        if idx < 0:
            return f"serve your {dish} at {place} (it matches no order: it would be refused)"
        return f"serve your {dish} at {place} (it completes order {state.orders[idx].order_id})"
    if effect == Bump.TRASH:
        if state.geo.item_kind[held] == Item.PLATE:
            return f"empty your {item_words(state, held)} into {place}"
        return f"throw your {item_words(state, held)} into {place}"
    return f"bump {place}: nothing happens"


def action_words(state: State, agent: int, action: int) -> str:
    """What ``action`` would do for cook ``agent`` now, in words: ``"walk to (row 2, col 3)"``,
    ``"pick up the fresh tomato from the tomato counter at (row 0, col 2)"``, ... (read off
    :func:`~.queries.bump_effect`, the rule the transition itself uses)."""
    if action == Action.STAY:
        return "stay where you are"
    pos = state.agent_pos[agent]
    target = state.geo.neighbors[pos][action]
    if target < 0:
        return "bump the edge of the kitchen: nothing happens"
    if state.geo.walkables[state.layout_index][target]:
        if target in state.agent_pos:
            other = state.agent_pos.index(target)
            return (f"walk to {at(state, target)}, where cook {other} stands now "
                    "(blocked unless they move away)")
        return f"walk to {at(state, target)}"
    held = state.agent_hand[agent]
    return _bump_words(state, bump_effect(state, held, target), held, target)


__all__ = ["ACTION_BY_WORD", "ACTION_WORDS", "CELL_GLYPHS", "CELL_WORDS", "action_words", "at", "cell_words",
           "indefinite", "item_words", "map_rows", "recipe_words", "state_word", "where_words"]


def indefinite(words: str) -> str:
    """``"empty clean plate"`` -> ``"an empty clean plate"``, ``"raw steak"`` -> ``"a raw
    steak"``."""
    return ("an " if words[:1].lower() in "aeiou" else "a ") + words


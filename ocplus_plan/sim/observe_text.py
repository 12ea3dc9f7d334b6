"""The ``text`` observation: one cook's view of the kitchen in plain words (SPEC section 8).

For a language model used as a cook (:mod:`ocplus_plan.agents.llm`) or a person reading a
log: the map, the stations, every cook, every item, the open orders, the timers (pans,
boards, sinks, the next layout switch) and what each of the five actions would do for this
cook right now. Every word comes from :mod:`.words`; what an action does is read off the
transition's own rule (:func:`~.queries.bump_effect`), so the text never disagrees with
the simulator. stdlib only.

``text_observation(state, agent)`` is one cook's text; ``kitchen_text(state)`` the part
every cook shares; ``text_observations(state)`` one text per cook. All characters are in
:data:`TEXT_CHARSET` (printable ASCII and newline), the Gymnasium ``Text`` space's charset.
"""

from __future__ import annotations

import string

from ..errors import ConfigError
from .codes import Action, Cell, Item, ItemState, Where
from .processes import process_tables
from .queries import ticks_until_burnt, ticks_until_cooked
from .rules import Rules, recipe_name
from .stations import KIND_OF, WORK_PLACES
from .state import State
from .words import (
    ACTION_WORDS,
    CELL_GLYPHS,
    CELL_WORDS,
    action_words,
    at,
    cell_words,
    indefinite,
    item_words,
    map_rows,
    recipe_words,
    where_words,
)

#: the characters a text observation may contain
TEXT_CHARSET: str = "".join(sorted(set(string.printable) - set("\t\r\x0b\x0c")))
#: stations listed by name, in this order (work stations, then crates: see :mod:`.stations`)
_STATION_ORDER = tuple(k.code for k in WORK_PLACES)


def max_text_length(state: State) -> int:
    """A generous bound on the length of any text observation of this kitchen (for the
    Gymnasium ``Text`` space): every line grows with the map, the items or the orders."""
    geo, rules = state.geo, state.rules
    return 4000 + 60 * geo.rows * geo.cols + 400 * len(geo.item_kind) + 200 * (
        rules.n_orders + state.n_agents)


def _legend(state: State) -> str:
    present = set(state.geo.terrains[state.layout_index])
    parts = []
    for code, glyph in CELL_GLYPHS.items():
        if code in present and code != Cell.SPAWN:
            parts.append(f"{glyph} {CELL_WORDS[code]}")
    return ", ".join(parts)


def _stations(state: State) -> list[str]:
    terrain = state.geo.terrains[state.layout_index]
    out = []
    for code in _STATION_ORDER:
        cells = [f for f, c in enumerate(terrain) if c == code]
        if cells:
            name = CELL_WORDS[code] + ("s" if len(cells) > 1 else "")
            out.append(f"- {name} at {', '.join(at(state, f) for f in cells)}")
    return out


def _holding(state: State, agent: int) -> str:
    held = state.agent_hand[agent]
    return "nothing" if held < 0 else f"{indefinite(item_words(state, held))} ({state.geo.item_names[held]})"


def _timers(state: State) -> list[str]:
    rules, geo = state.rules, state.geo
    out = []
    for i, kind in enumerate(geo.item_kind):
        if state.item_where[i] != Where.CELL:
            continue
        cell, st, progress = state.item_loc[i], state.item_state[i], state.item_progress[i]
        what = f"the {item_words(state, i)} on {cell_words(state, cell)}"
        if cell in geo.pans and kind == Item.STEAK and st != ItemState.BURNT:
            burn = ticks_until_burnt(rules, progress)
            if st == ItemState.FRESH:
                out.append(f"- {what}: cooked in {ticks_until_cooked(rules, progress)} steps, "
                           f"burnt in {burn} steps unless taken off")
            else:
                out.append(f"- {what}: burnt in {burn} steps unless taken off")
        elif progress and kind != Item.STEAK and kind != Item.PLATE and st == ItemState.FRESH:
            out.append(f"- {what}: chopped {progress} of {rules.tables.work(kind)} times")
        elif progress and kind == Item.PLATE and st == ItemState.DIRTY:
            out.append(f"- {what}: washed {progress} of {rules.tables.work(kind)} times")
    if rules.dynamic and len(geo.terrains) > 1:
        due = max(0, state.next_switch - state.t)
        out.append(f"- the walls switch in {due} steps (walls move between "
                   f"{', '.join(at(state, f) for f in geo.switch_cells)}; a switch waits while a "
                   "cook stands on a cell that would close or an item lies on a counter that "
                   "would go)")
    return out


def rules_text(rules: Rules) -> str:
    """The rules of the kitchen in a few sentences, with this rule set's numbers (SPEC 1-5)."""
    work = process_tables(rules).duration_at
    lines = [
        ("Cooks move one cell per step onto floor; moving into anything else (a counter, a "
         "station, a wall) uses it instead, and the cook stays in place. Two cooks never "
         "share a cell or pass items hand to hand: hand things over on a counter."),
        ("Empty-handed, using a counter or a pan picks up what lies there (a cutting board "
         "chops the fresh vegetable on it instead, a sink washes the dirty plate in it). "
         "Holding something, using an empty counter puts it down."),
        (f"Vegetables are chopped on a cutting board: put the fresh vegetable there, then use "
         f"the board {work(Cell.BOARD)} times with empty hands."),
        ("Dishes are served on a clean plate: put chopped vegetables and cooked steak onto a "
         "plate (use the plate while holding the ingredient, or use the ingredient while "
         "holding the plate), then carry the plate to the serving window."),
    ]
    heat = process_tables(rules).station_of(int(Item.STEAK))  # the pan (an oven with steak)
    if any(Item.STEAK in r for r in rules.recipes) and heat >= 0:
        lines.append(f"A raw steak put {'on' if heat == Cell.PAN else 'in'} "
                     f"{indefinite(KIND_OF[heat].word)} cooks by itself: cooked after "
                     f"{work(heat)} steps, burnt after "
                     f"{process_tables(rules).overrun_at(heat) + 1}. Take it "
                     "off (or take it onto a plate) in time; the trash can takes burnt food "
                     "back to its counter fresh.")
    if rules.dirty_plates:
        lines.append(f"A served plate comes back dirty on its counter: put it in the sink and "
                     f"use the sink {work(Cell.SINK)} times with empty hands to clean it.")
    if rules.dynamic:
        lines.append(f"Some walls move every {rules.map_switch_step} steps.")
    earns = f"{rules.rewards.correct_delivery:g}"
    if any(v != rules.rewards.correct_delivery for v in rules.recipe_rewards):  # the dishes'
        earns = "its dish's reward (" + ", ".join(
            f"{recipe_name(r)} {v:g}" for r, v in zip(rules.recipes, rules.recipe_rewards)) + ")"
    lines.append(f"A served order earns {earns}; a plate that "
                 f"matches no order is refused ({rules.rewards.wrong_delivery:g}).")
    return "\n".join(lines)


def kitchen_text(state: State) -> str:
    """What every cook sees: the map, stations, cooks, items, orders and timers."""
    rules = state.rules
    lines = [(f"Kitchen {rules.layout.name} (preset {rules.preset}), step {state.t} of "
              f"{rules.horizon}. Places are (row, col), counted from 0 at the top-left corner."),
             (f"Map, one character per cell, row 0 first ({_legend(state)}; a digit is a "
              "cook):")]
    lines += [f"  {r:>2} {row}" for r, row in enumerate(map_rows(state, mark_items=False))]
    lines.append("Stations:")
    lines += _stations(state)
    lines.append("Cooks (a cook walks onto floor; moving into anything else uses it):")
    for a in range(state.n_agents):
        lines.append(f"- cook {a} at {at(state, state.agent_pos[a])}, holding "
                     f"{_holding(state, a)}")
    lines.append("Items:")
    for i, name in enumerate(state.geo.item_names):
        if state.item_where[i] not in (Where.PLATE, Where.HAND):
            lines.append(f"- {name}: {item_words(state, i)} {where_words(state, i)}")
    lines.append("Orders, oldest first (serve a clean plate holding exactly these):")
    for o in state.orders:
        left = (f"{max(0, o.deadline - state.t)} steps left" if o.deadline >= 0
                else "no time limit")
        lines.append(f"- order {o.order_id}: {recipe_words(o.recipe, rules.tables)} ({left})")
    timers = _timers(state)
    if timers:
        lines.append("Timers:")
        lines += timers
    return "\n".join(lines)


def actions_text(state: State, agent: int) -> str:
    """What each of the five actions would do for cook ``agent`` now, one per line."""
    return "\n".join(f"- {ACTION_WORDS[a]}: {action_words(state, agent, a)}" for a in Action)


def text_observation(state: State, agent: int, kitchen: str | None = None) -> str:
    """Cook ``agent``'s text observation (``kitchen``: a ready :func:`kitchen_text`)."""
    if not 0 <= agent < state.n_agents:
        raise ConfigError(f"cook {agent} does not exist: the kitchen has cooks "
                          f"0..{state.n_agents - 1}")
    shared = kitchen_text(state) if kitchen is None else kitchen
    return (f"You are cook {agent}, at {at(state, state.agent_pos[agent])}, holding "
            f"{_holding(state, agent)}.\n{shared}\nYour actions now:\n"
            f"{actions_text(state, agent)}")


def text_observations(state: State) -> list[str]:
    """One :func:`text_observation` per cook (the shared part is written once)."""
    shared = kitchen_text(state)
    return [text_observation(state, a, shared) for a in range(state.n_agents)]


__all__ = ["TEXT_CHARSET", "actions_text", "kitchen_text", "max_text_length", "rules_text", "text_observation",
           "text_observations"]

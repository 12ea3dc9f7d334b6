"""Kitchen words: items, recipes, places, and what an action would do (read off the rules)."""

from __future__ import annotations

import numpy as np

from ocplus_plan.sim import Item, ItemState, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.words import action_words, item_words, recipe_words, where_words

from .conftest import kitchen
from .helpers import give, item_of, on_plate, place, set_pos

G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]
R, D, L, U, S = (int(a) for a in Action)


def g_kitchen():
    return kitchen(G, [[1, 1]], preset="medium", recipes=["tomato+steak"])


def test_a_fresh_steak_is_called_raw():
    _, s = g_kitchen()
    assert item_words(s, item_of(s, Item.STEAK)) == "raw steak"


def test_a_plate_names_what_lies_on_it():
    _, s = g_kitchen()
    plate, tomato = item_of(s, Item.PLATE), item_of(s, Item.TOMATO)
    s.item_state[tomato] = int(ItemState.CHOPPED)
    on_plate(s, tomato, plate)
    assert item_words(s, plate) == "clean plate with chopped tomato"


def test_a_recipe_lists_its_ingredients_ready_to_serve():
    assert recipe_words((Item.TOMATO, Item.STEAK)) == "chopped tomato + cooked steak"


def test_where_words_names_the_holder():
    _, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    give(s, 0, tomato)
    assert where_words(s, tomato) == "held by cook 0"


def test_an_action_into_a_pan_with_a_steak_in_hand_puts_it_down():
    _, s = g_kitchen()
    give(s, 0, item_of(s, Item.STEAK))
    set_pos(s, 0, (1, 3))
    assert action_words(s, 0, U) == "put your raw steak on the pan at (row 0, col 3)"


def test_serving_a_plate_that_matches_no_order_says_it_would_be_refused():
    _, s = g_kitchen()
    plate = item_of(s, Item.PLATE)
    give(s, 0, plate)
    set_pos(s, 0, (1, 5))
    assert "it would be refused" in action_words(s, 0, R)


def test_chopping_counts_the_chops():
    _, s = g_kitchen()
    tomato = item_of(s, Item.TOMATO)
    place(s, tomato, (2, 2))
    set_pos(s, 0, (1, 2))
    assert action_words(s, 0, D).endswith("(chop 1 of 3)")


def test_every_described_action_does_what_its_words_say():
    """Random play on the hard preset: a walk ends on the named cell, a pick-up picks up,
    and 'nothing happens' changes nothing."""
    rules = make_rules("hard", n_agents=1)
    s = new_state(rules, 3)
    rng = np.random.default_rng(0)
    seen = set()
    for _ in range(300):
        action = int(rng.integers(0, 5))
        words = action_words(s, 0, action)
        before = (s.agent_pos[0], s.agent_hand[0], s.state_hash())
        events = [e.kind for e in transition(s, [action]).events]
        if words.startswith("walk to"):
            r, c = s.geo.rc(s.agent_pos[0])
            assert words == f"walk to (row {r}, col {c})"
            seen.add("walk")
        elif words.startswith("pick up"):
            assert "pickup" in events and s.agent_hand[0] >= 0
            seen.add("pick")
        elif words.startswith("put your"):
            assert {"putdown", "plate_add"} & set(events)
            seen.add("put")
        elif words.endswith("nothing happens"):
            assert s.agent_pos[0] == before[0] and s.agent_hand[0] == before[1]
            assert not {"pickup", "putdown", "chop", "wash", "delivery", "trash"} & set(events)
            seen.add("nothing")
    assert {"walk", "pick", "put", "nothing"} <= seen


def test_the_indefinite_article_follows_the_first_sound():
    from ocplus_plan.sim.words import indefinite

    assert indefinite("empty clean plate") == "an empty clean plate"
    assert indefinite("raw steak") == "a raw steak"

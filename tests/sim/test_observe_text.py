"""The text observation: what each cook reads, in plain words."""

from __future__ import annotations

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import Item, make_rules, new_state, transition
from ocplus_plan.sim.observe_text import (
    TEXT_CHARSET,
    max_text_length,
    text_observation,
    text_observations,
)

from .helpers import give, item_of, place


@pytest.fixture
def hard():
    return new_state(make_rules("hard", n_agents=2), 0)


def test_each_cook_is_told_who_it_is(hard):
    texts = text_observations(hard)
    assert [t.splitlines()[0].split(",")[0] for t in texts] == ["You are cook 0", "You are cook 1"]


def test_the_text_lists_the_open_orders(hard):
    text = text_observation(hard, 0)
    for o in hard.orders:
        assert f"order {o.order_id}: " in text


def test_the_text_lists_all_five_actions(hard):
    tail = text_observation(hard, 1).split("Your actions now:\n")[1].splitlines()
    assert [line.split(":")[0] for line in tail] == ["- right", "- down", "- left", "- up",
                                                     "- stay"]


def test_a_steak_on_the_pan_has_its_timer(hard):
    steak = item_of(hard, Item.STEAK)
    place(hard, steak, hard.geo.rc(hard.geo.pans[0]))
    hard.item_progress[steak] = 4
    assert "cooked in 6 steps, burnt in 17 steps" in text_observation(hard, 0)


def test_a_held_item_is_named_in_the_first_line(hard):
    give(hard, 0, item_of(hard, Item.TOMATO))
    assert "holding a fresh tomato (tomato0)" in text_observation(hard, 0).splitlines()[0]


def test_the_next_layout_switch_is_announced(hard):
    assert f"the walls switch in {hard.next_switch} steps" in text_observation(hard, 0)


def test_a_cook_that_does_not_exist_is_refused(hard):
    with pytest.raises(ConfigError, match="cook 2 does not exist"):
        text_observation(hard, 2)


def test_texts_stay_within_the_charset_and_the_length_bound(hard):
    for _ in range(40):
        transition(hard, [1, 2])
        for text in text_observations(hard):
            assert set(text) <= set(TEXT_CHARSET)
            assert len(text) <= max_text_length(hard)


def test_the_rules_in_words_carry_this_rule_sets_numbers():
    from ocplus_plan.sim.observe_text import rules_text

    text = rules_text(make_rules("easy", chop_steps=5))
    assert "use the board 5 times" in text
    assert "A raw steak" not in text and "A raw steak" in rules_text(make_rules("hard"))

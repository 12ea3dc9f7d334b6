from __future__ import annotations

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import Item, make_rules

VEG = {Item.TOMATO, Item.LETTUCE, Item.ONION}


def test_easy_recipes_are_one_chopped_vegetable():
    rules = make_rules("easy")
    assert rules.recipes and all(len(r) == 1 and r[0] in VEG for r in rules.recipes)
    assert not rules.dirty_plates and not rules.dynamic


def test_medium_recipes_are_one_steak_and_one_or_two_vegetables():
    rules = make_rules("medium")
    assert rules.recipes
    for r in rules.recipes:
        assert r.count(Item.STEAK) == 1 and 2 <= len(r) <= 3
        assert all(i in VEG for i in r if i != Item.STEAK)


def test_hard_recipes_have_three_or_more_and_dirty_plates_and_switches():
    rules = make_rules("hard")
    assert rules.recipes and all(len(r) >= 3 for r in rules.recipes)
    assert any(Item.STEAK in r for r in rules.recipes)
    assert rules.dirty_plates and rules.dynamic and rules.n_agents == 2


def test_recipe_pool_respects_the_number_of_spawn_tiles():
    # trio_kitchen has two tomato tiles, mapC one
    assert any(r.count(Item.TOMATO) == 2 for r in make_rules("hard", map="trio_kitchen").recipes)
    assert not any(r.count(Item.TOMATO) > 1 for r in make_rules("hard").recipes)


def test_any_parameter_can_be_overridden():
    rules = make_rules("hard", cook_time=5, burn_time=7, horizon=50, n_orders=3,
                       rewards={"correct_delivery": 100}, dynamic=False, recipes=["tomato+onion+lettuce"])
    assert (rules.cook_time, rules.burn_time, rules.horizon, rules.n_orders) == (5, 7, 50, 3)
    assert rules.rewards.correct_delivery == 100 and rules.rewards.wrong_delivery == -5
    assert rules.recipes == ((Item.TOMATO, Item.LETTUCE, Item.ONION),)


@pytest.mark.parametrize(
    "args, kw, words",
    [
        (("impossible",), {}, "unknown preset"),
        (("easy",), {"speed": 3}, "unknown rule parameter"),
        (("medium",), {"map": "easy_open"}, "needs pan"),
        (("hard",), {"map": "medium_kitchen"}, "dynamic"),
        (("easy",), {"n_agents": 3}, "at most 2"),
        (("easy",), {"recipes": ["steak"]}, "cannot be made"),
        (("easy",), {"recipes": ["pizza"]}, "unknown ingredient"),
        (("medium",), {"cook_time": 10, "burn_time": 5}, "burn_time"),
        (("easy",), {"rewards": {"tip": 1}}, "unknown reward"),
        (("easy",), {"horizon": 0}, "horizon"),
    ],
)
def test_impossible_configurations_are_clear_errors(args, kw, words):
    with pytest.raises(ConfigError, match=words):
        make_rules(*args, **kw)


def test_reward_keys_accept_the_papers_rewardlist_spelling():
    paper = {"subtask finished": 7, "correct delivery": 100, "wrong delivery": -1,
             "step penalty": 0.0, "burned penalty": -3}
    rules = make_rules("easy", rewards=paper)
    r = rules.rewards
    assert (r.subtask_finished, r.correct_delivery, r.wrong_delivery, r.step_penalty,
            r.burned_penalty) == (7, 100, -1, 0.0, -3)
    with pytest.raises(ConfigError, match="mapping"):
        make_rules("easy", rewards=[("step penalty", 1)])

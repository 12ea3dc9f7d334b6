"""The generator's drawn recipes: seeded, within what the kitchen can make, of the asked
lengths, and accepted by make_rules; bad arguments are refused naming the fix."""

from __future__ import annotations

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import load_kitchen, make_rules, new_state
from ocplus_plan.sim.generate_recipes import draw_recipes

KITCHEN = "gen:open:train:0:medium"


def test_a_menu_is_seeded_and_of_the_asked_lengths():
    layout = load_kitchen(KITCHEN)
    menu = draw_recipes(layout, 7, (2, 3), 3)
    assert menu == draw_recipes(layout, 7, (2, 3), 3) and len(set(menu)) == 3
    assert all(len(r.split("+")) in (2, 3) for r in menu)
    assert any(draw_recipes(layout, s, (2, 3), 3) != menu for s in range(8, 12))


def test_the_rules_take_a_drawn_menu_and_orders_come_from_it():
    layout = load_kitchen(KITCHEN)
    menu = draw_recipes(layout, 3, (3,), 2)
    rules = make_rules("medium", map=layout, recipes=menu)
    state = new_state(rules, 0)
    assert {"+".join(i.name.lower() for i in o.recipe) for o in state.orders} <= set(menu)


@pytest.mark.parametrize("kwargs, message", [
    ({"lengths": (0,)}, "from 1 to 6"), ({"count": 0}, "positive integer"),
    ({"steak": "sometimes"}, "never, required or allowed"),
    ({"lengths": (6,), "steak": "never"}, "can make no recipe"),
])
def test_bad_menu_arguments_are_refused_naming_the_fix(kwargs, message):
    with pytest.raises(ConfigError, match=message):
        draw_recipes(load_kitchen(KITCHEN), 0, **kwargs)


def test_a_drawn_menu_as_dishes_is_the_same_menu_in_records_a_kitchen_file_reads():
    from ocplus_plan.sim.dishes import dish_to_dict
    from ocplus_plan.sim.generate import map_from_name
    from ocplus_plan.sim.generate_recipes import draw_dishes
    from ocplus_plan.sim.maps import load_map

    layout = load_kitchen(KITCHEN)
    dishes = draw_dishes(layout, 7, (2, 3), 3, reward=120)
    assert ["+".join(k.name.lower() for k in d.recipe) for d in dishes] == \
        draw_recipes(layout, 7, (2, 3), 3)
    spec = dict(map_from_name(KITCHEN), recipes=[dish_to_dict(d) for d in dishes])
    rules = make_rules("medium", map=load_map(spec))
    assert rules.dishes == dishes and set(rules.recipe_rewards) == {120.0}

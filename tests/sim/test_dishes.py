"""Recipe records (dishes): a kitchen file's ``recipes`` is its menu, each dish with its
ingredients in their required states, its plate and its reward; the presets' pools are the
same records with the default reward; bad entries are refused naming the entry and the fix.
Map G (3x7):

    row 0:  counter steak counter pan  counter tomato counter
    row 1:  plate   .     .       .    .       .      delivery
    row 2:  counter trash board   sink counter counter counter
"""

from __future__ import annotations

import pytest

from ocplus_plan.cli import main
from ocplus_plan.errors import MapFormatError
from ocplus_plan.render.replay import layout_to_dict, rules_from_dict, rules_to_dict
from ocplus_plan.sim import Item, ItemState, make_rules, new_state
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.dishes import Dish, dish_of, dish_to_dict, parse_recipes
from ocplus_plan.sim.maps import load_map
from ocplus_plan.sim.observe_text import rules_text
from ocplus_plan.sim.presets import PRESETS
from ocplus_plan.sim.step import apply_bump
from ocplus_plan.sim.processes import PROCESSES

from .helpers import give, item_of, on_plate, run, set_pos

R, S = int(Action.RIGHT), int(Action.STAY)
G = [
    [1, 10, 1, 9, 1, 3, 1],
    [5, 0, 0, 0, 0, 0, 7],
    [1, 12, 6, 11, 1, 1, 1],
]
STEAK_TOMATO = [{"steak": "cooked"}, {"tomato": "chopped"}]


def g_map(recipes, **extra):
    return {"name": "g", "game_map": G, "agent_spawn_points": [[1, 1]], "recipes": recipes,
            **extra}


def test_a_kitchen_files_recipes_are_its_menu_with_their_rewards():
    rules = make_rules("medium", map=g_map([{"ingredients": STEAK_TOMATO, "reward": 260},
                                            {"ingredients": [{"tomato": "chopped"}]}]))
    assert rules.recipes == ((Item.TOMATO, Item.STEAK), (Item.TOMATO,))
    assert rules.recipe_rewards == (260.0, 200.0)  # none given: correct_delivery
    assert rules.dishes[0] == Dish(((Item.TOMATO, ItemState.CHOPPED),
                                    (Item.STEAK, ItemState.COOKED)), Item.PLATE, 260.0)


def _serving_tomato(rules):
    """Cook 0 at (1, 5), beside the window, holding a plate of chopped tomato."""
    state = new_state(rules, 0)
    plate, tomato = item_of(state, Item.PLATE), item_of(state, Item.TOMATO)
    give(state, 0, plate)
    on_plate(state, tomato, plate)
    state.item_state[tomato] = int(ItemState.CHOPPED)
    set_pos(state, 0, (1, 5))
    return state


def test_serving_a_dish_pays_its_reward():
    rules = make_rules("easy", map=g_map([{"ingredients": [{"tomato": "chopped"}],
                                           "reward": 30}]))
    state = _serving_tomato(rules)
    events, rewards = run(state, R)
    assert "delivery" in [e.kind for e in events]
    assert rewards[0] == [pytest.approx(30.0 + rules.rewards.step_penalty)]
    assert "A served order earns its dish's reward (tomato 30)" in rules_text(rules)


def test_a_bump_applied_alone_serves_the_dish_as_a_step_does():
    # apply_bump: one cook's interaction with the simulator's rules (a partner model
    # applies a predicted delivery to a copy of the state with it)
    rules = make_rules("easy", map=g_map([{"ingredients": [{"tomato": "chopped"}]}]))
    state = _serving_tomato(rules)
    alone, stepped = state.copy(), state.copy()
    events = apply_bump(alone, 0, state.geo.flat(1, 6))
    run(stepped, R)
    assert "delivery" in [e.kind for e in events]
    for name in ("agent_hand", "cell_item", "item_state", "item_where", "item_loc"):
        assert getattr(alone, name) == getattr(stepped, name)
    assert [o.recipe for o in alone.orders] == [o.recipe for o in stepped.orders]
    assert alone.t == state.t and state.agent_hand[0] == item_of(state, Item.PLATE)  # no tick


def test_the_presets_pools_are_dishes_of_the_default_reward_and_read_back_the_same():
    for name in PRESETS:
        rules = make_rules(name)
        assert [d.recipe for d in rules.dishes] == list(rules.recipes)
        assert set(rules.recipe_rewards) == {rules.rewards.correct_delivery}
        assert all(d == dish_of(d.recipe, PROCESSES) for d in rules.dishes)
        entries = [dish_to_dict(d) for d in rules.dishes]
        back = parse_recipes(entries, "<test>", PROCESSES, dict(rules.layout.stations))
        assert back == rules.dishes
        assert "its dish's reward" not in rules_text(rules)


def test_a_recording_keeps_the_kitchens_dishes():
    rules = make_rules("medium", map=g_map([{"ingredients": STEAK_TOMATO, "reward": 260}]))
    again = rules_from_dict("medium", layout_to_dict(rules), rules_to_dict(rules))
    assert again.recipe_rewards == (260.0,) and again.recipes == rules.recipes


@pytest.mark.parametrize("recipes, message", [
    ({"ingredients": STEAK_TOMATO}, r"'recipes' must be a list of 1 to 32 dishes"),
    ([], r"'recipes' must be a list of 1 to 32 dishes"),
    (["steak+tomato"], r"recipes\[0\] must be a mapping such as"),
    ([{"ingredients": STEAK_TOMATO, "price": 3}], r"recipes\[0\]: unknown key 'price'; allowed"),
    ([{"reward": 3}], r"recipes\[0\]: 'ingredients' must be a list of 1 to 6"),
    ([{"ingredients": [{"tomato": "chopped"}] * 7}], r"'ingredients' must be a list of 1 to 6"),
    ([{"ingredients": ["tomato"]}], r"each ingredient is a one-key mapping kind: state"),
    ([{"ingredients": [{"bread": "baked"}]}], r"ingredient 'bread' is not one of tomato, "),
    ([{"ingredients": [{"plate": "clean"}]}], r"ingredient 'plate' is not one of"),
    ([{"ingredients": [{"tomato": "sliced"}]}], r"tomato's state 'sliced' is not one of"),
    ([{"ingredients": [{"tomato": "fresh"}]}],
     r"recipes\[0\]: tomato must be chopped here \(the state its process makes, the only one "
     r"a plate takes\), not fresh"),
    ([{"ingredients": [{"steak": "burnt"}]}], r"steak must be cooked here"),
    ([{"ingredients": [{"lettuce": "chopped"}]}],
     r"recipes\[0\] needs 1 lettuce but the map has 0 spawn tile\(s\) for it \(code 4\)"),
    ([{"ingredients": [{"tomato": "chopped"}, {"tomato": "chopped"}]}],
     r"needs 2 tomato but the map has 1 spawn tile"),
    ([{"ingredients": [{"tomato": "chopped"}], "plate": "bowl"}],
     r"recipes\[0\]: plate 'bowl' is not one of plate"),
    ([{"ingredients": [{"tomato": "chopped"}], "reward": "lots"}],
     r"'reward' must be a number from -1e\+06 to 1e\+06, got 'lots'"),
    ([{"ingredients": [{"tomato": "chopped"}], "reward": float("nan")}], r"'reward' must be"),
    ([{"ingredients": [{"tomato": "chopped"}], "reward": True}], r"'reward' must be"),
    ([{"ingredients": [{"tomato": "chopped"}], "reward": 10**400}], r"'reward' must be"),
    ([{"ingredients": [{"tomato": "chopped"}], "reward": float("inf")}], r"'reward' must be"),
    ([{"ingredients": [{3: "chopped"}]}], r"ingredient '3' is not one of"),
    ([{"ingredients": [{"tomato": ["chopped"]}]}], r"tomato's state \"\['chopped'\]\" is not"),
    ([{"ingredients": [{"tomato": "chopped"}]}, {"ingredients": [{"tomato": "chopped"}]}],
     r"recipes\[1\] has the same ingredients as an earlier dish"),
])
def test_bad_recipes_are_refused_naming_the_entry_and_the_fix(recipes, message):
    with pytest.raises(MapFormatError, match=message) as err:
        load_map(g_map(recipes))
    assert str(err.value).startswith("<dict>: ") and "\n" not in str(err.value)


def test_an_ingredient_whose_station_is_missing_is_refused():
    no_pan = [row[:] for row in G]
    no_pan[0][3] = 1
    with pytest.raises(MapFormatError, match=r"recipes\[0\]: steak needs a pan \(code 9\) and "
                                             r"the map has none; add one or drop steak"):
        load_map({"game_map": no_pan, "agent_spawn_points": [[1, 1]],
                  "recipes": [{"ingredients": STEAK_TOMATO}]})


def test_check_map_lists_the_dishes_and_refuses_a_bad_one_in_one_line(tmp_path, capsys):
    import yaml

    good = tmp_path / "good.yaml"
    good.write_text(yaml.safe_dump(g_map([{"ingredients": STEAK_TOMATO, "reward": 260}])))
    assert main(["check-map", str(good)]) == 0
    assert "recipe    chopped tomato + cooked steak on a plate, reward 260" in \
        capsys.readouterr().out
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(g_map([{"ingredients": [{"tomato": "fresh"}]}])))
    assert main(["check-map", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "tomato must be chopped here" in err


def test_a_recipes_parameter_replaces_the_menu_and_a_declared_dish_keeps_its_reward():
    rules = make_rules("medium", map=g_map([{"ingredients": STEAK_TOMATO, "reward": 260}]),
                       recipes=["steak+tomato", "tomato"])
    assert rules.recipes == ((Item.TOMATO, Item.STEAK), (Item.TOMATO,))
    assert rules.recipe_rewards == (260.0, rules.rewards.correct_delivery)

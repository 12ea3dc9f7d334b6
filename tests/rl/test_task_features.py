"""The ``tasks`` observation: the path features plus what the orders still lack (numpy only)."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.agents.greedy_view import KitchenView
from ocplus_plan.errors import ConfigError
from ocplus_plan.rl.features import FeatureEncoder
from ocplus_plan.rl.obs import make_encoder
from ocplus_plan.rl.task_features import TASK_NAMES, TaskEncoder, unmet_need
from ocplus_plan.sim import Item, ItemState, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

from ..sim.helpers import give, item_of, place, set_pos, tomato_kitchen

R, D, L, U, S = (int(a) for a in Action)
_kitchen = tomato_kitchen


def _value(enc, x: np.ndarray, name: str) -> float:
    return float(x[enc.feature_names().index(name)])


def test_names_size_and_the_path_features_come_first():
    rules, state = _kitchen()
    enc = make_encoder("tasks", rules)
    assert isinstance(enc, TaskEncoder)
    assert enc.size == len(enc.feature_names()) == FeatureEncoder(rules).size + len(TASK_NAMES)
    x = enc.encode_all(state)
    assert x.shape == (2, enc.size) and np.all((x >= -1) & (x <= 1))
    np.testing.assert_array_equal(x[:, :-len(TASK_NAMES)], FeatureEncoder(rules).encode_all(state))


def test_a_chopped_tomato_on_the_counter_meets_the_need_the_path_features_still_show():
    rules, state = _kitchen()
    enc = TaskEncoder(rules)
    x = enc.encode_all(state)[0]
    assert _value(enc, x, "unmet:tomato") == 0.5 and _value(enc, x, "unmet_fresh:present") == 1
    tomato = item_of(state, Item.TOMATO)
    place(state, tomato, (1, 5))
    state.item_state[tomato] = int(ItemState.CHOPPED)
    x = enc.encode_all(state)[0]
    assert _value(enc, x, "unmet:tomato") == 0.0 and _value(enc, x, "unmet_fresh:present") == 0
    assert _value(enc, x, "wanted_ready:present") == 1  # the path features see it either way


def test_unmet_fresh_points_the_way_and_says_when_the_other_cook_is_nearer():
    rules, state = _kitchen()
    enc = TaskEncoder(rules)
    x = enc.encode_all(state)
    # cook 0 at (1, 1) bumps the tomato at (0, 1) by going up; cook 1 at (2, 4) is farther
    assert _value(enc, x[0], "unmet_fresh:go_up") == 1.0
    assert _value(enc, x[0], "unmet_fresh:cost") == pytest.approx(1 / 20)
    assert _value(enc, x[0], "unmet_fresh:other_nearer") == 0.0
    assert _value(enc, x[1], "unmet_fresh:other_nearer") == 1.0


def test_plate_ready_points_to_what_a_matched_plate_misses():
    rules, state = _kitchen()
    enc = TaskEncoder(rules)
    assert _value(enc, enc.encode_all(state)[0], "plate_ready:present") == 0  # nothing ready
    tomato = item_of(state, Item.TOMATO)
    place(state, tomato, (0, 3))  # chopped, on the board
    state.item_state[tomato] = int(ItemState.CHOPPED)
    give(state, 1, item_of(state, Item.PLATE))  # cook 1 holds a clean plate: matched to the order
    set_pos(state, 0, (1, 3))
    x = enc.encode_all(state)[0]
    assert _value(enc, x, "plate_ready:go_up") == 1.0 and _value(enc, x, "plate_ready:present")
    assert _value(enc, x, "free_boards") == 0.0


def test_unmet_need_is_what_the_greedy_cook_counts():
    """On the states of a greedy episode (medium, 2 cooks) the need less the supply and the
    matched plates' missing ingredients equal greedy's own bookkeeping."""
    rules = make_rules("medium", n_agents=2)
    state = new_state(rules, 1)
    cook = GreedyAgent(1)
    cook.reset(state)
    for _ in range(120):
        view = KitchenView(state, driven=2)
        unmet, missing = unmet_need(state)
        assert unmet == Counter({k: n - view.supply[k] for k, n in view.need.items()
                                 if n > view.supply[k]})
        assert +missing == +sum(view.plate_missing.values(), Counter())
        result = transition(state, cook.act(state))
        cook.observe(state, result.events)


def test_training_on_tasks_runs_on_the_loop_engine():
    from ocplus_plan.rl.train import TrainConfig

    assert TrainConfig(obs="tasks").engine == "loop"
    with pytest.raises(ConfigError, match="--engine loop"):
        TrainConfig(obs="tasks", engine="batch").validate()

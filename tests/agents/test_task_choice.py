"""The task-choice controller: a policy picks each free cook's subtask among those the greedy
cook would consider, and the greedy cook's skills move (numpy only)."""

from __future__ import annotations

import numpy as np
import pytest

from ocplus_plan.agents import make_controller
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.agents.task_choice import FEATURES, KINDS, SLOTS, TaskChoice
from ocplus_plan.rl.task_features import TaskEncoder
from ocplus_plan.sim import Item, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action
from ocplus_plan.sim.records import Order

from ..sim.helpers import give, item_of, tomato_kitchen

R, D, L, U, S = (int(a) for a in Action)
_kitchen = tomato_kitchen


def _slots(rules, obs: np.ndarray) -> np.ndarray:
    return obs[:, TaskEncoder(rules).size:].reshape(len(obs), SLOTS, FEATURES)


def _kind(row: np.ndarray) -> str:
    return KINDS[int(np.argmax(row[1:1 + len(KINDS)]))]


def test_the_observation_is_the_tasks_vector_then_one_row_per_slot():
    rules, state = _kitchen()
    chooser = TaskChoice(0)
    chooser.reset(state)
    obs = chooser.prepare(state)
    assert obs.shape == (2, TaskChoice.obs_size(rules))
    np.testing.assert_array_equal(obs[:, :TaskEncoder(rules).size],
                                  TaskEncoder(rules).encode_all(state))
    slots = _slots(rules, obs)
    # the one subtask: fetch the tomato; the cook beside it sees another cook is not nearer
    assert slots[0, 0, 0] == 1 and _kind(slots[0, 0]) == "fetch"
    assert slots[0, 0, 1 + len(KINDS)] == 1  # its item is a tomato
    assert slots[0, 0, -1] == 0 and slots[1, 0, -1] == 1  # cook 0 is nearer than cook 1
    assert slots[0, 0, -3] < slots[1, 0, -3]  # the walking cost
    assert not slots[:, 1:].any()  # the other slots are empty


def test_a_cook_that_holds_something_has_no_slots_and_carries_it_as_greedy_does():
    rules, state = _kitchen()
    give(state, 0, item_of(state, Item.TOMATO))
    chooser, greedy = TaskChoice(0), GreedyAgent(0)
    chooser.reset(state)
    greedy.reset(state)
    assert not _slots(rules, chooser.prepare(state))[0].any()
    assert chooser.drive(state, [SLOTS, SLOTS])[0] == greedy.act(state)[0]


def test_slot_zero_walks_to_the_subtask_and_none_leaves_the_cook_idle():
    rules, state = _kitchen(spawns=([1, 3], [2, 4]))
    chooser = TaskChoice(0)
    chooser.reset(state)
    chooser.prepare(state)
    assert chooser.drive(state, [0, SLOTS])[0] == L  # towards the tomato at (0, 1)
    chooser.prepare(state)
    assert chooser.drive(state, [SLOTS, SLOTS]) == [S, S]
    chooser.prepare(state)
    assert chooser.drive(state, [3, SLOTS])[0] == S  # an empty slot: idle too


def test_two_cooks_that_pick_one_subtask_do_not_both_take_it():
    rules, state = _kitchen()
    chooser = TaskChoice(0)
    chooser.reset(state)
    chooser.prepare(state)
    chooser.drive(state, [0, 0])
    assert chooser.tasks[0] is not None and chooser.tasks[1] is None


def test_the_current_subtask_stays_in_slot_zero():
    rules, state = _kitchen(spawns=([1, 4], [2, 1]))
    state.orders.append(Order(1, (int(Item.LETTUCE),), 0, 10_000))
    chooser = TaskChoice(0)
    chooser.reset(state)
    slots = _slots(rules, chooser.prepare(state))
    assert slots[0, 0, -2] == 0 and slots[0, 1, 0] == 1  # two subtasks, nothing current yet
    far = int(np.argmax(slots[0, :2, -3]))  # cook 0 takes the farther one
    item = int(np.argmax(slots[0, far, 1 + len(KINDS):-3]))
    transition(state, chooser.drive(state, [far, SLOTS]))
    slots = _slots(rules, chooser.prepare(state))
    assert slots[0, 0, -2] == 1 and slots[0, 1, -2] == 0  # slot 0, whatever its cost now
    assert int(np.argmax(slots[0, 0, 1 + len(KINDS):-3])) == item


def test_drive_needs_prepare_on_the_same_state():
    rules, state = _kitchen()
    chooser = TaskChoice(0)
    chooser.reset(state)
    with pytest.raises(RuntimeError, match="prepare"):
        chooser.drive(state, [0, 0])
    chooser.prepare(state)
    with pytest.raises(ValueError, match="2 cooks"):
        chooser.drive(state, [0])


def test_without_a_policy_it_takes_the_current_or_nearest_subtask_and_serves():
    rules = make_rules("easy", n_agents=2)
    state = new_state(rules, 0)
    chooser = make_controller("nearest", 0)  # the registered agent: the options, no learning
    assert isinstance(chooser, TaskChoice) and chooser.choose is None
    chooser.reset(state)
    while not state.done:
        transition(state, chooser.act(state))
    assert state.stats["dishes_served"] >= 3

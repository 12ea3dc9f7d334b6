"""The scripted greedy controller: it serves dishes on every preset and never breaks rules."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import StayAgent, Team, make_controller
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import available_maps, conservation_problems, make_rules, new_state, transition


def _episode(rules, seed: int, controller=None):
    state = new_state(rules, seed)
    ctrl = controller or make_controller("greedy", seed)
    ctrl.reset(state)
    actions = []
    while not state.done:
        joint = ctrl.act(state)
        assert len(joint) == rules.n_agents and all(0 <= a <= 4 for a in joint)
        actions.append(tuple(joint))
        transition(state, joint)
        assert not conservation_problems(state)
    return state, actions


@pytest.mark.parametrize(("preset", "n_agents", "at_least"), [
    ("easy", 1, 7), ("easy", 2, 9), ("medium", 1, 2), ("medium", 2, 4), ("hard", 2, 2),
])
def test_serves_several_dishes_per_200_step_episode(preset, n_agents, at_least):
    rules = make_rules(preset, n_agents=n_agents)
    for seed in (0, 1):
        state, _ = _episode(rules, seed)
        assert state.stats["dishes_served"] >= at_least, (preset, n_agents, seed, state.stats)
        assert state.stats["wrong_deliveries"] == 0
        assert state.stats["burns"] == 0


def test_hard_preset_washes_plates_and_lives_through_layout_switches():
    state, _ = _episode(make_rules("hard", n_agents=2), 0)
    assert state.stats["washes"] >= 1 and state.stats["layout_switches"] >= 3
    assert state.stats["dishes_served"] >= 2


def test_hands_over_through_the_counter_wall():
    """easy_divided: tomatoes and the window are on one side, the boards on the other."""
    rules = make_rules("easy", map="easy_divided", n_agents=2)
    g = GreedyAgent(0)
    state, _ = _episode(rules, 0, g)
    assert state.stats["dishes_served"] >= 4
    assert g.info()["greedy_handovers"] >= 4


def test_is_deterministic_per_seed():
    rules = make_rules("medium", n_agents=2)
    assert _episode(rules, 3)[1] == _episode(rules, 3)[1]


def test_never_causes_collisions_between_its_own_cooks():
    rules = make_rules("easy", map="trio_kitchen", n_agents=3)
    state = new_state(rules, 0)
    g = make_controller("greedy", 0)
    g.reset(state)
    blocked = 0
    while not state.done:
        result = transition(state, g.act(state))
        blocked += sum(e.kind == "move_blocked" for e in result.events)
    assert blocked == 0 and state.stats["dishes_served"] >= 5


def _valid_kitchens():
    for preset in ("easy", "medium", "hard"):
        for name in sorted(available_maps()):
            for n in (1, 2, 3):
                try:
                    yield make_rules(preset, map=name, n_agents=n, horizon=100)
                except ConfigError:
                    continue


def test_runs_on_every_shipped_map_preset_and_agent_count():
    kitchens = list(_valid_kitchens())
    assert len(kitchens) >= 30
    served = 0
    for rules in kitchens:
        state, _ = _episode(rules, 0)
        served += state.stats["dishes_served"] > 0
    assert served >= len(kitchens) - 8  # one-cook MapC and the 1-lane corridor are the hard ones


def test_drives_a_subset_of_the_cooks_in_a_team():
    rules = make_rules("easy", n_agents=2)
    team = Team([StayAgent(), GreedyAgent(0)], [[0], [1]])
    state = new_state(rules, 0)
    team.reset(state)
    while not state.done:
        transition(state, team.act(state))
    assert state.agent_pos[0] == new_state(rules, 0).agent_pos[0]
    assert state.stats["dishes_served"] >= 4


def test_relays_items_down_a_one_lane_corridor():
    """corridor3: nobody can pass anybody, so carried items go cook to cook via counters."""
    rules = make_rules("easy", map="corridor3", n_agents=2)
    g = GreedyAgent(0)
    state, _ = _episode(rules, 0, g)
    assert g.info().get("greedy_relays", 0) >= 1
    assert state.stats["dishes_served"] >= 2

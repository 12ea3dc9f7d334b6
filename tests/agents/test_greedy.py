"""The scripted greedy controller: it serves dishes on every preset and never breaks rules."""

from __future__ import annotations

import pytest

from ocplus_plan.agents import StayAgent, Team, make_controller
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import available_maps, conservation_problems, make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, ItemState, Where


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


def test_a_greedy_partner_alone_on_its_side_of_a_switching_kitchen_waits_for_the_switch():
    # hard, 2 cooks, greedy driving only the second: nothing is in its reach in the first
    # layout, and it has no teammate to hand over to, so it plans over both layouts (as a
    # lone cook does) instead of standing still for the whole episode
    rules = make_rules("hard", n_agents=2, horizon=60)
    team = Team([GreedyAgent(0), GreedyAgent(0)], [[0], [1]])
    state = new_state(rules, 0)
    team.reset(state)
    moves = 0
    while not state.done:
        joint = team.act(state)
        moves += joint[1] != int(Action.STAY)
        transition(state, joint)
    assert moves >= 20
    assert team.controllers[1].counts["task_fetch"] >= 1


def test_relays_items_down_a_one_lane_corridor():
    """corridor3: nobody can pass anybody, so carried items go cook to cook via counters."""
    rules = make_rules("easy", map="corridor3", n_agents=2)
    g = GreedyAgent(0)
    state, _ = _episode(rules, 0, g)
    assert g.info().get("greedy_relays", 0) >= 1
    assert state.stats["dishes_served"] >= 2


def test_where_a_cook_carries_things_is_what_the_bump_there_does():
    """On sampled states, every destination the greedy cook picks for what it holds gets the
    interaction its label promises when the cook bumps it (the step decides, not a copy of
    the rules in the controller)."""
    from ocplus_plan.agents.greedy_view import KitchenView
    from ocplus_plan.sim.queries import direction, interaction_spots

    from ..sim.helpers import run, sampled_states

    promised = {"to_board": "putdown", "to_pan": "putdown", "to_sink": "putdown",
                "put_down": "putdown", "handover": "putdown", "relay": "putdown",
                "deliver": "delivery", "trash": "trash", "empty_plate": "trash",
                "to_plate": "plate_add", "collect": "plate_add"}
    checked = set()
    for preset in ("easy", "medium", "hard"):
        for state in sampled_states(preset, 2, 30, seed=3, max_steps=199):
            cook = GreedyAgent(0)
            cook.reset(state)
            view = KitchenView(state)
            for a in range(state.n_agents):
                if state.agent_hand[a] < 0:
                    continue
                goal = cook._carry(view, a, set(), cook._budgets(view))
                if goal is None or goal[1] not in promised:
                    continue  # nothing to do, or waiting by a busy station (a harmless bump)
                cell, label = goal
                walk = state.geo.walkables[state.layout_index]
                spots = [p for p in interaction_spots(state.geo.neighbors, walk, cell)
                         if p not in state.agent_pos or p == state.agent_pos[a]]
                if not spots:
                    continue
                copy = state.copy()
                copy.agent_pos[a] = spots[0]
                joint = [int(Action.STAY)] * copy.n_agents
                joint[a] = direction(state.geo, spots[0], cell)
                ev, _ = run(copy, joint)
                assert promised[label] in {e.kind for e in ev if e.agent == a}, \
                    (preset, state.t, a, label, state.geo.rc(cell))
                checked.add(label)
    assert {"to_board", "to_pan", "to_plate", "deliver", "to_sink", "put_down"} <= checked, checked


# one lettuce crate, one or two steak crates, a board, the trash, the window; a plate far
# from the pan (1,0) and one beside it (0,5); the cook stands at the pan (1,6) with a
# cooked steak
PLATES = [[1, 6, 12, 1, 1, 5, 1],
          [5, 0, 0, 0, 0, 0, 9],
          [1, 4, 10, 7, 1, 1, 1]]


def _steak_in_hand(steak_crates: int):
    from ocplus_plan.sim.codes import Item, ItemState

    from ..sim.helpers import give, item_of, on_plate, set_pos

    grid = [list(r) for r in PLATES]
    if steak_crates == 2:
        grid[2][4] = 10
    m = {"name": "plates", "max_n_agent": 1, "game_map": grid, "agent_spawn_points": [[1, 3]]}
    state = new_state(make_rules("medium", map=m, n_agents=1, recipes=["lettuce+steak"]), 0)
    far = next(p for p in range(state.n_items) if state.item_loc[p] == state.geo.flat(1, 0))
    lettuce, steak = item_of(state, Item.LETTUCE), item_of(state, Item.STEAK)
    state.item_state[lettuce] = int(ItemState.CHOPPED)
    on_plate(state, lettuce, far)
    state.item_state[steak] = int(ItemState.COOKED)
    give(state, 0, steak)
    set_pos(state, 0, (1, 5))
    return state


@pytest.mark.parametrize(("steak_crates", "plate"), [(1, (1, 0)), (2, (0, 5))])
def test_the_last_of_its_kind_goes_onto_a_plate_that_holds_food(steak_crates, plate):
    """With one steak in the kitchen, the cooked steak goes onto the far plate holding the
    lettuce, not the empty one beside the pan (that would leave the lettuce's plate
    unfinishable for good); with a second steak it goes onto the nearest plate, as before."""
    from ocplus_plan.agents.greedy_view import KitchenView

    state = _steak_in_hand(steak_crates)
    cook = GreedyAgent(0)
    cook.reset(state)
    view = KitchenView(state)
    assert cook._carry(view, 0, set(), cook._budgets(view)) == (state.geo.flat(*plate),
                                                               "to_plate")


# a one-lane way along row 1; (0, 2)'s plate crate is worked from (1, 2) alone
WAY = [[1, 1, 5, 1, 1, 1],
       [7, 0, 0, 0, 0, 6],
       [1, 3, 1, 1, 1, 1]]


def test_an_idle_cook_moves_off_for_a_cook_it_does_not_drive_that_waits_beside_it():
    """Greedy knows nothing of a partner's goal: an idle greedy cook standing on the only
    cell in front of the plate crate, beside a partner that has stood still there for
    ``_WAITING`` steps, moves off it, and not to another cell beside that partner."""
    from ocplus_plan.agents.greedy_moves import _WAITING
    from ocplus_plan.agents.greedy_view import KitchenView

    m = {"name": "t", "game_map": WAY, "max_n_agent": 2, "agent_spawn_points": [[1, 1], [1, 2]]}
    state = new_state(make_rules("easy", map=m, n_agents=2), 0)
    g = GreedyAgent(0)
    g.reset(state, [1])
    partner, idle = state.agent_pos
    moves = []
    for _ in range(_WAITING + 1):  # the greedy cook idle (no goal), the partner staying
        g._active(state)  # what ``goals`` notes of the partner each step
        moves.append(g._moves(KitchenView(state, driven=1), {})[0])
        transition(state, [int(Action.STAY), moves[-1]])
    assert moves[:_WAITING] == [int(Action.STAY)] * _WAITING
    assert moves[-1] == int(Action.RIGHT)  # off the crate's only cell, away from the partner
    assert state.agent_pos == [partner, idle + 1]


# one board, worked from (1,1) alone; the tomato and lettuce crates, a plate and the window
ONE_BOARD = [[1, 6, 1, 3, 1, 1],
             [1, 0, 0, 0, 0, 4],
             [1, 7, 1, 5, 1, 1]]


def test_a_greedy_partner_at_the_only_board_chops_the_raw_vegetable_lying_there():
    """A partner (cook 0, not driven) left a raw tomato on the only board; the greedy cook
    (1) holds the lettuce and stands in the board's only way in. Waiting there for the board
    to be free would wait for ever (nobody else can get to it): it puts the lettuce down
    and chops the tomato."""
    spec = {"name": "one-board", "game_map": ONE_BOARD,
            "agent_spawn_points": [[1, 3], [1, 1]]}
    state = new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                 horizon=30), 0)
    geo = state.geo
    board, tomato_crate, lettuce_crate = geo.flat(0, 1), geo.flat(0, 3), geo.flat(1, 5)
    tomato, lettuce = state.cell_item[tomato_crate], state.cell_item[lettuce_crate]
    state.cell_item[tomato_crate], state.cell_item[board] = -1, tomato  # the partner's tomato
    state.item_loc[tomato] = board
    state.cell_item[lettuce_crate] = -1  # the greedy cook holds the lettuce
    state.item_where[lettuce], state.item_loc[lettuce] = int(Where.HAND), 1
    state.agent_hand[1] = lettuce
    assert not conservation_problems(state)
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    for _ in range(10):
        transition(state, [int(Action.STAY), *greedy.act(state)])
    assert greedy.counts["drops_for_board"] == 1
    assert state.item_state[tomato] == ItemState.CHOPPED
    assert state.item_where[lettuce] == Where.CELL
    assert not conservation_problems(state)

"""The partner model on hand-drawn kitchens: predictions, the state planned from, repairs,
and the walks the executive's paths keep clear."""

from __future__ import annotations

from collections import deque

import pytest

from ocplus_plan.agents import StayAgent
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.agents.partner_model import PartnerModel
from ocplus_plan.execution.executive import Executive, PlanOutcome
from ocplus_plan.execution.partner import (
    Prediction,
    answer_taken,
    brings,
    delivering,
    hand_off,
    onto_our_plate,
    ours_first,
    predicted_state,
    repair_taken,
    reserved_walks,
    shut_out,
    vacate,
)
from ocplus_plan.execution.plans import PlanStep
from ocplus_plan.execution.queue_check import check_queues, known_when_planned
from ocplus_plan.execution.tasks import Task, ready
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action, Cell, ItemState, Where
from ocplus_plan.sim.queries import distances, interaction_spots

# board on top, tomato crate left, window right, plate below; our cook 0 right, partner 1 left
KITCHEN = {"name": "two", "max_n_agent": 2,
           "game_map": [[1, 1, 6, 1, 1],
                        [3, 0, 0, 0, 7],
                        [1, 5, 1, 1, 1]],
           "agent_spawn_points": [[1, 3], [1, 1]]}
# one lane from the crate to the board: the partner stands in the middle of it
LANE = {"name": "lane", "max_n_agent": 2,
        "game_map": [[1, 1, 1, 1, 1, 1, 1],
                     [3, 0, 0, 0, 0, 0, 6],
                     [1, 7, 1, 1, 1, 5, 1]],
        "agent_spawn_points": [[1, 1], [1, 3]]}
S, L = int(Action.STAY), int(Action.LEFT)


def _state(spec, horizon=60):
    return new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                horizon=horizon), 0)


def _carrying_partner():
    """The partner (cook 1) has just taken the tomato from its crate."""
    state = _state(KITCHEN)
    transition(state, [S, L])
    tomato = state.agent_hand[1]
    assert tomato >= 0
    return state, tomato


def test_a_greedy_partner_carrying_the_needed_item_is_predicted_by_its_own_policy():
    state, _tomato = _carrying_partner()
    model = PartnerModel(GreedyAgent(0))
    model.reset(state, [0])
    pred = model(state)[1]
    board = state.geo.flat(0, 2)
    assert pred.target == board
    assert pred.path == (state.geo.flat(1, 2),)  # one step right, then it bumps up


def test_work_the_partner_is_about_to_do_is_not_planned_again():
    # the state the planner is asked about has the tomato on the board already: the plan
    # chops it there instead of fetching another one, and the partner is not modelled
    state, tomato = _carrying_partner()
    board = state.geo.flat(0, 2)
    problem = predicted_state(state, {1: Prediction(1, board, (state.geo.flat(1, 2),))})
    assert problem.cell_item[board] == tomato and problem.agent_hand[1] == -1
    assert problem.item_where[tomato] == Where.CELL
    assert state.agent_hand[1] == tomato  # the real state is left alone
    # a queued step on the tomato waits while the partner still carries it
    chop = Task(PlanStep(0, 0, "chop", board, (tomato,)), frozenset())
    assert not ready(state, 0, chop, set())


def test_a_partner_that_takes_an_item_repairs_the_plan_instead_of_replacing_it():
    state, tomato = _carrying_partner()
    crate, board = state.geo.flat(1, 0), state.geo.flat(0, 2)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    steps = [PlanStep(0, 0, "pickup", crate, (tomato,)), PlanStep(1, 0, "putdown", board, (tomato,)),
             PlanStep(2, 0, "chop", board, (tomato,)), PlanStep(3, 0, "pickup", board, (tomato,)),
             PlanStep(4, 0, "plate", 11, (plate, tomato))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    done: set[int] = set()
    preds = {1: Prediction(1, board)}
    assert answer_taken(state, queues[0][0], queues, done, preds) == "repaired"
    assert [t.step.kind for t in queues[0]] == ["chop", "pickup", "plate"]
    assert done == {0, 1}
    # now the plan counts on the partner's bump: no replan
    assert answer_taken(state, queues[0][0], queues, done, preds) == "expected"
    # a partner predicted to take the item elsewhere does not fit: plan again
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    assert answer_taken(state, queues[0][0], queues, set(),
                        {1: Prediction(1, state.geo.flat(1, 4))}) == "taken"
    assert not repair_taken(queues, set(), tomato, None)
    assert len(queues[0]) == 5


def test_a_step_of_the_items_next_life_does_not_fit_a_partners_bump():
    # two dishes from the crate's one tomato: the first is served (the tomato goes home),
    # then the tomato is fetched again and, for the second, put down on the counter right of
    # the crate. The partner carrying the tomato of the first dish to that counter does not
    # fit: dropping the first dish's steps would drop its delivery too
    state, tomato = _carrying_partner()
    crate, board, window = state.geo.flat(1, 0), state.geo.flat(0, 2), state.geo.flat(1, 4)
    counter = state.geo.flat(0, 3)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    first = [PlanStep(0, 0, "pickup", crate, (tomato,)),
             PlanStep(1, 0, "putdown", board, (tomato,)),
             PlanStep(2, 0, "chop", board, (tomato,)),
             PlanStep(3, 0, "plate", board, (plate, tomato)),
             PlanStep(4, 0, "deliver", window, (plate, tomato))]
    second = [PlanStep(5, 0, "pickup", crate, (tomato,)),
              PlanStep(6, 0, "putdown", counter, (tomato,))]
    queues = {0: deque(Task(s, frozenset()) for s in first + second)}
    assert not repair_taken(queues, set(), tomato, counter)
    assert len(queues[0]) == 7
    assert repair_taken(queues, done := set(), tomato, board)  # the first life fits
    assert done == {0, 1} and [t.step.index for t in queues[0]] == [2, 3, 4, 5, 6]


def test_a_partner_blocking_the_only_corridor_is_a_wall_in_the_plan_and_in_the_paths():
    state = _state(LANE)
    model = PartnerModel(StayAgent())
    model.reset(state, [0])
    for _ in range(model.patience):
        transition(state, [S, S])
        preds = model(state)
    assert preds[1].target is None  # it has not moved: it is expected to stay
    problem = predicted_state(state, preds)
    board = state.geo.flat(1, 6)
    spot = interaction_spots(state.geo.neighbors, state.geo.walkables[0], board)[0]
    reach = distances(problem.geo.neighbors, problem.geo.walkables[0], [state.agent_pos[0]])
    assert reach[spot] < 0  # the board is cut off in the problem
    reach = distances(state.geo.neighbors, state.geo.walkables[0], [state.agent_pos[0]])
    assert reach[spot] > 0  # (not in the kitchen itself)
    assert reserved_walks(state, preds, {0: None}) == {1: state.agent_pos[1]}


def test_a_partner_walking_down_the_corridor_has_its_walk_reserved():
    state = _state(LANE)
    transition(state, [S, L])  # partner one step left: next to our cook
    model = PartnerModel(GreedyAgent(0))
    model.reset(state, [0])
    pred = model(state)[1]
    assert pred.target is not None and pred.path
    walk = reserved_walks(state, {1: pred}, {0: ["a step"]})[1]
    if state.agent_pos[0] in (state.agent_pos[1], *pred.path):
        assert walk == state.agent_pos[1]  # through our busy cook: it cannot pass; it stays
    else:
        assert walk == (state.agent_pos[1], *pred.path[:8])
    # our cook with nothing to do steps off the partner's walk: it is reserved whole
    assert reserved_walks(state, {1: pred}, {0: None})[1] == (state.agent_pos[1], *pred.path[:8])


# the partner takes the tomato at the crate, far from the only board
WANDER = {"name": "wander", "max_n_agent": 2,
          "game_map": [[1, 1, 1, 1, 1, 1, 1],
                       [3, 0, 0, 0, 0, 0, 6],
                       [1, 0, 0, 0, 0, 0, 1],
                       [1, 7, 1, 1, 1, 5, 1]],
          "agent_spawn_points": [[2, 5], [1, 1]]}


def _wandering_partner():
    state = _state(WANDER)
    transition(state, [S, L])  # the partner takes the tomato
    assert state.agent_hand[1] >= 0
    model = PartnerModel(StayAgent())
    model.reset(state, [0])
    board = state.geo.flat(1, 6)
    assert model(state)[1].target == board  # guessed: it carries the tomato to the board
    return state, model, board


def test_a_guess_the_partner_does_not_follow_is_dropped():
    # it paces up and down beside the crate, never closer to the board: after ``doubt``
    # steps it is expected to stay (our cook no longer keeps the way clear for it)
    state, model, board = _wandering_partner()
    for k in range(1, model.doubt + 1):
        transition(state, [S, int(Action.DOWN) if k % 2 else int(Action.UP)])
        pred = model(state)[1]
        assert model(state)[1] == pred  # counted once per step, however often it is asked
        assert pred.target == (board if k < model.doubt else None), k
    assert reserved_walks(state, {1: pred}, {0: None}) == {1: state.agent_pos[1]}
    # once it heads for the board the guess holds again
    transition(state, [S, int(Action.RIGHT)])
    transition(state, [S, int(Action.RIGHT)])
    assert model(state)[1].target == board


def test_a_partner_that_keeps_putting_its_item_down_and_taking_it_up_is_not_followed():
    # it puts the tomato down on the counter above it and takes it up again, over and over:
    # the guess turns from the board (while it holds the tomato) to the tomato (while it
    # lies there) and back every step, and the partner never comes closer to the board
    state, model, board = _wandering_partner()
    guesses = []
    for _ in range(2 * model.doubt):
        transition(state, [S, int(Action.UP)])
        if state.agent_hand[1] >= 0:
            guesses.append(model(state)[1].target)
        else:
            model(state)
    assert guesses[0] == board
    assert guesses[-1] is None  # expected to stay: our cook no longer waits for its tomato
    # once it heads for the board the guess holds again
    for _ in range(model.patience + 1):
        transition(state, [S, int(Action.RIGHT)])
    assert state.agent_hand[1] >= 0 and model(state)[1].target == board


def test_a_partner_on_its_way_keeps_its_guessed_target():
    state, model, board = _wandering_partner()
    for _ in range(4):  # right along the row to the board: closer every step
        transition(state, [S, int(Action.RIGHT)])
        assert model(state)[1].target == board


def test_a_taken_item_is_replaced_by_an_equivalent_one_in_the_plan():
    # two tomato crates: the partner takes the tomato of the left one, which the plan
    # meant to fetch; the plan fetches the right one instead and keeps every other step
    spec = dict(KITCHEN, game_map=[[1, 1, 6, 1, 1], [3, 0, 0, 0, 3], [1, 5, 1, 7, 1]])
    state = _state(spec)
    left, right, board = state.geo.flat(1, 0), state.geo.flat(1, 4), state.geo.flat(0, 2)
    mine = state.cell_item[left]
    transition(state, [S, L])
    assert state.agent_hand[1] == mine
    steps = [PlanStep(0, 0, "pickup", left, (mine,)), PlanStep(1, 0, "putdown", board, (mine,)),
             PlanStep(2, 0, "chop", board, (mine,))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    # the partner is predicted to take it to the window: the plan does not fit that
    assert answer_taken(state, queues[0][0], queues, set(),
                        {1: Prediction(1, state.geo.flat(2, 3))}) == "repaired"
    other = state.cell_item[right]
    assert [(t.step.kind, t.step.target, t.step.items) for t in queues[0]] == [
        ("pickup", right, (other,)), ("putdown", board, (other,)), ("chop", board, (other,))]


def test_a_lone_cook_that_gives_way_to_a_partner_hands_off_what_it_holds():
    state, tomato = _carrying_partner()  # (the partner holds the tomato: swap the roles)
    assert hand_off(state, 0, 7) == []  # our cook holds nothing
    steps = hand_off(state, 1, 7)
    (task,) = steps
    assert task.step.kind == "putdown" and task.step.items == (tomato,)
    assert state.geo.terrains[0][task.step.target] == 1  # a plain counter both reach


def test_a_cook_that_hands_off_steps_off_the_counters_way_in():
    """Our cook puts the tomato on a counter, then leaves the cell in front of it, to one
    from which the partner still reaches the counter (else the partner, which treats our
    cook as an obstacle, could never take the tomato on)."""
    spec = {"name": "room", "max_n_agent": 2,
            "game_map": [[1, 1, 1, 1, 1], [3, 0, 0, 0, 7], [1, 0, 0, 0, 1], [1, 5, 1, 6, 1]],
            "agent_spawn_points": [[1, 1], [2, 3]]}
    state = _state(spec)
    transition(state, [L, S])  # our cook takes the tomato from its crate
    tomato = state.agent_hand[0]
    assert tomato >= 0
    put, away = hand_off(state, 0, 7)
    assert (put.step.kind, put.step.items) == ("putdown", (tomato,))
    assert away.step.kind == "goto" and away.step.agent == 0
    walk = state.geo.walkables[0]
    spots = interaction_spots(state.geo.neighbors, walk, put.step.target)
    assert away.step.target not in spots
    reach = distances(state.geo.neighbors, walk, [state.agent_pos[1]], blocked=[away.step.target])
    assert any(reach[s] >= 0 for s in spots)


# one board, worked from (1,2) only; tomato crate left, lettuce crate below right
ONE_BOARD = {"name": "one-board", "max_n_agent": 2,
             "game_map": [[1, 1, 6, 1, 1],
                          [3, 0, 0, 0, 7],
                          [1, 5, 1, 4, 1]],
             "agent_spawn_points": [[1, 3], [1, 1]]}


def test_a_board_a_partner_waits_for_is_freed_before_it_blocks_the_only_way_in():
    # our chopped lettuce waits on the only board for a plate; the partner carries a raw
    # tomato to that board: a greedy partner would stand in the board's only cell until the
    # board is free, and nobody could reach the lettuce again. Our free cook first moves
    # the lettuce to the nearest free counter, and the plate step takes it there.
    state = _state(ONE_BOARD)
    transition(state, [S, L])  # the partner takes the tomato
    tomato, board = state.agent_hand[1], state.geo.flat(0, 2)
    lettuce = next(i for i, k in enumerate(state.geo.item_kind) if k == 4)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    state.cell_item[state.item_loc[lettuce]] = -1
    state.cell_item[board] = lettuce
    state.item_where[lettuce], state.item_loc[lettuce] = int(Where.CELL), board
    state.item_state[lettuce] = int(ItemState.CHOPPED)
    assert tomato >= 0 and state.item_state[tomato] == int(ItemState.FRESH)
    steps = [PlanStep(0, 0, "pickup", state.geo.flat(2, 1), (plate,)),
             PlanStep(1, 0, "plate", board, (plate, lettuce))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    warned: set = set()
    model = PartnerModel(GreedyAgent(0))
    model.reset(state, [0])
    preds = model(state)
    assert preds[1].target == board  # greedy heads for the busy board and would wait there
    assert vacate(state, queues, preds, 99, warned) == 2
    kinds = [(t.step.kind, t.step.items) for t in queues[0]]
    assert kinds == [("pickup", (lettuce,)), ("putdown", (lettuce,)), ("pickup", (plate,)),
                     ("plate", (plate, lettuce))]
    counter = queues[0][1].step.target
    assert state.geo.terrains[0][counter] == int(Cell.COUNTER) and state.cell_item[counter] < 0
    assert queues[0][0].step.target == board and queues[0][3].step.target == counter
    assert queues[0][0].step.index < queues[0][1].step.index
    # once per item; and nothing to do when no partner wants the board
    assert vacate(state, queues, preds, 97, warned) == 0
    assert vacate(state, {0: deque(Task(s, frozenset()) for s in steps)},
                  {1: Prediction(1, None)}, 99, set()) == 0


def test_a_dish_the_partner_carries_to_the_window_is_left_to_it():
    # the partner has taken the plate our cook was to serve and its next bump is the
    # window: the delivery is dropped from our plan (counted done), so our cook does not
    # wait in front of the window, in the partner's way
    state = _state(KITCHEN)
    transition(state, [S, int(Action.DOWN)])  # the partner takes the plate
    plate, window = state.agent_hand[1], state.geo.flat(1, 4)
    assert plate >= 0 and state.geo.item_kind[plate] == 5
    for steps in ([PlanStep(0, 0, "pickup", state.geo.flat(2, 1), (plate,)),
                   PlanStep(1, 0, "deliver", window, (plate,))],
                  [PlanStep(1, 0, "deliver", window, (plate,))]):
        queues = {0: deque(Task(s, frozenset()) for s in steps)}
        done: set[int] = set()
        assert answer_taken(state, queues[0][0], queues, done, {1: Prediction(1, window)}) \
            == "repaired"
        assert not queues[0] and 1 in done


def test_a_partner_with_nothing_to_do_in_the_only_way_in_shuts_the_station_off():
    # the board is worked from (1,2) only; a partner standing there that its own policy
    # keeps there will not make way (the executive hands off at once, not after a livelock)
    state = _state(KITCHEN)
    transition(state, [S, int(Action.RIGHT)])
    board, spot = state.geo.flat(0, 2), state.geo.flat(1, 2)
    assert state.agent_pos[1] == spot
    spots = interaction_spots(state.geo.neighbors, state.geo.walkables[0], board)
    assert spots == [spot]
    assert shut_out(state, spots, {1: Prediction(1, None)})
    assert not shut_out(state, spots, {1: Prediction(1, board)})  # it is about to work there
    window = state.geo.flat(1, 4)
    assert not shut_out(state, interaction_spots(state.geo.neighbors, state.geo.walkables[0],
                                                 window), {1: Prediction(1, None)})


def test_a_cook_waiting_in_the_only_way_in_for_what_the_partner_brings_lets_it_by():
    # our cook waits in the board's only cell to chop the tomato the partner carries there:
    # the partner's walk is reserved (our cook steps off it) instead of our cook holding
    # the cell and the partner, which treats it as a wall, never arriving
    state, tomato = _carrying_partner()
    transition(state, [L, S])
    board, spot = state.geo.flat(0, 2), state.geo.flat(1, 2)
    assert state.agent_pos[0] == spot
    preds = {1: Prediction(1, board, (spot,))}
    chop = Task(PlanStep(0, 0, "chop", board, (tomato,)), frozenset())
    assert brings(state, chop, preds, {0: deque([chop])})
    assert reserved_walks(state, preds, {0: deque([chop])})[1] == (state.agent_pos[1], spot)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    other = Task(PlanStep(0, 0, "pickup", board, (plate,)), frozenset())
    assert not brings(state, other, preds, {0: deque([other])})
    assert reserved_walks(state, preds, {0: deque([other])})[1] == state.agent_pos[1]


def test_an_item_the_partner_takes_again_after_putting_it_down_is_checked_again():
    # the partner carries our tomato to the board (the plan counts on it: checked, no
    # repair), chops it there, then takes it on to the plate: our pickup and plating are
    # dropped, not left waiting for an item that has gone
    state, tomato = _carrying_partner()
    board, plate_cell = state.geo.flat(0, 2), state.geo.flat(2, 1)
    plate = state.cell_item[plate_cell]
    steps = [PlanStep(0, 0, "chop", board, (tomato,)), PlanStep(1, 0, "pickup", board, (tomato,)),
             PlanStep(2, 0, "plate", plate_cell, (plate, tomato))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    done: set[int] = set()
    warned: set = set()
    for _ in range(3):  # one step after another while the partner walks to the board
        assert check_queues(state, queues, done, {1: Prediction(1, board)}, warned) == (False, 0)
    state.agent_hand[1] = -1  # put down on the board and chopped there
    state.cell_item[board] = tomato
    state.item_where[tomato], state.item_loc[tomato] = int(Where.CELL), board
    state.item_state[tomato] = int(ItemState.CHOPPED)
    queues[0].popleft()
    done.add(0)
    assert check_queues(state, queues, done, {1: Prediction(1, board)}, warned) == (False, 0)
    state.cell_item[board] = -1  # taken again, on its way to the plate
    state.agent_hand[1] = tomato
    state.item_where[tomato], state.item_loc[tomato] = int(Where.HAND), 1
    assert check_queues(state, queues, done, {1: Prediction(1, plate_cell)}, warned) == (False, 1)
    assert not queues[0] and {1, 2} <= done


def test_our_steps_stop_at_the_first_that_waits_for_a_partners():
    # a plan for every cook: the partner (1) fetches the tomato and leaves it on the counter
    # between the halves; ours (0) moves the plate over, then takes the tomato on
    crate, counter, plate, spot, board = 5, 7, 14, 12, 9
    steps = [PlanStep(0, 1, "pickup", crate, (0,)), PlanStep(1, 0, "pickup", plate, (1,)),
             PlanStep(2, 1, "putdown", counter, (0,)), PlanStep(3, 0, "putdown", spot, (1,)),
             PlanStep(4, 0, "pickup", counter, (0,)), PlanStep(5, 0, "putdown", board, (0,))]
    assert [s.index for s in ours_first(steps, (0,))] == [1, 3]
    assert ours_first(steps[:1] + steps[4:], (0,)) == []  # its first step waits


def test_our_steps_that_wait_for_no_partner_step_are_kept_after_one_that_does():
    # ours (0) waits for the lettuce the partner (1) leaves on the counter, but the steak
    # from our crate to the pan waits for nobody: it is done meanwhile
    crate, counter, board, steak_crate, pan = 5, 7, 9, 11, 13
    steps = [PlanStep(0, 1, "pickup", crate, (0,)), PlanStep(1, 1, "putdown", counter, (0,)),
             PlanStep(2, 0, "pickup", counter, (0,)), PlanStep(3, 0, "putdown", board, (0,)),
             PlanStep(4, 0, "pickup", steak_crate, (2,)), PlanStep(5, 0, "putdown", pan, (2,)),
             PlanStep(6, 0, "chop", board, (0,))]
    assert [s.index for s in ours_first(steps, (0,))] == [4, 5]
    # with prefix (the plan of every cook beside a partner run by its own policy) our cook
    # keeps nothing: its first step already waits for the partner's
    assert ours_first(steps, (0,), prefix=True) == []
    assert [s.index for s in ours_first(steps[4:], (0,), prefix=True)] == [4, 5, 6]


@pytest.mark.parametrize(("meet", "kept"), [((), []), ((7,), [0, "putdown@7"])])
def test_a_pickup_whose_next_step_waits_for_the_partner_ends_where_they_meet(meet, kept):
    # ours (0) takes the cooked steak off the pan to plate it on the plate the partner (1)
    # brings to the counter 7: on a free plain counter it puts the steak down there (the
    # partner takes it on), elsewhere it leaves the steak where it is
    pan, counter, shelf = 13, 7, 3
    steps = [PlanStep(0, 0, "pickup", pan, (2,)), PlanStep(1, 1, "pickup", shelf, (1,)),
             PlanStep(2, 1, "putdown", counter, (1,)), PlanStep(3, 0, "plate", counter, (2, 1))]
    out = ours_first(steps, (0,), meet)
    assert [s.index if s.index < 4 else f"{s.kind}@{s.target}" for s in out] == kept


def test_a_crate_whose_only_way_in_a_partner_holds_still_compiles():
    # the partner stands in the crate's only way in: a wall in the problem, the crate
    # out of everyone's reach (the items from it have no home the plan could use)
    from ocplus_plan.planning.compile import compile as compile_state

    spec = {"name": "halves", "max_n_agent": 2,
            "game_map": [[1, 1, 1, 1, 1], [3, 0, 1, 0, 6], [7, 0, 1, 0, 5], [1, 1, 1, 1, 1]],
            "agent_spawn_points": [[1, 3], [1, 1]]}
    state = _state(spec)
    problem = predicted_state(state, {1: Prediction(1, None)})
    assert not problem.geo.walkables[0][state.geo.flat(1, 1)]
    compiled = compile_state(problem, None, agents=[0])
    assert compiled.problem is not None


# three rows of floor: a way round any one cook (crate left, board and window right)
HALL = {"name": "hall", "max_n_agent": 2,
        "game_map": [[1, 1, 1, 1, 1, 1, 1],
                     [3, 0, 0, 0, 0, 0, 6],
                     [1, 0, 0, 0, 0, 0, 7],
                     [1, 0, 0, 0, 0, 0, 1],
                     [1, 1, 1, 5, 1, 1, 1]],
        "agent_spawn_points": [[1, 3], [1, 1]]}


def test_a_greedy_partners_predicted_walk_goes_round_our_cook_as_its_policy_does():
    # the partner carries the tomato to the board; its shortest walk runs through our cook
    # at (1,3), and greedy treats our cook as a wall: the walk it takes goes round, so
    # our cook's paths keep clear of it (a walk through our cook reserved nothing, and
    # both cooks stepped into the same cell; hard, seed 0, steps 61-93)
    state = _state(HALL)
    transition(state, [S, L])
    assert state.agent_hand[1] >= 0
    model = PartnerModel(GreedyAgent(0))
    model.reset(state, [0])
    pred = model(state)[1]
    assert pred.target == state.geo.flat(1, 6) and pred.path
    assert state.agent_pos[0] not in pred.path
    walk = reserved_walks(state, {1: pred}, {0: ["a step"]})[1]
    assert walk == (state.agent_pos[1], *pred.path[:8])
    # with no way round (one lane), the walk it waits to take: an idle cook steps off it
    state = _state(LANE)
    transition(state, [S, L])
    model = PartnerModel(GreedyAgent(0))
    model.reset(state, [0])
    pred = model(state)[1]
    assert state.agent_pos[0] in pred.path


def _chopped_tomato_for_our_plate():
    """The partner carries a chopped tomato; our queue takes the plate on and serves it with
    the tomato on it (the state the partner's bump leaves)."""
    state, tomato = _carrying_partner()
    state.item_state[tomato] = int(ItemState.CHOPPED)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    plate_cell, window = state.item_loc[plate], state.geo.flat(1, 4)
    steps = [PlanStep(0, 0, "pickup", plate_cell, (plate,)),
             PlanStep(1, 0, "deliver", window, (plate, tomato))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    return state, tomato, plate, plate_cell, queues


def test_a_partner_carrying_an_item_onto_our_plate_is_expected_not_replanned():
    # the plan was made from the state the partner's bump leaves: the chopped tomato on
    # the plate; its first step with the tomato serves the plate (a replan every step
    # while the partner walked, medium seed 0, steps 100-108)
    state, tomato, plate, plate_cell, queues = _chopped_tomato_for_our_plate()
    preds = {1: Prediction(1, plate_cell)}
    assert onto_our_plate(state, queues, 1, tomato, plate_cell)
    assert answer_taken(state, queues[0][1], queues, set(), preds) == "expected"
    assert len(queues[0]) == 2
    # and our cook does not take the plate away before the partner's bump
    assert tomato in queues[0][0].step.items
    # a plan that takes the tomato on elsewhere first does not fit
    board = state.geo.flat(0, 2)
    queues = {0: deque([Task(PlanStep(0, 0, "plate", board, (tomato,)), frozenset())])}
    assert not onto_our_plate(state, queues, 1, tomato, plate_cell)


def test_our_cook_waits_for_the_partner_to_put_its_item_on_our_plate_before_taking_it():
    """The plan takes the plate on with the partner's tomato on it (the state the partner's
    bump leaves). While the partner still carries the tomato, our pickup of the plate is not
    ready (taken at once, the plate was served without it: hard seed 0 beside greedy); once
    the tomato lies on the plate, it is."""
    state, tomato, plate, plate_cell, queues = _chopped_tomato_for_our_plate()
    state.agent_pos[0] = state.geo.flat(1, 1)  # in front of the plate
    assert ready(state, 0, queues[0][0], set())  # the plate alone: ready
    check_queues(state, queues, set(), {1: Prediction(1, plate_cell)}, set())
    assert not ready(state, 0, queues[0][0], set())
    # the partner's bump: the tomato onto the plate
    state.agent_hand[1] = -1
    state.item_where[tomato], state.item_loc[tomato] = int(Where.PLATE), plate
    assert ready(state, 0, queues[0][0], set())


@pytest.mark.parametrize("onto_plate", [True, False])
def test_a_new_plan_takes_the_plate_only_after_the_partners_item_from_its_first_action(
        onto_plate):
    """A plan made from the state the partner's bump leaves (its chopped tomato on the plate)
    is installed: from the plan's first action on, our pickup of that plate waits for the
    tomato, not only from the next check of the queued steps (taken at once, the plate left
    before the partner got there: ``gen:multiroom:test:0``, seed 0, beside greedy). A
    partner whose bump goes elsewhere leaves the pickup as the plan has it."""
    state, tomato, plate, plate_cell, queues = _chopped_tomato_for_our_plate()
    state.agent_pos[0] = state.geo.flat(1, 1)  # in front of the plate
    target = plate_cell if onto_plate else state.geo.flat(0, 1)
    ex = Executive(lambda *a: None)
    ex.reset(state, [0])
    ex.partner_model = lambda s: {1: Prediction(1, target)}
    ex.install([t.step for t in queues[0]], state)
    first = ex.queues[0][0]
    assert first.step.kind == "pickup"
    assert (tomato in first.step.items) is onto_plate
    assert ready(state, 0, first, set()) is not onto_plate


def _partner_serving():
    """The partner (cook 1) stands at the window with a plate of chopped tomato (the open
    order); our cook 0 stands left."""
    state = _state(KITCHEN)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    tomato = next(i for i, k in enumerate(state.geo.item_kind) if k == 3)
    state.cell_item[state.item_loc[plate]] = state.cell_item[state.item_loc[tomato]] = -1
    state.item_where[plate], state.item_loc[plate] = int(Where.HAND), 1
    state.item_where[tomato], state.item_loc[tomato] = int(Where.PLATE), plate
    state.item_state[tomato] = int(ItemState.CHOPPED)
    state.agent_hand[1] = plate
    state.agent_pos[0], state.agent_pos[1] = state.geo.flat(1, 1), state.geo.flat(1, 3)
    return state, plate, tomato


def test_a_dish_the_partner_serves_next_is_served_in_the_state_planned_from():
    # hard, seed 1, steps 97-112: the partner carried a finished dish to the window and our
    # plans kept using its plate: a `taken` replan every step until it was served
    state, plate, tomato = _partner_serving()
    window = state.geo.flat(1, 4)
    assert delivering(state, {1: Prediction(1, window)}) == {plate, tomato}
    assert not delivering(state, {1: Prediction(1, state.geo.flat(0, 2))})  # not to the window
    served = [o.order_id for o in state.orders]
    problem = predicted_state(state, {1: Prediction(1, window)})
    # the simulator's delivery: its order gone (the next one drawn), the plate and the
    # tomato back home, the partner's hand empty
    assert served[0] not in [o.order_id for o in problem.orders]
    assert problem.agent_hand[1] == -1 and problem.stats["dishes_served"] == 1
    assert problem.item_where[plate] in (int(Where.CELL), int(Where.WAITING))
    assert problem.item_where[tomato] in (int(Where.CELL), int(Where.WAITING))
    assert problem.item_state[tomato] == int(ItemState.FRESH)
    assert state.agent_hand[1] == plate and [o.order_id for o in state.orders] == served
    # a plan made from that state takes the plate from its home: expected, not replanned
    home = state.geo.item_home[plate]
    queues = {0: deque([Task(PlanStep(0, 0, "pickup", home, (plate,)), frozenset())])}
    assert check_queues(state, queues, set(), {1: Prediction(1, window)}, set()) == (False, 0)
    assert check_queues(state, queues, set(), {1: Prediction(1, state.geo.flat(0, 2))},
                        set())[0]


def _chopped_tomato_and_plate():
    state = _state(KITCHEN)
    plate = next(i for i, k in enumerate(state.geo.item_kind) if k == 5)
    tomato = next(i for i, k in enumerate(state.geo.item_kind) if k == 3)
    state.cell_item[state.item_loc[tomato]] = -1
    state.item_state[tomato] = int(ItemState.CHOPPED)
    return state, plate, tomato


def test_a_plating_step_the_partner_did_already_is_dropped_as_done():
    # medium beside greedy, seed 4, steps 121-140: the partner put the chopped vegetable on
    # the plate our cook then held; our step to take it off the board onto that plate
    # waited 20 steps in front of the empty board
    state, plate, tomato = _chopped_tomato_and_plate()
    state.item_where[tomato], state.item_loc[tomato] = int(Where.PLATE), plate
    plate_cell, board = state.item_loc[plate], state.geo.flat(0, 2)
    steps = [PlanStep(0, 0, "plate", board, (tomato, plate)),
             PlanStep(1, 0, "pickup", plate_cell, (plate,))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    done: set[int] = set()
    assert check_queues(state, queues, done, {}, set()) == (False, 1)
    assert [t.step.index for t in queues[0]] == [1] and done == {0}


def test_a_plating_step_of_a_later_dish_with_the_same_items_is_kept():
    # multiroom beside an idle partner, seed 2, step 131: the steak lay on the plate our cook
    # was about to serve; the plan's next dish plates the steak and plate again (served
    # items come back) and that later step was dropped as done: the cook stood idle
    state, plate, tomato = _chopped_tomato_and_plate()
    state.item_where[tomato], state.item_loc[tomato] = int(Where.PLATE), plate
    plate_cell, board, window = state.item_loc[plate], state.geo.flat(0, 2), state.geo.flat(1, 4)
    steps = [PlanStep(0, 0, "pickup", plate_cell, (plate,)),
             PlanStep(1, 0, "deliver", window, (plate, tomato)),
             PlanStep(2, 0, "plate", board, (tomato, plate))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    done: set[int] = set()
    assert check_queues(state, queues, done, {}, set()) == (False, 0)
    assert [t.step.index for t in queues[0]] == [0, 1, 2] and not done


def _held(state, cook: int, item: int) -> None:
    state.cell_item[state.item_loc[item]] = -1
    state.item_where[item], state.item_loc[item] = int(Where.HAND), cook
    state.agent_hand[cook] = item


@pytest.mark.parametrize("loose", ["ingredient", "plate"])
def test_a_plating_step_whose_item_lies_elsewhere_is_replanned(loose):
    # the ingredient a partner carried on, or the plate it put down elsewhere than the plan
    # had it (hard beside greedy, seed 2, steps 102-122: our cook stood 20 steps in front
    # of the empty counter where the plan had the partner put the plate)
    state, plate, tomato = _chopped_tomato_and_plate()
    item, held = (tomato, plate) if loose == "ingredient" else (plate, tomato)
    _held(state, 0, held)  # our cook brings the other one
    # the board, or the counter where the plan meets the partner; and where it lies instead
    station, other = ((state.geo.flat(0, 2), state.geo.flat(0, 1)) if loose == "ingredient"
                      else (state.geo.flat(0, 1), state.geo.flat(0, 3)))
    state.cell_item[state.item_loc[item]] = -1
    state.cell_item[other] = item
    state.item_where[item], state.item_loc[item] = int(Where.CELL), other
    steps = [PlanStep(0, 0, "plate", station, (tomato, plate))]
    assert check_queues(state, {0: deque(Task(s, frozenset()) for s in steps)}, set(), {},
                        set())[0]
    # where the step expects it, the plan fits
    state.cell_item[other], state.cell_item[station] = -1, item
    state.item_loc[item] = station
    assert check_queues(state, {0: deque(Task(s, frozenset()) for s in steps)}, set(), {},
                        set()) == (False, 0)


# a room on the left, a lane to the window on the right; the partner stands in the lane's entry
ROOM_AND_LANE = {"name": "room-and-lane", "max_n_agent": 2,
                 "game_map": [[-1, 6, -1, -1, 1, -1],
                              [3, 0, 0, 0, 0, 7],
                              [-1, 0, 0, -1, -1, -1],
                              [-1, 0, 0, -1, -1, -1],
                              [-1, 0, 0, -1, -1, -1],
                              [-1, 1, 5, -1, -1, -1]],
                 "agent_spawn_points": [[1, 1], [1, 3]]}


def test_a_hand_off_is_to_a_counter_our_cook_reaches_round_the_partner():
    """The counter nearest in walks that ignore cooks lies behind the partner guessed to stay
    in the lane (our cook could only reach it through the partner): the item goes on the
    room's counter, which both cooks reach. A partner on its way leaves the lane, and a
    greedy one steps off for a cook waiting beside it: the counter behind it is taken."""
    state = _state(ROOM_AND_LANE)
    transition(state, [L, S])  # our cook takes the tomato from its crate
    tomato = state.agent_hand[0]
    assert tomato >= 0
    put = hand_off(state, 0, 7, {1: Prediction(1, None)})[0]
    assert (put.step.kind, put.step.items) == ("putdown", (tomato,))
    assert put.step.target == state.geo.flat(5, 1)
    on_its_way = {1: Prediction(1, state.geo.flat(1, 5), (state.geo.flat(1, 4),))}
    assert hand_off(state, 0, 7, on_its_way)[0].step.target == state.geo.flat(0, 4)
    by_policy = {1: Prediction(1, None, (), by_policy=True)}  # greedy steps off for our cook
    assert hand_off(state, 0, 7, by_policy)[0].step.target == state.geo.flat(0, 4)


def test_a_plan_made_while_the_partner_holds_its_item_is_not_checked_again_for_it():
    """The partner holds the tomato and nothing says where it takes it: a plan made from
    that state counts on the partner for it, so the item in the partner's hand is no news,
    and the check does not ask for the same plan again every step; once the partner has
    put it down somewhere else, the check answers again."""
    state, tomato = _carrying_partner()
    board = state.geo.flat(0, 2)
    steps = [PlanStep(0, 0, "chop", board, (tomato,))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    unknown = {1: Prediction(1, None)}
    assert check_queues(state, queues, set(), unknown, set()) == (True, 0)
    known = known_when_planned(state, queues, unknown)
    assert check_queues(state, queues, set(), unknown, set(known)) == (False, 0)
    # with a predicted target the plan was made from the state that bump leaves: no key
    assert known_when_planned(state, queues, {1: Prediction(1, state.geo.flat(1, 4))}) == set()
    transition(state, [S, int(Action.UP)])  # the partner puts it on the counter above
    assert check_queues(state, queues, set(), unknown, set(known))[0]


def test_a_plan_that_counts_on_a_partner_to_bring_its_plate_is_not_checked_again_for_it():
    """The plan's plating step takes the tomato onto a plate at the board, where a partner
    (in the joint plan) is to bring the plate: where the plate lies was known when the plan
    was made, so only its moving is news."""
    state = _state(KITCHEN)
    board, plate = state.geo.flat(0, 2), state.cell_item[state.geo.flat(2, 1)]
    steps = [PlanStep(0, 0, "plate", board, (plate,))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    unknown = {1: Prediction(1, None)}
    known = known_when_planned(state, queues, unknown)
    assert check_queues(state, queues, set(), unknown, set()) == (True, 0)
    assert check_queues(state, queues, set(), unknown, set(known)) == (False, 0)


def test_a_bump_predicted_for_the_partner_holding_the_item_is_news():
    """The plan was made while nothing said where the partner takes the tomato; once its
    bump is predicted the plan is checked against it again."""
    state, tomato = _carrying_partner()
    steps = [PlanStep(0, 0, "chop", state.geo.flat(0, 2), (tomato,))]
    queues = {0: deque(Task(s, frozenset()) for s in steps)}
    known = known_when_planned(state, queues, {1: Prediction(1, None)})
    onto_counter = {1: Prediction(1, state.geo.flat(0, 1))}
    assert check_queues(state, queues, set(), onto_counter, set(known)) == (True, 0)


def test_a_cook_that_handed_its_item_off_is_planned_for_again_once_the_partner_has_it():
    """After a livelock our lone cook puts what it holds where the partner takes it on and
    stands aside for ``2 * block_patience`` steps; it is planned for again in the step the
    partner has the item in hand (medium, seed 0, beside greedy: it stood idle 4 steps
    after the partner had taken the steak it handed off, twice in the episode)."""
    state = _state(KITCHEN)
    tomato = next(i for i, k in enumerate(state.geo.item_kind) if k == 3)
    state.cell_item[state.item_loc[tomato]] = -1
    state.item_where[tomato], state.item_loc[tomato] = int(Where.HAND), 0
    state.agent_hand[0] = tomato
    asked: list[int] = []

    def planner(st, agents, reason=""):
        asked.append(st.t)
        return PlanOutcome("solved", [], 0.0)

    ex = Executive(planner)
    ex.reset(state, [0])
    ex.partner_model = lambda s: {1: Prediction(1, None)}
    ex.act(state)  # the first plan
    ex._replan(state, "livelock")  # a lone cook: it hands off
    assert [t.step.kind for t in ex.queues[0]][0] == "putdown"
    ex.queues[0].clear()  # put down, stood aside
    state.agent_hand[0] = -1
    counter = state.geo.flat(0, 3)
    state.item_where[tomato], state.item_loc[tomato] = int(Where.CELL), counter
    state.cell_item[counter] = tomato
    ex.act(state)
    assert asked == [0]  # the item lies there: the cook still waits
    state.cell_item[counter] = -1  # the partner takes it
    state.item_where[tomato], state.item_loc[tomato] = int(Where.HAND), 1
    state.agent_hand[1] = tomato
    ex.act(state)
    assert asked == [0, 0]
    ex.act(state)  # once: the wait goes on as before for the next plan
    assert asked == [0, 0]

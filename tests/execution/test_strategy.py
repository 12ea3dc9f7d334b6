"""Changes of strategy (execution/strategy.py): who gives way, and when a cook that gave way
is planned for again."""

from __future__ import annotations

from collections import Counter, deque
from types import SimpleNamespace

from ocplus_plan.execution.livelock import Contests
from ocplus_plan.execution.strategy import GIVE_WAY_SPANS, give_way, rejoining, stall_strategy
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

KITCHEN = {"name": "two", "max_n_agent": 2,
           "game_map": [[1, 1, 6, 1, 1], [3, 0, 0, 0, 7], [1, 5, 1, 1, 1]],
           "agent_spawn_points": [[1, 3], [1, 1]]}


def _executive(state, work):
    """The parts of an executive the strategies read: cook -> queued steps."""
    return SimpleNamespace(agent_ids=(0, 1), queues={a: deque(range(n)) for a, n in work.items()},
                           yielding={}, gave_way=0, block_patience=6,
                           stall_strategies=Counter())


def test_a_cook_that_gave_way_is_planned_for_again_when_its_time_is_up():
    state = new_state(make_rules("easy", map=KITCHEN, n_agents=2, recipes=["tomato"]), 0)
    ex = _executive(state, {0: 3, 1: 2})
    assert give_way(ex, state)
    cook = next(iter(ex.yielding))
    assert ex.yielding[cook] == state.t + GIVE_WAY_SPANS * ex.block_patience
    ex.queues[cook].clear()  # the plan made while it stood aside gives it nothing
    assert not rejoining(ex, state)  # not yet
    state.t = ex.yielding[cook]
    assert rejoining(ex, state)  # back, idle, and the other cook still has work
    ex.queues[1 - cook].clear()
    assert not rejoining(ex, state)  # nobody has work: the plan is done, plan_finished asks


def test_a_stall_gives_way_first_then_models_every_cook():
    state = new_state(make_rules("easy", map=KITCHEN, n_agents=2, recipes=["tomato"]), 0)
    ex = _executive(state, {0: 1, 1: 1})
    assert stall_strategy(ex, state, 18) == "stall"
    assert ex.stall_strategies == Counter(give_way=1)
    assert stall_strategy(ex, state, 36) == "stall_all"
    assert stall_strategy(ex, state, 54) == "stall_all"
    assert ex.stall_strategies["reallocate"] == 1 and not ex.yielding
    assert not any(ex.queues.values())  # re-allocated from scratch


def test_a_lone_cook_hands_off_in_a_stall_only_what_it_holds():
    """Beside a partner, the first strategy of a lone cook is to hand off what it holds; with
    a free hand there is nothing to hand off, and it goes straight to a plan with cells."""
    state = new_state(make_rules("easy", map=KITCHEN, n_agents=2, recipes=["tomato"]), 0)
    ex = _executive(state, {0: 1})
    ex.agent_ids = (0,)
    assert state.agent_hand[0] < 0
    assert stall_strategy(ex, state, 18) == "stall_all"
    assert ex.stall_strategies == Counter(every_cook=1)
    state.agent_hand[0] = 0  # (only the hand is read)
    assert stall_strategy(ex, state, 18) == "livelock"
    assert ex.stall_strategies["hand_off"] == 1


# our cook below the free cell (1, 2), a partner left of it: both step into it
CROSS = {"name": "cross", "max_n_agent": 2,
         "game_map": [[1, 3, 6, 7, 1],
                      [1, 0, 0, 0, 5],
                      [1, 1, 0, 1, 1],
                      [1, 1, 1, 1, 1]],
         "agent_spawn_points": [[2, 2], [1, 1]]}


def test_a_cook_whose_move_a_partner_keeps_contesting_stays_a_step_and_lets_it_through():
    state = new_state(make_rules("easy", map=CROSS, n_agents=2, recipes=["tomato"]), 0)
    start, cell = list(state.agent_pos), state.geo.flat(1, 2)
    up, right, stay = int(Action.UP), int(Action.RIGHT), int(Action.STAY)
    watch = Contests(patience=2)
    for _ in range(2):  # a contested cell leaves both where they are (docs/spec.md, 5)
        ours = watch.settle(state, {0: up})[0]
        assert ours == up
        transition(state, [ours, right])
        assert list(state.agent_pos) == start
    assert watch.settle(state, {0: up}) == {0: stay}  # it gives the cell up for a step
    transition(state, [stay, right])
    assert state.agent_pos[1] == cell
    assert watch.settle(state, {0: up}) == {0: up}  # a new count


def test_a_move_into_a_cell_a_partner_stands_on_is_no_contest():
    state = new_state(make_rules("easy", map=CROSS, n_agents=2, recipes=["tomato"]), 0)
    transition(state, [int(Action.STAY), int(Action.RIGHT)])  # the partner takes the cell
    watch = Contests(patience=2)
    for _ in range(4):  # waiting behind a cook that stays is the paths' business, not this
        assert watch.settle(state, {0: int(Action.UP)}) == {0: int(Action.UP)}
        transition(state, [int(Action.UP), int(Action.STAY)])


def test_a_deadlock_that_comes_with_a_stall_is_planned_for_as_a_deadlock():
    """A stall and a deadlock seen on one step: the planner is asked for the deadlock (a plan
    with cells, which respects who stands where), not for the stall's give-way, which plans
    with stations again and so gets back the plan that deadlocked."""
    from ocplus_plan.execution.executive import Executive

    from .toy_planner import toy_planner

    asked = []

    def planner(state, agents, reason=""):
        asked.append(reason)
        return toy_planner(state, agents, reason)

    state = new_state(make_rules("easy", map=KITCHEN, n_agents=2, recipes=["tomato"]), 0)
    ex = Executive(planner)
    ex.reset(state)
    ex.act(state)
    assert asked == ["initial"]
    ex.unhandled += ["stall", "deadlock"]
    ex.act(state)
    assert asked == ["initial", "deadlock"]

"""Changes of strategy (execution/strategy.py): who gives way, and when a cook that gave way
is planned for again."""

from __future__ import annotations

from collections import Counter, deque
from types import SimpleNamespace

from ocplus_plan.execution.strategy import GIVE_WAY_SPANS, give_way, rejoining, stall_strategy
from ocplus_plan.sim import make_rules, new_state

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

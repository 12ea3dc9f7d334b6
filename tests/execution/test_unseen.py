"""The planning pipeline on kitchens unlike the presets: hand-overs, one-lane corridors and
cooks it does not control (hand-drawn maps; the generated families are measured by
experiments/bench_unseen.py)."""

from __future__ import annotations

import warnings

import pytest

from ocplus_plan.agents import StayAgent, run_episode
from ocplus_plan.agents.planner import PlannerAgent
from ocplus_plan.sim import make_rules, new_state

warnings.simplefilter("ignore", UserWarning)


def _fd_ok() -> bool:
    try:
        from ocplus_plan.planning.engines import availability
    except ImportError:  # pragma: no cover
        return False
    return availability("fast-downward").ok


needs_fd = pytest.mark.skipif(not _fd_ok(), reason="fast-downward unavailable")

#: two halves meeting only at the counters of column 2: tomato and plates on the left,
#: board and window on the right, so every dish is handed over
SPLIT = [[1, 3, 1, 1, 1, 1],
         [1, 0, 1, 0, 0, 7],
         [5, 0, 1, 0, 0, 1],
         [1, 0, 1, 0, 0, 6],
         [1, 1, 1, 1, 1, 1]]


def split_kitchen(n_agents: int = 2):
    spec = {"name": "split", "game_map": SPLIT, "agent_spawn_points": [[1, 1], [2, 3]]}
    return make_rules("easy", map=spec, n_agents=n_agents, recipes=["tomato"], horizon=80)


@needs_fd
def test_one_cook_unsolvable_falls_back_to_every_cook_and_is_not_asked_again():
    state = new_state(split_kitchen(), 0)
    agent = PlannerAgent("fast-downward", plan_cooks="one")
    stats = run_episode(state, agent)
    info = agent.info()
    assert stats["dishes_served"] >= 1, info
    # proven once per half a modelled cook stands in, then every cook at once
    assert 1 <= info["all_cooks_fallbacks"] <= 2 < info["planner_calls"], info
    assert info["statuses"].get("unsolvable", 0) == 0, info  # the fallback answered each call


def test_a_proven_answer_is_reused_for_the_same_question():
    from ocplus_plan.execution.proven import ProvenOutcomes, problem_key

    class Result:
        status = "unsolvable"

    state = new_state(split_kitchen(), 0)
    record = ProvenOutcomes()
    key = problem_key(state, [0], None, "stations")
    record.put(key, Result())
    assert record.get(problem_key(state.copy(), [0], None, "stations")).status == "unsolvable"
    assert record.get(problem_key(state, [0, 1], None, "stations")) is None
    assert record.hits == 1


def test_the_relaxed_kitchen_is_another_question():
    from ocplus_plan.execution.proven import problem_key
    from ocplus_plan.planning.spots import relaxed_state

    state = new_state(make_rules("hard", n_agents=2), 1)
    relaxed = relaxed_state(state)
    assert problem_key(state, None, 1, "stations") != problem_key(relaxed, None, 1, "stations")


def test_a_timeout_is_not_a_proof():
    from ocplus_plan.execution.proven import ProvenOutcomes

    class Result:
        status = "timeout"

    record = ProvenOutcomes()
    record.put("k", Result())
    assert record.get("k") is None


#: two rooms joined by the one-lane corridor of row 1: tomato and plates on the left, board
#: and window on the right; three cooks cannot pass each other in the lane
CORRIDOR = [[1, 3, 1, 1, 1, 1, 1, 6, 1],
            [5, 0, 0, 0, 0, 0, 0, 0, 7],
            [1, 0, 1, 1, 1, 1, 1, 0, 1],
            [1, 1, 1, 1, 1, 1, 1, 1, 1]]


#: the same with a side pocket below (1,5): no longer one lane, so plans use stations, in
#: which the cooks jump past each other
CORRIDOR_POCKET = [row[:] for row in CORRIDOR]
CORRIDOR_POCKET[2][5] = 0


def corridor_kitchen(grid=CORRIDOR):
    spec = {"name": "corridor", "game_map": grid,
            "agent_spawn_points": [[1, 1], [2, 1], [2, 7]]}
    return make_rules("easy", map=spec, n_agents=3, recipes=["tomato"], horizon=120)


def test_livelock_needs_blocked_triggers_and_no_progress():
    from ocplus_plan.execution.livelock import LivelockWatch

    watch = LivelockWatch(patience=12, stretch=30)
    watch.on_blocked()
    assert not watch.check(20)  # one blocked trigger is a collision, not a livelock
    watch.on_blocked()
    assert not watch.check(11) and watch.check(12)
    assert not watch.check(13) and watch.check(24)  # declared again while it lasts
    watch.progress(40)
    assert watch.stretches == [(0, 40)] and not watch.check(60)


@needs_fd
def test_corridor_livelock_is_detected_and_a_cook_gives_way():
    state = new_state(corridor_kitchen(CORRIDOR_POCKET), 0)
    agent = PlannerAgent("fast-downward")
    stats = run_episode(state, agent)
    info = agent.info()
    assert info["livelocks_detected"] >= 1 and info["gave_way"] >= 1, info
    assert info["livelock_stretches"] == [], info
    assert stats["dishes_served"] >= 2, info


@needs_fd
def test_cooks_in_one_lane_are_planned_with_cells_and_never_livelock():
    # three cooks who can never pass each other: every plan is made with cells, whose
    # moves respect occupancy (with stations plans: 2 dishes, after a livelock and a
    # cook giving way)
    state = new_state(corridor_kitchen(), 0)
    agent = PlannerAgent("fast-downward")
    stats = run_episode(state, agent)
    info = agent.info()
    assert info["livelocks_detected"] == 0 and info["stall_stretches"] == [], info
    assert stats["dishes_served"] >= 3, info

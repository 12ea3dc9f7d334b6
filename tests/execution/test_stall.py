"""The stall measure: progress toward an open order read from the state alone."""

from __future__ import annotations

from ocplus_plan.agents import make_controller, run_episode
from ocplus_plan.execution.executive import Executive, PlanOutcome
from ocplus_plan.execution.stall import STALL_PATIENCE, STALL_STRETCH, ProgressMeter, StallWatch
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

# a corridor: tomato crate on the left, board on the right, window below the middle
LANE = {"name": "lane", "game_map": [[1, 1, 1, 1, 1, 1],
                                     [3, 0, 0, 0, 0, 6],
                                     [1, 1, 7, 5, 1, 1]],
        "agent_spawn_points": [[1, 1]]}
R, L, S = int(Action.RIGHT), int(Action.LEFT), int(Action.STAY)


def _lane(horizon: int = 60):
    rules = make_rules("easy", map=LANE, n_agents=1, recipes=["tomato"], horizon=horizon)
    return new_state(rules, 0)


def test_carrying_an_item_toward_its_station_is_progress_and_to_and_fro_is_not():
    state = _lane()
    meter = ProgressMeter(state)
    transition(state, [L])  # pick up the tomato from its crate
    assert state.agent_hand[0] >= 0
    meter.update(state)
    transition(state, [R])
    assert meter.update(state)  # one step nearer the board
    transition(state, [L])
    assert not meter.update(state)  # back: farther
    transition(state, [R])
    assert not meter.update(state)  # forward to where it was: no new low
    transition(state, [R])
    assert meter.update(state)  # a new low


# two halves joined by the counters of column 3: the tomato crate and cook 0 on the right,
# the board and cook 1 on the left
HALVES = {"name": "halves", "game_map": [[1, 6, 1, 1, 1, 1, 1],
                                         [1, 0, 0, 1, 0, 0, 3],
                                         [1, 0, 0, 1, 0, 0, 1],
                                         [1, 7, 5, 1, 1, 1, 1]],
          "agent_spawn_points": [[1, 5], [1, 2]]}


def _halves(cooks: int):
    rules = make_rules("easy", map=HALVES, n_agents=cooks, recipes=["tomato"], horizon=40)
    return new_state(rules, 0)


def test_carrying_an_item_toward_the_counter_it_is_handed_over_on_is_progress():
    # the board is reached only through a counter between the halves: with a cook on the
    # other side, the tomato carried to that counter, put on it and taken on from the other
    # side comes nearer the board at each step
    state = _halves(cooks=2)
    meter = ProgressMeter(state)
    transition(state, [R, S])  # take the tomato from its crate
    assert state.agent_hand[0] >= 0
    meter.update(state)
    transition(state, [L, S])  # left: in front of the counter
    assert meter.update(state)
    transition(state, [L, S])  # put it on the counter
    assert meter.update(state)
    transition(state, [S, R])  # the other cook takes it on
    assert state.agent_hand[1] >= 0
    assert meter.update(state)


def test_a_lone_cook_carrying_an_item_to_a_counter_it_cannot_hand_over_on_makes_no_progress():
    state = _halves(cooks=1)
    meter = ProgressMeter(state)
    transition(state, [R])
    meter.update(state)
    transition(state, [L])
    assert not meter.update(state)  # nobody takes it on from the other side


def test_a_cook_standing_still_is_one_stall_of_the_whole_episode():
    state = _lane(horizon=50)
    watch = StallWatch(state)
    while not state.done:
        transition(state, [S])
        watch.update(state)
    assert watch.info()["stall_stretches"] == [(0, 50)]
    assert watch.info()["longest_stall"] == 50


def test_greedy_serving_dishes_has_no_stall():
    state = new_state(make_rules("easy", n_agents=1, horizon=120), 0)
    ctrl = make_controller("greedy", 0)
    ctrl.reset(state)
    watch = StallWatch(state)
    while not state.done:
        transition(state, ctrl.act(state))
        watch.update(state)
    assert state.stats["dishes_served"] >= 3
    assert watch.info()["stall_stretches"] == []
    assert watch.info()["longest_stall"] < STALL_STRETCH


def test_the_executive_changes_strategy_in_a_stall():
    asked: list[str] = []

    def nothing(state, agents, reason=""):  # a plan that never moves anything
        asked.append(reason)
        return PlanOutcome("solved", [], 0.0)

    state = _lane(horizon=2 * STALL_PATIENCE + 5)
    ex = Executive(nothing)
    run_episode(state, [(ex, [0])])
    info = ex.info()
    assert "stall_all" in asked  # every cook modelled, one order at a time
    assert info["stall_strategies"].get("every_cook", 0) >= 1
    (first, last), = info["stall_stretches"]
    assert first == 0 and last >= 2 * STALL_PATIENCE


def test_a_stall_changes_strategy_at_once_while_failed_calls_back_off():
    # after one empty plan every call fails, and the retries back off (5, 10, 15 steps):
    # the stall's change of strategy does not wait for the next retry
    asked: list[tuple[int, str]] = []

    def first_only(state, agents, reason=""):
        asked.append((state.t, reason))
        return PlanOutcome("solved" if len(asked) == 1 else "timeout", [], 0.0)

    state = _lane(horizon=STALL_PATIENCE + 3)
    run_episode(state, [(Executive(first_only), [0])])
    assert (STALL_PATIENCE, "stall_all") in asked, asked


def test_result_rows_record_stalls_for_any_agent(tmp_path):
    from ocplus_plan.eval.results import read_results
    from ocplus_plan.eval.runner import EvalConfig, run_eval

    run_eval(EvalConfig(presets=["easy"], agents=["stay", "greedy"], seeds=[0], out=tmp_path,
                        horizon=40, n_agents=1, jobs=1, quiet=True), echo=lambda *a: None)
    rows = {r["agent"]: r for r in read_results(tmp_path)}
    assert rows["stay"]["stall_stretches"] == [[0, 40]]
    assert rows["greedy"]["stall_stretches"] == []


def test_carrying_a_raw_steak_toward_the_oven_is_progress_where_the_oven_heats_it():
    from tests.sim.test_oven_kitchen import OVEN_MAP, TO_OVEN

    state = new_state(make_rules("medium", map=OVEN_MAP), 0)
    meter = ProgressMeter(state)
    for a in TO_OVEN[:2]:  # step left, then take the steak from its counter
        transition(state, [a])
    assert state.agent_hand[0] >= 0
    meter.update(state)
    transition(state, [TO_OVEN[2]])  # down: next to the oven
    assert meter.update(state)

"""Beside a partner on a switching kitchen: a greedy cook passes over what the cook it does
not drive finishes sooner than its own walk over the switch (``agents/greedy.py``,
``_pass_sooner``), and a planning cook beside a greedy partner keeps its part of every cook's
plan when that ends sooner than its own (``execution.partner.sooner_jointly``)."""

from __future__ import annotations

import warnings

import pytest

from ocplus_plan.agents import Episode, with_partner
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.agents.planner import make_planner_agent
from ocplus_plan.execution.partner import Prediction, plan_around
from ocplus_plan.execution.plans import PlanOutcome, PlanStep
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

warnings.simplefilter("ignore", UserWarning)

# two rooms; the gap (1,3) is a wall in layout 0 and floor in layout 1 (switch every 10
# steps); counters (2,3) and (3,3) between them. Left: the tomato crate and the window;
# right: the board and the plates
GAP = [[1, 3, 1, 1, 1, 6, 1],
       [1, 0, 0, -1, 0, 0, 1],
       [1, 0, 0, 1, 0, 0, 1],
       [1, 0, 0, 1, 0, 0, 1],
       [1, 7, 1, 1, 1, 5, 1]]
_STAY = int(Action.STAY)


def _kitchen(horizon: int, dynamic: bool = True, spawns=((2, 4), (1, 1))):
    walls = [[0 if v == -1 else v for v in row] for row in GAP]
    spec = {"name": "gap", "game_map": GAP if dynamic else walls, "switch_map": walls,
            "agent_spawn_points": [list(p) for p in spawns], "is_dynamic_map": dynamic,
            "map_switch_step": 10}
    return new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                dynamic=dynamic, horizon=horizon), 0)


def _middle(state) -> list[int]:
    return [state.geo.flat(r, 3) for r in (2, 3)]


def _greedy_left(state, steps: int) -> GreedyAgent:
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    for _ in range(steps):
        transition(state, [_STAY, *greedy.act(state)])
    return greedy


def test_greedy_passes_over_what_the_other_room_finishes_before_the_switch():
    """Layout 0: the gap is shut for 10 steps. The greedy cook (left) takes the tomato; the
    board is in the right room, where the cook it does not drive stands: it passes the
    tomato over a middle counter instead of waiting to carry it across, and leaves it there
    for that cook (it does not take it back while the cook stands still)."""
    state = _kitchen(20)
    greedy = _greedy_left(state, 9)
    assert greedy.info().get("greedy_passes") == 1
    passed = [state.cell_item[c] for c in _middle(state) if state.cell_item[c] >= 0]
    assert len(passed) == 1 and state.agent_hand[1] < 0
    for _ in range(6):
        transition(state, [_STAY, *greedy.act(state)])
        assert state.agent_hand[1] != passed[0]


def test_greedy_carries_it_itself_where_no_switch_stands_in_the_way():
    """The same kitchen with the gap always open: the greedy cook reaches the board now and
    carries the tomato there itself (nothing passed)."""
    state = _kitchen(20, dynamic=False)
    greedy = _greedy_left(state, 12)
    assert "greedy_passes" not in greedy.info()
    assert all(state.cell_item[c] < 0 for c in _middle(state))


def _fd_ok() -> bool:
    from ocplus_plan.planning.engines import availability

    return availability("fast-downward").ok


@pytest.mark.skipif(not _fd_ok(), reason="fast-downward unavailable")
def test_a_planning_cook_takes_what_a_greedy_partner_passes_across():
    """Our cook in the right room (board, plates), the greedy partner in the left (crate,
    window), the gap shut for the first 10 steps: the partner passes the tomato over a
    middle counter, the partner model predicts it, and our plan takes it from there: the
    first dish at step 24 (at 37 when the partner carried it across itself)."""
    state = _kitchen(30)
    agent = make_planner_agent("", 0)
    Episode(state, with_partner(agent, GreedyAgent(0), 2)).run()
    assert state.stats["dishes_served"] >= 1, agent.info()


# sooner_jointly, with planners that answer as scripted: which plan our cook keeps
def _own(end: float) -> PlanOutcome:
    return PlanOutcome("solved", [PlanStep(0, 0, "pickup", 1, (0,), start=0.0, duration=end)],
                       relaxed=True)


def _joint(ours_waits: bool) -> PlanOutcome:
    """The partner (cook 1) passes item 5 over counter 20, our cook (0) takes it there; unless
    ``ours_waits``, our cook first fetches item 6 from cell 30 (nothing the partner touches)."""
    steps = [PlanStep(0, 1, "pickup", 10, (5,), 0.0, 2.0),
             PlanStep(1, 1, "putdown", 20, (5,), 2.0, 2.0),
             PlanStep(2, 0, "pickup", 20, (5,), 4.0, 1.0)]
    if not ours_waits:
        steps.append(PlanStep(3, 0, "pickup", 30, (6,), 0.0, 3.0))
    return PlanOutcome("solved", steps, relaxed=True)


def _planner(own: PlanOutcome, joint: PlanOutcome, asked: list):
    def plan(state, agents, reason):
        asked.append(tuple(agents))
        return joint if len(agents) > 1 else own
    return plan


@pytest.mark.parametrize(("own_end", "ours_waits", "kept"), [
    (30.0, False, [3]),  # every cook's plan ends sooner: our step before the hand-over
    (4.0, False, [0]),  # it ends no sooner: our own plan
    (30.0, True, [0]),  # our first step waits for the partner's: our own plan
])
def test_every_cooks_plan_is_kept_up_to_the_partners_step_when_it_ends_sooner(
        own_end, ours_waits, kept):
    state, asked = _kitchen(30), []
    predictions = {1: Prediction(1, None, by_policy=True)}
    out = plan_around(_planner(_own(own_end), _joint(ours_waits), asked), state, (0,),
                      "initial", predictions)
    assert [s.index for s in out.steps] == kept
    assert asked == [(0,), (0, 1)]


def test_a_partner_not_predicted_by_its_policy_gets_no_plan_of_every_cook():
    """A guessed partner (idle, learned) may never make the hand-over: our own plan only."""
    state, asked = _kitchen(30), []
    out = plan_around(_planner(_own(30.0), _joint(False), asked), state, (0,), "initial",
                      {1: Prediction(1, None)})
    assert [s.index for s in out.steps] == [0] and asked == [(0,)]


# the same two rooms with the crate and the board swapped: the tomato crate in the right
# room (with the plates), the board and the window in the left; the gap shut for 40 steps
CRATE_RIGHT = [[1, 6, 1, 1, 1, 3, 1], *GAP[1:]]


def _crate_right(partner_at: tuple[int, int]):
    spec = {"name": "gap-crate-right", "game_map": CRATE_RIGHT,
            "switch_map": [[0 if v == -1 else v for v in row] for row in CRATE_RIGHT],
            "agent_spawn_points": [list(partner_at), [1, 1]], "is_dynamic_map": True,
            "map_switch_step": 40}
    return new_state(make_rules("easy", map=spec, n_agents=2, recipes=["tomato"],
                                dynamic=True, horizon=60), 0)


def _fetch_steps(state, partner_moves: bool) -> list[int]:
    """Greedy drives the left cook (1); the partner (0) stands still, or steps to and fro
    in its room. The steps of the shut gap (0-39) at which greedy heads for the crate."""
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    heading = []
    for t in range(40):
        assert state.layout_index == 0
        _, goals = greedy.goals(state)
        if goals.get(1, (None, ""))[1] == "fetch":
            heading.append(t)
        partner = (int(Action.DOWN) if t % 2 == 0 else int(Action.UP)) if partner_moves else _STAY
        transition(state, [partner, *greedy.act(state)])
    return heading


def test_greedy_leaves_work_behind_the_switch_to_a_partner_that_moves():
    """The crate is in the right room, where the partner (moving) stands. Beside it the
    greedy cook, on the left, works as beside a teammate, in what it reaches now: it does
    not wait for the switch to cross, fetch the tomato and cross back."""
    assert _fetch_steps(_crate_right((2, 4)), partner_moves=True) == []


def test_greedy_hands_over_to_a_partner_that_moves_as_to_a_teammate():
    """The first kitchen (crate and window left, board right, the gap shut for 10 steps),
    the partner stepping to and fro in the right room: the greedy cook fetches the tomato
    and puts it on a middle counter for the partner before the gap opens."""
    state = _kitchen(12)
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    for t in range(10):
        partner = int(Action.DOWN) if t % 2 == 0 else int(Action.UP)
        transition(state, [partner, *greedy.act(state)])
    assert greedy.info().get("greedy_passes") == 1
    assert sum(state.cell_item[c] >= 0 for c in _middle(state)) == 1


def test_greedy_does_not_count_on_a_partner_that_stands_still():
    """The partner in the right room never moves: after 30 steps the greedy cook stops
    counting on it and heads for the tomato over the switch itself."""
    heading = _fetch_steps(_crate_right((2, 4)), partner_moves=False)
    assert heading and heading[0] == 30

"""``--partner AGENT``: the last cook is played by an agent the evaluated one does not drive,
and a planner-backed controller plans around it."""

from __future__ import annotations

import warnings

import pytest

from ocplus_plan.agents import Episode, StayAgent, make_controller
from ocplus_plan.agents import with_partner
from ocplus_plan.agents.base import Controller
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.agents.planner import PlannerAgent, make_planner_agent
from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, run_eval
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.codes import Action

warnings.simplefilter("ignore", UserWarning)


def _cfg(out, **kw) -> EvalConfig:
    base = dict(presets=["easy"], agents=["greedy"], seeds=[0], out=out, horizon=40,
                n_agents=2, jobs=1, quiet=True)
    base.update(kw)
    return EvalConfig(**base)


def test_an_idle_partner_plays_the_last_cook_and_never_moves():
    state = new_state(make_rules("easy", n_agents=2), 0)
    start = state.agent_pos[1]
    episode = Episode(state, with_partner(make_controller("greedy"), "idle", 2))
    for _ in range(40):
        episode.step()
        assert state.agent_pos[1] == start
    assert episode.team.assignment == [(0,), (1,)]


@pytest.mark.parametrize("partner", ["idle", "greedy"])
def test_eval_partner_rows_name_the_partner(tmp_path, partner):
    out = tmp_path / partner
    run_eval(_cfg(out, partner=partner), echo=lambda *a: None)
    (row,) = read_results(out)
    assert row["status"] == "ok", row.get("reason")
    assert row["partner"] == partner and row["agent"] == f"greedy +{partner}"


def test_eval_partner_needs_a_second_cook(tmp_path):
    with pytest.raises(ConfigError, match="at least 2 cooks"):
        run_eval(_cfg(tmp_path / "one", n_agents=1, partner="idle"))


def test_eval_partner_must_be_a_known_agent(tmp_path):
    with pytest.raises(ConfigError, match="unknown agent"):
        run_eval(_cfg(tmp_path / "bad", partner="nobody"))


def test_the_cli_takes_partner(tmp_path):
    from ocplus_plan.cli import main

    out = tmp_path / "cli"
    assert main(["eval", "--presets", "easy", "--agents", "greedy", "--seeds", "1",
                 "--horizon", "30", "--n-agents", "2", "--partner", "idle", "--out", str(out),
                 "--quiet"]) == 0
    assert read_results(out)[0]["partner"] == "idle"


def _fd_ok() -> bool:
    try:
        from ocplus_plan.planning.engines import availability
    except ImportError:  # pragma: no cover
        return False
    return availability("fast-downward").ok


@pytest.mark.skipif(not _fd_ok(), reason="fast-downward unavailable")
def test_an_idle_partner_is_planned_around_not_given_work():
    """The planner models only the cook it drives: no step goes to the partner's cook, and
    the driven cook serves dishes with the idle cook in its kitchen."""
    rules = make_rules("easy", n_agents=2, recipes=["tomato"], horizon=60)
    state = new_state(rules, 0)
    agent = PlannerAgent("fast-downward")
    seen: set[int] = set()

    def watch(episode, result):
        seen.update(t.step.agent for q in agent.executive.queues.values() for t in q)

    Episode(state, with_partner(agent, StayAgent(), 2)).run(on_step=watch)
    assert agent.executive.agent_ids == (0,)
    assert agent.executive.planner.modelled_cooks(state, (0,), "stations") == [0]
    assert seen <= {0}
    assert state.stats["dishes_served"] >= 1, agent.info()


def test_a_partner_holding_an_item_is_modelled_but_not_driven():
    from ocplus_plan.execution.planning_step import compile_and_solve

    state = new_state(make_rules("easy", map="gen:open:train:0:easy", n_agents=3), 0)
    pipeline = compile_and_solve("fast-downward")
    assert pipeline.modelled_cooks(state, (0, 1), "stations") == [0, 1]
    assert pipeline.modelled_cooks(state, (0, 1, 2), "stations") is None
    state.agent_hand[2] = 0  # (only the hand is read)
    assert pipeline.modelled_cooks(state, (0, 1), "stations") == [0, 1, 2]


# two halves joined by the counters (1,2) and (2,2): the tomato crate and the window on the
# partner's side (cook 1, left), the board and the plate on ours (cook 0, right)
HALVES = {"name": "halves", "max_n_agent": 2,
          "game_map": [[1, 1, 1, 1, 1],
                       [3, 0, 1, 0, 6],
                       [7, 0, 1, 0, 5],
                       [1, 1, 1, 1, 1]],
          "agent_spawn_points": [[1, 3], [1, 1]]}


class _Teammate(Controller):
    """Plays its cook as a greedy controller driving every cook would: it hands what it
    cannot use over to the other cook through a counter (as a clone of two greedy cooks)."""

    name = "teammate"

    def __init__(self) -> None:
        self.inner = GreedyAgent(0)

    def _reset(self, state) -> None:
        self.inner.reset(state, list(range(state.n_agents)))

    def act(self, state) -> list[int]:
        actions = self.inner.act(state)
        return [actions[a] for a in self.agent_ids]


@pytest.mark.skipif(not _fd_ok(), reason="fast-downward unavailable")
def test_a_cook_that_cannot_serve_alone_does_its_half_of_a_split_kitchen():
    """Our cook reaches neither the crate nor the window: alone it has no plan. It plans
    every cook, does its steps up to the first that waits for the partner's hand-over (it
    waits, asking again), then chops and plates what the partner hands over and leaves
    the dish on a counter between the halves, where the partner takes it to the window."""
    state = new_state(make_rules("easy", map=HALVES, n_agents=2, recipes=["tomato"],
                                 horizon=25), 0)
    agent = make_planner_agent("", 0)
    Episode(state, with_partner(agent, _Teammate(), 2)).run()
    info = agent.info()
    assert state.stats["dishes_served"] >= 1, info
    assert info["statuses"].get("waiting", 0) >= 1  # its first step waited for the partner


def _halves(horizon: int, spawns=((1, 3), (1, 1)), game_map=None, recipe="tomato"):
    m = dict(HALVES, agent_spawn_points=[list(p) for p in spawns])
    if game_map is not None:
        m["game_map"] = game_map
    return new_state(make_rules("easy", map=m, n_agents=2, recipes=[recipe], horizon=horizon), 0)


def test_a_greedy_cook_hands_over_to_a_cook_it_does_not_drive():
    """Driving only the crate side (cook 1), greedy passes the tomato over a counter between
    the halves to the cook it does not drive, which alone reaches the board."""
    state = _halves(12)
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    middle = [state.geo.flat(r, 2) for r in (1, 2)]
    for _ in range(12):
        transition(state, [int(Action.STAY), *greedy.act(state)])
        if any(state.cell_item[c] >= 0 for c in middle):
            break
    assert any(state.cell_item[c] >= 0 for c in middle)
    assert greedy.info()["greedy_passes"] == 1


def test_two_greedy_controllers_one_cook_each_serve_on_a_split_kitchen():
    """Each greedy controller drives one cook of the split kitchen: the tomato crosses one
    way, the dish the other, and dishes are served (before, neither half served anything)."""
    state = _halves(60)
    left, right = GreedyAgent(0), GreedyAgent(1)
    Episode(state, [(right, [0]), (left, [1])]).run()
    assert state.stats["dishes_served"] >= 2
    assert left.info()["greedy_passes"] >= 2 and right.info()["greedy_passes"] >= 1


# the halves with four counters between them and three crates (tomato, lettuce, onion) on
# the left: more items than the bounded passes
TALL = [[1, 1, 1, 1, 1],
        [3, 0, 1, 0, 6],
        [4, 0, 1, 0, 1],
        [8, 0, 1, 0, 1],
        [7, 0, 1, 0, 5],
        [1, 1, 1, 1, 1]]


def test_a_greedy_cook_beside_an_idle_partner_stops_passing_items():
    """The cook it does not drive never takes anything: of the three vegetables the orders
    need, greedy passes 2 (the bound on items lying untaken) and then leaves the crates
    alone; the counters between the halves do not fill up."""
    state = _halves(80, game_map=TALL, recipe="tomato+onion+lettuce")
    greedy = GreedyAgent(0)
    greedy.reset(state, [1])
    middle = [state.geo.flat(r, 2) for r in range(1, 5)]
    for _ in range(80):
        transition(state, [int(Action.STAY), *greedy.act(state)])
    assert sum(state.cell_item[c] >= 0 for c in middle) == 2
    assert greedy.info()["greedy_passes"] == 2
    assert state.agent_hand[1] < 0  # it is not left carrying a third


@pytest.mark.skipif(not _fd_ok(), reason="fast-downward unavailable")
@pytest.mark.parametrize("spawns", [((1, 3), (1, 1)), ((1, 1), (1, 3))])
def test_a_planning_cook_serves_beside_a_greedy_partner_on_a_split_kitchen(spawns):
    """Our cook on either half, a greedy partner on the other: the partner's policy, as the
    partner model predicts it, passes the tomato (or the dish) over, and our cook plans to
    take it from the counter: dishes are served both ways."""
    state = _halves(24, spawns)
    agent = make_planner_agent("", 0)
    Episode(state, with_partner(agent, GreedyAgent(0), 2)).run()
    assert state.stats["dishes_served"] >= 1, agent.info()

"""Faults from the CLI: the ``--faults`` grammar, the schedule it makes, and a blocking
agent that moves and never seals the kitchen."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ocplus_plan.agents import run_episode
from ocplus_plan.agents.greedy import GreedyAgent
from ocplus_plan.cli import main
from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.results import read_results
from ocplus_plan.eval.runner import EvalConfig, run_eval
from ocplus_plan.execution.faults import (
    FAULT_KEYS,
    BlockingAgent,
    FaultSpec,
    parse_faults,
    safe_cells,
)
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import Cell
from ocplus_plan.sim.maps import available_maps
from ocplus_plan.sim.queries import distances, interaction_spots

#: shipped maps and a preset that takes each
MAPS = {"easy_open": "easy", "easy_divided": "easy", "medium_kitchen": "medium",
        "mapA": "easy", "mapB": "easy", "mapC": "hard", "hard_switch": "hard",
        "trio_kitchen": "hard", "corridor3": "easy", "medium_ring": "medium"}


def test_the_documented_example_parses():
    spec = parse_faults("burns:3,switches:40,message-loss:0.3,blocker:moving")
    assert spec == FaultSpec(burns=3, switch_every=40, message_loss=0.3, blocker="moving")
    assert str(spec) == "burns:3,switches:40,message-loss:0.3,blocker:moving"
    assert parse_faults(str(spec)) == spec


def test_no_faults_is_empty_and_false():
    assert not parse_faults("") and not parse_faults(None) and str(parse_faults("")) == ""


@pytest.mark.parametrize("bad, problem", [
    ("burn:3", "known key"), ("burns", "KEY:VALUE"), ("burns:0", "whole number"),
    ("burns:-1", "whole number"), ("switches:x", "whole number"),
    ("message-loss:1.5", "probability"), ("message-loss:nan", "probability"),
    ("blocker:still", "moving"), ("burns:1,burns:2", "twice"),
])
def test_bad_faults_are_refused_with_the_allowed_keys(bad, problem):
    with pytest.raises(ConfigError, match=problem) as info:
        parse_faults(bad)
    assert all(key in str(info.value) for key in FAULT_KEYS)


def test_cli_exits_2_naming_the_keys(tmp_path, capsys):
    code = main(["eval", "--presets", "easy", "--agents", "greedy", "--seeds", "1",
                 "--faults", "fire:1", "--out", str(tmp_path / "x"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "message-loss" in err and "blocker" in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


def test_schedule_spreads_burns_and_repeats_switches():
    sched = parse_faults("burns:3,switches:40").schedule(200)
    assert sched.burns == [50, 100, 150]
    assert sched.switches == [40, 80, 120, 160]


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 50), horizon=st.integers(1, 500))
def test_burns_are_inside_the_episode_and_as_many_as_asked(n, horizon):
    burns = FaultSpec(burns=n).schedule(horizon).burns
    assert len(burns) == n and all(0 <= t <= horizon for t in burns)
    assert burns == sorted(burns)


def _geo(name):
    try:
        rules = make_rules(MAPS[name], map=name)
    except ConfigError:  # a paper map without a switch layout on the hard preset
        rules = make_rules(MAPS[name], map=name, dynamic=False)
    return new_state(rules, 0).geo


@pytest.mark.parametrize("name", sorted(MAPS))
def test_a_safe_cell_neither_splits_the_floor_nor_blocks_a_stations_only_access(name):
    assert name in available_maps()
    geo = _geo(name)
    for li, walk in enumerate(geo.walkables):
        n = geo.rows * geo.cols
        interactive = [f for f in range(n) if not walk[f] and geo.terrains[li][f] != Cell.BLOCK]
        for cell in safe_cells(geo, li):
            assert walk[cell] and cell not in geo.switch_cells
            without = list(walk)
            without[cell] = False
            floor = [f for f in range(n) if walk[f] and f != cell]
            for f in floor:  # every pair that was connected still is
                before = distances(geo.neighbors, walk, [f])
                after = distances(geo.neighbors, without, [f])
                assert all((before[g] >= 0) == (after[g] >= 0) for g in floor)
            for station in interactive:
                if interaction_spots(geo.neighbors, walk, station):
                    assert interaction_spots(geo.neighbors, without, station)


def test_a_ring_kitchen_has_no_safe_cell_and_refuses_a_blocker(tmp_path):
    assert not safe_cells(_geo("medium_ring"), 0)
    with pytest.raises(ConfigError, match="no floor cell"):
        BlockingAgent().reset(new_state(make_rules("medium", map="medium_ring", n_agents=2), 0))


def test_a_blocking_cell_before_the_only_window_spot_is_refused():
    state = new_state(make_rules("easy", n_agents=2), 0)
    geo = state.geo
    window = next(f for f, code in enumerate(geo.terrains[0]) if code == Cell.DELIVERY)
    (spot,) = interaction_spots(geo.neighbors, geo.walkables[0], window)
    with pytest.raises(ConfigError, match="seal"):
        BlockingAgent(geo.rc(spot)).reset(state, [1])


@pytest.mark.parametrize("preset, name, seed", [("medium", "medium_kitchen", 0),
                                                ("hard", "mapC", 1), ("easy", "easy_open", 2)])
def test_the_moving_blocker_moves_and_once_safe_never_stands_on_an_unsafe_cell(preset, name,
                                                                               seed):
    rules = make_rules(preset, map=name, n_agents=2)
    state = new_state(rules, seed)
    blocker = BlockingAgent(seed=seed)
    seen = []

    class Watch(GreedyAgent):
        def act(self, st):
            seen.append((st.agent_pos[1], st.layout_index))
            return super().act(st)

    stats = run_episode(state, [(Watch(seed), [0]), (blocker, [1])], steps=150)
    assert stats["max_agents_per_cell"] == 1
    assert len({pos for pos, _ in seen}) >= 4 and blocker.moves >= 10  # it moves
    first_safe = next(i for i, (pos, li) in enumerate(seen) if pos in safe_cells(state.geo, li))
    after = seen[first_safe:]
    unsafe = [(i, pos) for i, (pos, li) in enumerate(after)
              if pos not in safe_cells(state.geo, li) and not state.rules.dynamic]
    assert not unsafe


def test_eval_with_faults_records_what_they_did(tmp_path, capsys):
    out = tmp_path / "f"
    assert main(["eval", "--presets", "medium", "--agents", "greedy", "--seeds", "1",
                 "--n-agents", "1", "--horizon", "120", "--faults", "burns:2,blocker:moving",
                 "--out", str(out), "--quiet"]) == 0
    assert "[burns:2,blocker:moving]" in capsys.readouterr().out
    (row,) = read_results(out)
    assert row["faults"] == "burns:2,blocker:moving" and row["key"].endswith(row["faults"])
    assert row["n_agents"] == 1 and len(row["metrics"]["heatmaps"]) == 2  # cook + blocker
    assert row["fault_report"]["blocker_moves"] > 0
    assert row["fault_report"]["burns"] <= 2
    assert "faults" in (out / "summary.csv").read_text().splitlines()[0]


def test_a_blocker_needs_room_for_one_more_agent(tmp_path):
    cfg = EvalConfig(presets=["easy"], agents=["greedy"], seeds=[0], out=tmp_path / "b",
                     n_agents=2, faults="blocker:moving", quiet=True)
    with pytest.raises(ConfigError, match="no room"):
        run_eval(cfg)
    assert not (tmp_path / "b").exists()

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError, MapFormatError, OcplusError
from ocplus_plan.sim import available_maps, load_map, make_rules, new_state, transition
from ocplus_plan.sim.codes import Cell
from ocplus_plan.sim.state import conservation_problems
from tests.paper_maps import LOADABLE, PAPER_MAPS, paper_map_text

GOOD = {
    "name": "g",
    "game_map": [[1, 3, 1, 6, 1], [5, 0, 0, 0, 7], [1, 1, 1, 1, 1]],
    "agent_spawn_points": [[1, 1], [1, 3]],
}


def load_yaml(tmp_path: Path, text: str):
    p = tmp_path / "m.yaml"
    p.write_text(text)
    return load_map(p)


def test_every_shipped_map_loads_and_mapc_matches_the_paper():
    maps = available_maps()
    assert {"mapC", "easy_open", "easy_divided", "medium_kitchen", "medium_ring",
            "hard_switch", "trio_kitchen", "corridor3"} <= set(maps)
    for name in maps:
        assert load_map(name).name == name
    c = load_map("mapC")
    assert c.shape == (9, 9) and c.max_agents == 3 and c.is_dynamic and c.map_switch_step == 15
    assert c.spawn_points == ((1, 7), (7, 7), (1, 4))
    assert c.cells_of(Cell.PAN) == ((8, 5),) and c.cells_of(Cell.DELIVERY) == ((4, 0),)
    assert len(c.switching_cells()) == 6


def test_both_key_spellings_load_the_same_map(tmp_path):
    a = load_yaml(tmp_path, """
game_map: [[1, 3, 1, 6, 1], [5, 0, 0, 0, 7], [1, 1, 1, 1, 1]]
max_n_agent: 2
agent_spawn_points: [[1, 1], [1, 3]]
""")
    b = load_yaml(tmp_path, """
map: [[1, 3, 1, 6, 1], [5, 0, 0, 0, 7], [1, 1, 1, 1, 1]]
max_n_agnet: 2
agent_initial_coordinates: [[1, 1], [1, 3]]
""")
    assert (a.grid == b.grid).all() and a.spawn_points == b.spawn_points == ((1, 1), (1, 3))
    assert a.max_agents == b.max_agents == 2


def test_spawn_cells_with_code_2_are_spawn_points():
    layout = load_map({"game_map": [[1, 3, 1, 6, 1], [5, 2, 0, 2, 7], [1, 1, 1, 1, 1]]})
    assert layout.spawn_points == ((1, 1), (1, 3))


@pytest.mark.parametrize(
    "change, words",
    [
        ({"game_map": [[1, 3, 1], [5, 0, 0, 7], [1, 1, 1]]}, ["row 1", "4 cells"]),
        ({"game_map": [[1, 3, 1, 6, 1], [5, 0, 14, 0, 7], [1, 1, 1, 1, 1]]},
         ["row 1, column 2", "14"]),
        ({"game_map": [[1, 3, 1, 6, 1], [5, 0, 0, 0, 1], [1, 1, 1, 1, 1]]}, ["delivery"]),
        ({"agent_spawn_points": [[0, 0]]}, ["[0, 0]", "counter", "floor"]),
        ({"agent_spawn_points": [[5, 1]]}, ["[5, 1]", "outside"]),
        ({"max_n_agent": 0}, ["max_n_agent", "positive"]),
        ({"map_switch_step": -1}, ["map_switch_step", "-1"]),
        ({"switch_map": GOOD["game_map"], "is_dynamic_map": True, "map_switch_step": 0},
         ["map_switch_step", "dynamic", "got 0"]),
        ({"colour": "red"}, ["unknown key 'colour'"]),
        ({"dimensions": [4, 3]}, ["dimensions", "5 columns"]),
        ({"switch_map": [[1, 3, 1, 1, 1], [5, 0, 0, 0, 7], [1, 1, 1, 1, 1]]},
         ["row 0, column 3", "board"]),
        ({"switch_map": [[1, 1, 1, 6, 1], [5, 0, 0, 0, 7], [1, 1, 1, 1, 1]]},
         ["row 0, column 1", "tomato"]),
        ({"map": [[1]]}, ["repeats"]),
        ({"is_dynamic_map": True}, ["no 'switch_map'"]),
    ],
)
def test_bad_maps_name_the_fault(change, words):
    spec = {**GOOD, **change}
    with pytest.raises(MapFormatError) as err:
        load_map(spec, source="bad.yaml")
    msg = str(err.value)
    assert "bad.yaml" in msg
    for w in words:
        assert w in msg, (w, msg)


def test_yaml_syntax_error_names_file_and_line(tmp_path):
    with pytest.raises(MapFormatError, match=r"m\.yaml: YAML syntax error at line 2"):
        load_yaml(tmp_path, "game_map: [[1, 2]\n  bad: [\n")


def test_empty_file_is_an_error(tmp_path):
    with pytest.raises(MapFormatError, match="empty"):
        load_yaml(tmp_path, "")


def test_unknown_map_name_lists_the_registered_ones():
    with pytest.raises(OcplusError, match="registered maps: .*mapC"):
        load_map("no_such_map")


# ------------------------------------------------------------ the paper's own map files

#: the paper's presets (its env_creater): map -> the presets whose stations it has
PAPER_PRESETS = {"mapA": ("easy",), "mapB": ("easy", "medium"), "mapC": ("easy", "medium", "hard"),
                 "mapD": ("easy",), "mapF": ("easy", "medium")}


@pytest.mark.parametrize("name", LOADABLE)
def test_every_paper_map_in_its_own_format_loads(name, tmp_path):
    paper = PAPER_MAPS[name]
    layout = load_yaml(tmp_path, paper_map_text(name))
    assert layout.name == name and layout.is_dynamic == paper.dynamic
    assert layout.grid.tolist() == [list(r) for r in paper.rows]
    assert layout.spawn_points == paper.spawns
    # max_n_agent above the spawn count (mapF says 3 for 2 spawn points) is capped
    assert layout.max_agents == min(paper.max_n_agent, len(paper.spawns))
    assert layout.declared_max_agents == paper.max_n_agent


@pytest.mark.parametrize("name", LOADABLE)
def test_every_paper_map_runs_an_episode_with_the_presets_it_can_host(name, tmp_path):
    path = tmp_path / f"{name}.yaml"
    path.write_text(paper_map_text(name))
    layout = load_map(path)
    for preset in PAPER_PRESETS[name]:
        rules = make_rules(preset, map=layout, n_agents=layout.max_agents,
                           dynamic=layout.is_dynamic)
        state = new_state(rules, seed=3)
        rng = np.random.default_rng(0)
        result = None
        for _ in range(rules.horizon):
            result = transition(state, rng.integers(0, 5, rules.n_agents).tolist())
        assert result is not None and result.truncated and state.t == rules.horizon
        assert conservation_problems(state) == []


def test_a_static_map_ignores_its_switch_period_and_a_dynamic_one_needs_it(tmp_path):
    static = load_yaml(tmp_path, paper_map_text("mapA"))  # dynamic_map: False, map_switch_step: 0
    assert not static.is_dynamic and static.map_switch_step == 0
    rules = make_rules("easy", map=static)
    assert not rules.dynamic and rules.map_switch_step >= 1
    # a switch layout in a file marked static stays static, as in the paper's code
    with_switch = {**GOOD, "switch_map": GOOD["game_map"], "map_switch_step": 0,
                   "is_dynamic_map": False}
    with pytest.raises(ConfigError, match="marked static"):
        make_rules("easy", map=with_switch, dynamic=True)
    with pytest.raises(MapFormatError, match="map_switch_step.*dynamic"):
        load_map({**GOOD, "switch_map": GOOD["game_map"], "is_dynamic_map": True,
                  "map_switch_step": 0})


def test_max_n_agent_above_the_spawn_count_is_an_error_only_for_more_cooks(tmp_path):
    layout = load_yaml(tmp_path, paper_map_text("mapF"))
    assert make_rules("medium", map=layout, n_agents=2).n_agents == 2
    with pytest.raises(ConfigError) as err:
        make_rules("medium", map=layout, n_agents=3)
    msg = str(err.value)
    for words in ("n_agents=3", "mapF", "2 spawn points", "max_n_agent 3", "at most 2"):
        assert words in msg, (words, msg)


def test_the_paper_map_whose_switch_moves_a_station_is_refused_naming_the_cell(tmp_path):
    with pytest.raises(MapFormatError) as err:
        load_yaml(tmp_path, paper_map_text("mapE"))
    msg = str(err.value)
    assert "row 1, column 0" in msg and "sink (11)" in msg and "never move a station" in msg

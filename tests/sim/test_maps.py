from __future__ import annotations

from pathlib import Path

import pytest

from ocplus_plan.errors import MapFormatError, OcplusError
from ocplus_plan.sim import available_maps, load_map
from ocplus_plan.sim.codes import Cell

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
        ({"game_map": [[1, 3, 1, 6, 1], [5, 0, 13, 0, 7], [1, 1, 1, 1, 1]]},
         ["row 1, column 2", "13"]),
        ({"game_map": [[1, 3, 1, 6, 1], [5, 0, 0, 0, 1], [1, 1, 1, 1, 1]]}, ["delivery"]),
        ({"agent_spawn_points": [[0, 0]]}, ["[0, 0]", "counter", "floor"]),
        ({"agent_spawn_points": [[5, 1]]}, ["[5, 1]", "outside"]),
        ({"max_n_agent": 3}, ["max_n_agent", "3", "2 spawn points"]),
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

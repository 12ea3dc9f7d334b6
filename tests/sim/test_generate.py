"""The kitchen generator: determinism, soundness per family, splits and ``gen:`` names."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ocplus_plan.commands.check_map import summary
from ocplus_plan.errors import ConfigError, MapFormatError
from ocplus_plan.sim import make_rules, new_state
from ocplus_plan.sim.codes import WALKABLE, Cell
from ocplus_plan.sim.generate import (
    FAMILIES,
    PRESET_STATIONS,
    REQUIRED,
    SPLITS,
    floor_components,
    generate_map,
    lane_cells,
    map_from_name,
    map_to_yaml,
    parse_gen_name,
    split_seed,
    structure_problems,
)
from ocplus_plan.sim.generate_families import MAX_SIZE, MIN_COOKS, MIN_SIZE
from ocplus_plan.sim.kitchens import load_kitchen
from ocplus_plan.sim.maps import load_map, station_reachability


def _sizes(family: str) -> list[tuple[int, int]]:
    lo_r, lo_c = MIN_SIZE[family]
    return [(lo_r, lo_c), (MAX_SIZE, MAX_SIZE), (lo_r, MAX_SIZE), (MAX_SIZE, lo_c),
            ((lo_r + MAX_SIZE) // 2, (lo_c + MAX_SIZE) // 2)]


def test_same_arguments_give_the_same_bytes():
    first = map_to_yaml(generate_map("multiroom", 17, preset="medium"))
    assert map_to_yaml(generate_map("multiroom", 17, preset="medium")) == first


def test_a_fresh_process_gives_the_same_bytes():
    code = ("from ocplus_plan.sim.generate import generate_map, map_to_yaml; "
            "print(map_to_yaml(generate_map('corridor', 5)), end='')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out == map_to_yaml(generate_map("corridor", 5))


def test_different_seeds_give_different_kitchens():
    kitchens = {map_to_yaml(generate_map("open", s, name="k")) for s in range(10)}
    assert len(kitchens) == 10


def test_the_yaml_text_loads_to_the_same_map(tmp_path):
    spec = generate_map("switching", 3)
    path = tmp_path / "k.yaml"
    path.write_text(map_to_yaml(spec))
    a, b = load_map(path), load_map(spec)
    assert np.array_equal(a.grid, b.grid) and np.array_equal(a.switch_grid, b.switch_grid)
    assert a.spawn_points == b.spawn_points and a.map_switch_step == b.map_switch_step


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("preset", sorted(PRESET_STATIONS))
def test_every_size_and_cook_count_loads_and_is_sound(family, preset):
    for rows, cols in _sizes(family):
        for cooks in range(MIN_COOKS[family], 5):
            layout = load_map(generate_map(family, rows * cols + cooks, rows=rows, cols=cols,
                                           cooks=cooks, preset=preset))
            assert layout.shape == (rows, cols) and layout.max_agents == cooks
            assert structure_problems(layout, family, preset) == []
            assert all(layout.cells_of(code) for code in REQUIRED[preset])


@pytest.mark.parametrize("family", FAMILIES)
def test_check_map_finds_every_station_reachable_in_the_main_layout(family):
    layout = load_map(generate_map(family, 11))
    assert not [e for e in summary(layout)["unreachable"] if e["layout"] == 0]


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("preset", sorted(PRESET_STATIONS))
def test_a_preset_plays_its_own_kitchens(family, preset):
    layout = load_map(generate_map(family, 2, preset=preset))
    dynamic = {"dynamic": False} if preset == "hard" and family != "switching" else {}
    rules = make_rules(preset, map=layout, n_agents=layout.max_agents, **dynamic)
    assert new_state(rules, 0).orders


def test_split_halves_are_joined_by_no_floor_and_need_a_hand_over():
    layout = load_map(generate_map("split", 4))
    halves = floor_components(layout.grid)
    assert len(halves) == 2
    cols = layout.cols
    side = {i: next(k for k, h in enumerate(halves) if i in h) for h in halves for i in h}
    first, second = (side[r * cols + c] for r, c in layout.spawn_points[:2])
    assert first != second
    reach = [e for e in station_reachability(layout) if e["layout"] == 0]
    window = {k for e in reach if e["code"] == Cell.DELIVERY for k in e["reachable_from"]}
    boards = {k for e in reach if e["code"] == Cell.BOARD for k in e["reachable_from"]}
    assert window and boards and not window & boards


def test_split_needs_two_cooks():
    with pytest.raises(ConfigError, match="2 to 4 cooks"):
        generate_map("split", 0, cooks=1)


def test_corridor_has_one_lane_cells_on_one_floor():
    layout = load_map(generate_map("corridor", 8))
    assert lane_cells(layout.grid)
    assert len(floor_components(layout.grid)) == 1


def test_a_lane_cell_has_walls_on_both_sides():
    layout = load_map(generate_map("corridor", 9))
    walk = np.isin(layout.grid, [int(c) for c in WALKABLE])
    for r, c in lane_cells(layout.grid):
        assert (not walk[r - 1, c] and not walk[r + 1, c]) or (
            not walk[r, c - 1] and not walk[r, c + 1])


def test_switching_cuts_a_station_kind_off_in_the_switch_layout():
    layout = load_map(generate_map("switching", 6))
    assert layout.is_dynamic
    entries = station_reachability(layout)
    cut = {e["code"] for e in entries if e["layout"] == 1} - {
        e["code"] for e in entries if e["layout"] == 1 and e["reachable_from"]}
    assert cut and cut <= {int(Cell.BOARD), int(Cell.PAN)}
    assert all(e["reachable_from"] for e in entries if e["layout"] == 0)


def test_multiroom_has_rooms_joined_by_doors():
    layout = load_map(generate_map("multiroom", 2, rows=10, cols=10))
    doors = frozenset(r * layout.cols + c for r, c in lane_cells(layout.grid))
    assert doors and len(floor_components(layout.grid)) == 1
    assert len([c for c in floor_components(layout.grid, doors) if len(c) >= 2]) >= 2


def test_an_open_kitchen_fails_the_split_check():
    layout = load_map(generate_map("open", 1))
    assert structure_problems(layout, "split")


@settings(max_examples=40, deadline=None)
@given(family=st.sampled_from(FAMILIES), seed=st.integers(0, 2**31))
def test_any_seed_gives_a_sound_kitchen(family, seed):
    layout = load_map(generate_map(family, seed))
    assert structure_problems(layout, family) == []
    assert 3 <= layout.max_agents <= 4


def test_a_later_candidate_is_another_kitchen():
    a, b = generate_map("open", 3), generate_map("open", 3, candidate=1)
    assert a["game_map"] != b["game_map"]


def test_split_seeds_are_disjoint_ranges():
    assert split_seed("train", 5) == 5 and split_seed("test", 5) == SPLITS["test"] + 5
    with pytest.raises(ConfigError, match="split index"):
        split_seed("train", SPLITS["test"])


def test_a_gen_name_loads_the_split_kitchen():
    layout = load_kitchen("gen:corridor:test:2")
    expected = load_map(generate_map("corridor", split_seed("test", 2)))
    assert np.array_equal(layout.grid, expected.grid)
    assert layout.name == "gen:corridor:test:2"


def test_a_gen_name_takes_a_preset():
    assert parse_gen_name("gen:open:train:4:easy") == ("open", "train", 4, "easy")
    assert not load_kitchen("gen:open:train:4:easy").cells_of(Cell.PAN)


def test_the_map_parser_leaves_gen_names_to_the_kitchen_loader():
    with pytest.raises(MapFormatError, match="load it with sim.kitchens.load_kitchen"):
        load_map("gen:open:train:0")


@pytest.mark.parametrize("name", ["gen:open", "gen:kettle:test:1", "gen:open:dev:1",
                                  "gen:open:test:x", "gen:open:test:1:extreme"])
def test_a_bad_gen_name_says_how_to_write_one(name):
    with pytest.raises(MapFormatError, match="gen:FAMILY:SPLIT:INDEX"):
        map_from_name(name)


@pytest.mark.parametrize("kwargs, match", [
    ({"family": "maze"}, "unknown kitchen family"),
    ({"rows": 4}, "5 to 12 rows"),
    ({"cols": 13}, "cols"),
    ({"preset": "extreme"}, "unknown preset"),
    ({"cooks": 5}, "cooks"),
])
def test_bad_generator_arguments_are_refused(kwargs, match):
    args = {"family": "open", "seed": 0, **kwargs}
    family = args.pop("family")
    with pytest.raises(ConfigError, match=match):
        generate_map(family, **args)


def test_a_gen_name_listed_as_replaced_loads_its_proven_candidate():
    from ocplus_plan.sim.generate import PROOF_REPLACEMENTS

    (family, split, index), candidate = next(iter(PROOF_REPLACEMENTS.items()))
    loaded = map_from_name(f"gen:{family}:{split}:{index}")
    expected = generate_map(family, split_seed(split, index), candidate=candidate)
    assert loaded["game_map"] == expected["game_map"]


# ------------------------------------------------------------------ spawn cells
ROOM = np.array([[1, 1, 6, 1, 1],
                 [1, 0, 0, 0, 1],
                 [3, 0, 0, 0, 7],
                 [1, 0, 0, 0, 1],
                 [1, 1, 5, 1, 1]], dtype=np.int8)
#: the only cells in front of the board, the crate, the window and the plates
ONLY_WAYS = {(1, 2), (2, 1), (2, 3), (3, 2)}


def test_a_spawn_cell_is_never_the_only_way_to_a_station():
    from ocplus_plan.sim.generate import _place_cooks
    from ocplus_plan.sim.generate_checks import spawn_cuts_off
    from ocplus_plan.sim.generate_families import Sketch

    floor = [(r, c) for r in range(1, 4) for c in range(1, 4)]
    assert {c for c in floor if spawn_cuts_off([ROOM], c, floor)} == ONLY_WAYS
    sketch = Sketch(ROOM.copy(), {"room": floor}, cook_regions=("room", "room"))
    for seed in range(20):
        spawns = _place_cooks(sketch, np.random.default_rng(seed), [ROOM])
        assert not set(spawns) & ONLY_WAYS, (seed, spawns)


def test_a_one_lane_region_keeps_its_drawn_cell():
    from ocplus_plan.sim.generate import _place_cooks
    from ocplus_plan.sim.generate_families import Sketch

    lane = np.array([[1, 1, 1, 1, 1], [3, 0, 0, 0, 6], [1, 7, 1, 5, 1]], dtype=np.int8)
    cells = [(1, 1), (1, 2), (1, 3)]  # every one cuts the lane: nothing better to move to
    sketch = Sketch(lane.copy(), {"lane": cells}, cook_regions=("lane",))
    drawn = cells[int(np.random.default_rng(3).integers(3))]
    assert _place_cooks(sketch, np.random.default_rng(3), [lane]) == [drawn]


def test_an_idle_cook_on_its_spawn_cell_cuts_no_other_cook_off_outside_one_lane_regions():
    from ocplus_plan.sim.queries import stations_cut_off

    for family in FAMILIES:
        for index in range(6):
            rules = make_rules("medium", map=f"gen:{family}:test:{index}:medium", n_agents=2,
                               dynamic=family == "switching")
            state = new_state(rules, 0)
            geo, idle = state.geo, state.agent_pos[1]
            for layout in range(len(geo.walkables)):
                cut = stations_cut_off(geo, layout, idle, [state.agent_pos[0]])
                floor_nbrs = [n for n in geo.neighbors[idle] if n >= 0 and geo.walkables[layout][n]]
                # (a corridor kitchen may put a cook in a one-lane region: no cell there is free)
                assert not cut or (family == "corridor" and len(floor_nbrs) <= 2), \
                    (family, index, layout, cut)

"""One record per cell kind (``sim/stations.py``), and every table that shows or names a
cell kind agrees with it: words, map letters, heatmap colours and labels, sprites, the
planning model's place flags and object words."""

from __future__ import annotations

import numpy as np
import pytest

from ocplus_plan.planning.language import FACT_WORDS, PLACE_WORDS
from ocplus_plan.planning.model import FLUENTS
from ocplus_plan.render import sprites
from ocplus_plan.sim.codes import SPAWN_TILES, STATIONS, Cell, Item
from ocplus_plan.sim.observe_text import _STATION_ORDER
from ocplus_plan.sim.stations import (
    CELL_KINDS, KIND_OF, PLACE_FLAGS, ROLES, SPRITES, WORK_PLACES, CellKind,
)
from ocplus_plan.sim.words import CELL_GLYPHS, CELL_WORDS


def test_every_cell_code_has_exactly_one_record():
    assert sorted(int(k.code) for k in CELL_KINDS) == sorted(int(c) for c in Cell)


def test_every_record_is_well_formed():
    for k in CELL_KINDS:
        assert len(k.letter) == 1 and k.word, k
        assert all(0 <= v <= 255 for v in k.colour) and len(k.colour) == 3, k
        assert k.sprite in SPRITES and k.role in ROLES, k


def test_letters_tell_every_kind_apart_but_the_two_floors():
    letters = {}
    for k in CELL_KINDS:
        letters.setdefault(k.letter, set()).add(k.code)
    assert {c for codes in letters.values() if len(codes) > 1 for c in codes} == {
        Cell.FLOOR, Cell.SPAWN}


def test_the_kitchen_words_are_the_records():
    assert CELL_WORDS == {k.code: k.word for k in CELL_KINDS}
    assert CELL_GLYPHS == {k.code: k.letter for k in CELL_KINDS}


def test_the_text_lists_every_station_and_crate():
    assert set(_STATION_ORDER) == set(STATIONS)
    assert [k.code for k in WORK_PLACES] == list(_STATION_ORDER)


def test_crates_are_spawn_tiles_and_item_colours_are_their_crates():
    assert {k.code for k in CELL_KINDS if k.role == "crate"} == set(SPAWN_TILES)
    for item in Item:
        assert sprites.ITEM_COLOURS[int(item)] == KIND_OF[int(item)].colour


def test_every_tile_is_drawn_in_its_records_colour():
    for k in CELL_KINDS:
        tile = sprites.terrain_tile(int(k.code))
        found = {tuple(int(v) for v in px) for px in tile.reshape(-1, 3)}
        assert k.colour in found, k


def test_a_new_station_style_draws_a_marked_counter():
    oven = CellKind(Cell.PAN, "oven", "O", (200, 90, 20), "station", "process")
    tile = sprites._STYLES[oven.sprite](oven.colour)
    assert tile.shape == (sprites.TILE_SIZE, sprites.TILE_SIZE, 3)
    assert (tile == np.array(oven.colour, np.uint8)).all(axis=2).sum() > 50


def test_place_flags_are_model_fluents_over_places():
    assert set(PLACE_FLAGS.values()) <= set(FLUENTS)
    assert all(FLUENTS[flag] == ("place",) for flag in PLACE_FLAGS.values())
    for code, flag in PLACE_FLAGS.items():  # the words name the first kind with the flag
        owner = next(k for k in CELL_KINDS if k.pddl == flag)
        assert owner.word in FACT_WORDS[flag]
    # an added station plans as the shipped one whose flag it shares (the oven as the pan)
    assert PLACE_FLAGS[int(Cell.OVEN)] == PLACE_FLAGS[int(Cell.PAN)]


def test_planning_objects_are_called_by_the_record_word():
    for k in CELL_KINDS:
        assert PLACE_WORDS[k.name] == k.word


@pytest.mark.parametrize("kind", CELL_KINDS, ids=lambda k: k.name)
def test_heatmaps_use_the_record(kind):
    pytest.importorskip("matplotlib")
    from ocplus_plan.eval import plots

    assert plots._TERRAIN_RGB[int(kind.code)] == tuple(v / 255 for v in kind.colour)
    if kind.role in ("floor", "wall", "counter"):
        assert int(kind.code) not in plots._TERRAIN_LABEL
    else:
        assert plots._TERRAIN_LABEL[int(kind.code)] == kind.letter

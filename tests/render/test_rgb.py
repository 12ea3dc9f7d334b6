"""numpy RGB frames: shapes, what is drawn where, windows, and the rgb observation."""

from __future__ import annotations

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.render import TILE_SIZE, RgbEncoder, render_frame
from ocplus_plan.render.sprites import ITEM_COLOURS, UNKNOWN, terrain_tile
from ocplus_plan.sim import Cell, Item, make_rules, new_state, transition

T = TILE_SIZE


def tile(frame: np.ndarray, row: int, col: int) -> np.ndarray:
    return frame[row * T : (row + 1) * T, col * T : (col + 1) * T]


def test_whole_map_frame_shape_and_static_tiles():
    state = new_state(make_rules("hard", n_agents=2), 0)
    frame = render_frame(state)
    assert frame.shape == (9 * T, 9 * T, 3) and frame.dtype == np.uint8
    # the delivery window (4, 0) and the trash can (8, 1) are drawn as their tiles
    np.testing.assert_array_equal(tile(frame, 4, 0), terrain_tile(int(Cell.DELIVERY)))
    np.testing.assert_array_equal(tile(frame, 8, 1), terrain_tile(int(Cell.TRASH)))


def test_items_and_agents_are_drawn_and_move_with_the_state():
    state = new_state(make_rules("hard", n_agents=2), 0)
    frame = render_frame(state)
    tomato = np.array(ITEM_COLOURS[int(Item.TOMATO)], np.uint8)
    assert (tile(frame, 7, 8) == tomato).all(axis=2).sum() > 20  # tomato on its spawn tile
    floor = tile(frame, 2, 7).copy()
    agent_tile = tile(frame, 1, 7)
    assert not np.array_equal(agent_tile, floor)  # agent 0 stands on (1, 7)
    transition(state, [1, 4])  # agent 0 moves down
    after = render_frame(state)
    np.testing.assert_array_equal(tile(after, 1, 7), floor)


def test_window_frames_are_centred_and_black_outside_the_map():
    state = new_state(make_rules("hard", n_agents=2), 0)
    full = render_frame(state)
    win = render_frame(state, window=2, agent=0)  # agent 0 at (1, 7)
    assert win.shape == (5 * T, 5 * T, 3)
    assert (win[:T] == np.array(UNKNOWN, np.uint8)).all()  # row -1 is outside the map
    np.testing.assert_array_equal(win[2 * T : 3 * T, 2 * T : 3 * T], tile(full, 1, 7))
    np.testing.assert_array_equal(win[T:, : 4 * T], full[0 : 4 * T, 5 * T : 9 * T])


def test_rgb_encoder_observations_and_tile_rescaling():
    rules = make_rules("hard", n_agents=2)
    state = new_state(rules, 0)
    obs = RgbEncoder(rules, 1).encode(state)
    assert obs.shape == (2, 3 * T, 3 * T, 3)
    np.testing.assert_array_equal(obs[1], render_frame(state, window=1, agent=1))
    big = render_frame(state, tile=2 * T)
    assert big.shape == (18 * T, 18 * T, 3)
    np.testing.assert_array_equal(big[::2, ::2], render_frame(state))


@pytest.mark.parametrize("kw", [{"window": 2}, {"window": 2, "agent": 5}, {"window": -1},
                                {"tile": 0}])
def test_bad_arguments_are_config_errors(kw):
    state = new_state(make_rules("easy"), 0)
    with pytest.raises(ConfigError):
        render_frame(state, **kw)

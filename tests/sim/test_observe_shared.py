"""Encoders of the same kitchen share their tables (built once, read-only), encoders of
other kitchens or sizes do not, and sharing changes no observation (the values are held
to a slow reference by ``test_observe.py`` and ``fast/test_observe_incremental.py``)."""

from __future__ import annotations

import gc
import weakref

import gymnasium as gym
import numpy as np
import pytest

import ocplus_plan.env  # noqa: F401  (registers the ids)
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.fast.batch import BatchSim
from ocplus_plan.sim.fast.observe_incremental import IncrementalEncoder
from ocplus_plan.sim.observe import VectorEncoder, _plane_tables, _window_tables


def _core(**kw):
    return gym.make("OvercookedPlus-v0", **kw).unwrapped.core


def test_two_envs_on_the_same_kitchen_share_the_same_table_objects():
    a, b = (_core(preset="hard", n_agents=2, obs_radius=2) for _ in range(2))
    assert a.vector is not b.vector
    for name in ("_gather", "_padded_ext", "_blank", "_pos_feat"):
        assert getattr(a.vector, name) is getattr(b.vector, name), name
    assert a._live._rows is b._live._rows and a._live._agent_put is b._live._agent_put


def test_shared_tables_are_read_only():
    enc = VectorEncoder(make_rules("hard", n_agents=2), obs_radius=2)
    live = IncrementalEncoder(enc)
    for table in (enc._gather, enc._padded_ext, enc._blank, live._rows):
        with pytest.raises(ValueError, match="read-only"):
            table[0] = 0


def test_kitchens_with_other_terrain_of_the_same_shape_share_only_the_window_tables():
    a = VectorEncoder(make_rules("easy", map="mapA", n_agents=2), obs_radius=2)
    b = VectorEncoder(make_rules("easy", map="mapB", n_agents=2), obs_radius=2)
    assert (a.rows, a.cols) == (b.rows, b.cols) and a.n_features == b.n_features
    assert a._padded_ext is not b._padded_ext and not np.array_equal(a._padded_ext,
                                                                      b._padded_ext)
    assert a._gather is b._gather  # the window indices depend on the map's shape only


@pytest.mark.parametrize("other", [dict(obs_radius=3), dict(obs_radius=0), dict(n_agents=3),
                                   dict(agent_communication=True)])
def test_other_sizes_do_not_share(other):
    kw = dict(preset="hard", n_agents=2, obs_radius=2)
    a, b = _core(**kw), _core(**(kw | other))
    assert a.vector._blank is not b.vector._blank
    assert a.vector._gather is not b.vector._gather or b.vector._gather is None
    assert a._live._agent_put is not b._live._agent_put


def test_shared_tables_equal_freshly_built_ones():
    rules = make_rules("hard", n_agents=3)
    enc = VectorEncoder(rules, obs_radius=2)
    fresh = _window_tables(enc.rows, enc.cols, 2, enc.n_features)
    np.testing.assert_array_equal(enc._gather, fresh["gather"])
    planes = _plane_tables(rules, 2, 3, enc.n_features)
    np.testing.assert_array_equal(enc._blank, planes["blank"])
    np.testing.assert_array_equal(enc._padded_ext, planes["padded_ext"])


def test_an_encoder_beside_others_encodes_as_one_built_alone():
    rules = make_rules("hard", n_agents=2, horizon=30)
    others = [VectorEncoder(make_rules(p, n_agents=2), obs_radius=2) for p in ("easy", "medium")]
    shared = [IncrementalEncoder(VectorEncoder(rules, obs_radius=2)) for _ in range(2)]
    state, rng = new_state(rules, 11), np.random.default_rng(2)
    for _ in range(40):
        first, second = (live.encode(state) for live in shared)
        np.testing.assert_array_equal(first, second)
        np.testing.assert_array_equal(first, shared[0].encoder.encode(state))
        transition(state, rng.integers(0, 5, 2).tolist())
    assert others[0]._gather is not shared[0].encoder._gather


def test_tables_go_when_their_last_encoder_goes():
    enc = VectorEncoder(make_rules("hard", n_agents=2), obs_radius=5)  # a size no one else uses
    table = weakref.ref(enc._window)
    del enc
    gc.collect()
    assert table() is None


def test_batches_of_the_same_kitchen_share_their_static_tables():
    rules = make_rules("hard", n_agents=2)
    for radius in (0, 2):
        a, b = (BatchSim(rules, 2, obs_radius=radius, compiled=False) for _ in range(2))
        assert a.static.static_obs is b.static.static_obs
        assert a.static.static_gather is b.static.static_gather

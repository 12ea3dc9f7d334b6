"""The vector encoder against a slow, obviously-correct reference, plus its promises:
bounds, unknown cells outside the map, no memory, batch = single, symbolic snapshots."""

from __future__ import annotations

import numpy as np
import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.sim import Item, ItemState, Where, make_rules, new_state, transition
from ocplus_plan.sim.observe import (
    GRID_CHANNELS,
    INGREDIENT_KINDS,
    ITEM_KINDS,
    ITEM_STATES,
    StateSnapshot,
    VectorEncoder,
    snapshot,
)

TERRAIN_NAME = {-1: "block", 0: "floor", 1: "counter", 2: "floor", 3: "tomato", 4: "lettuce",
                5: "plate", 6: "board", 7: "delivery", 8: "onion", 9: "pan", 10: "steak",
                11: "sink", 12: "trash"}


def reference(enc: VectorEncoder, state, received=None) -> np.ndarray:
    """Per agent: loop over window cells and items, fill channels by name."""
    rules, r = state.rules, enc.radius
    rows, cols = rules.layout.shape
    grid = state.grid
    n = state.n_agents
    out = np.zeros((n, enc.size), np.float32)
    ch = {name: i for i, name in enumerate(GRID_CHANNELS)}
    fi = {name: i for i, name in enumerate(enc.feature_names)}
    item_at: dict[tuple[int, int], list[int]] = {}
    for i in range(state.n_items):
        rc = state.item_cell(i)
        if rc is not None:
            item_at.setdefault(rc, []).append(i)
    for a in range(n):
        g = np.zeros(enc.grid_shape, np.float32)
        ar, ac = state.agent_rc(a)
        wh, ww = enc.window
        for y in range(wh):
            for x in range(ww):
                mr, mc = (ar - r + y, ac - r + x) if r else (y, x)
                if not (0 <= mr < rows and 0 <= mc < cols):
                    g[ch["unknown"], y, x] = 1
                    continue
                g[ch["terrain:" + TERRAIN_NAME[int(grid[mr, mc])]], y, x] = 1
                for i in item_at.get((mr, mc), []):
                    kind = Item(state.geo.item_kind[i])
                    g[ch["item:" + kind.name.lower()], y, x] += 1
                    g[ch["state:" + ITEM_STATES[state.item_state[i]].name.lower()], y, x] += 1
                    p = state.item_progress[i]
                    if p and state.item_where[i] != Where.PLATE:
                        den = (rules.burn_time + 1 if kind == Item.STEAK
                               else rules.wash_steps if kind == Item.PLATE else rules.chop_steps)
                        g[ch["progress"], y, x] = min(1.0, p / den)
                for b in range(n):
                    if state.agent_rc(b) == (mr, mc):
                        g[ch["agent:self" if b == a else "agent:other"], y, x] = 1
        f = np.zeros(enc.n_features, np.float32)
        held = state.agent_hand[a]
        if held >= 0:
            f[fi["hand:" + Item(state.geo.item_kind[held]).name.lower()]] = 1
            f[fi["hand_state:" + ITEM_STATES[state.item_state[held]].name.lower()]] = 1
            for i in state.plate_contents(held):
                f[fi["hand_plate:" + Item(state.geo.item_kind[i]).name.lower()]] += 1
        f[fi["row"]] = ar / (rows - 1)
        f[fi["col"]] = ac / (cols - 1)
        f[fi["time"]] = state.t / rules.horizon
        f[fi["layout"]] = state.layout_index
        if rules.dynamic:
            f[fi["switch_in"]] = min(1.0, max(0, state.next_switch - state.t) / rules.map_switch_step)
        for o, order in enumerate(state.orders):
            for k in order.recipe:
                f[fi[f"order{o}:{k.name.lower()}"]] += 1
            f[fi[f"order{o}:present"]] = 1
            if rules.order_time_limit and order.deadline >= 0:
                f[fi[f"order{o}:time_left"]] = min(
                    1.0, max(0, order.deadline - state.t) / rules.order_time_limit)
        if enc.comm_vocab:
            for k in range(n - 1):
                tok = -1 if received is None else received[a, k]
                f[fi[f"msg{k + 1}:" + (f"token{tok}" if tok >= 0 else "none")]] = 1
        out[a] = np.concatenate([g.reshape(-1), f])
    return out


def rollout_states(rules, seed: int, steps: int):
    """States along a random episode that also serves dishes now and then (greedy-free:
    random actions visit many item configurations on small maps)."""
    state = new_state(rules, seed)
    rng = np.random.default_rng(seed)
    out = [state.copy()]
    for _ in range(steps):
        transition(state, rng.integers(0, 5, size=rules.n_agents).tolist())
        out.append(state.copy())
        if state.done:
            break
    return out


@pytest.mark.parametrize("preset,n_agents,radius", [
    ("hard", 2, 0), ("hard", 2, 2), ("hard", 3, 1), ("medium", 1, 0), ("easy", 2, 3),
])
def test_encoder_matches_reference_along_random_episodes(preset, n_agents, radius):
    rules = make_rules(preset, n_agents=n_agents, order_time_limit=40)
    enc = VectorEncoder(rules, radius)
    for seed in range(2):
        for state in rollout_states(rules, seed, 200)[::3]:
            np.testing.assert_allclose(enc.encode(state), reference(enc, state), atol=1e-6)


def test_plate_contents_are_counted_on_the_plate_cell_and_in_the_hand():
    rules = make_rules("hard", n_agents=2)
    state = new_state(rules, 0)
    geo = state.geo
    plate = geo.item_kind.index(int(Item.PLATE))
    veg = [i for i, k in enumerate(geo.item_kind) if k in (int(Item.TOMATO), int(Item.LETTUCE))]
    for i in veg:  # put two chopped vegetables on the plate by hand (a legal configuration)
        state.cell_item[state.item_loc[i]] = -1
        state.item_state[i] = int(ItemState.CHOPPED)
        state.item_where[i], state.item_loc[i] = int(Where.PLATE), plate
    enc = VectorEncoder(rules, 0)
    np.testing.assert_allclose(enc.encode(state), reference(enc, state))
    # now agent 0 holds the plate
    state.cell_item[state.item_loc[plate]] = -1
    state.item_where[plate], state.item_loc[plate] = int(Where.HAND), 0
    state.agent_hand[0] = plate
    obs = enc.encode(state)
    np.testing.assert_allclose(obs, reference(enc, state))
    feats = dict(zip(enc.feature_names, obs[0, enc.grid_size:]))
    assert feats["hand:plate"] == 1 and feats["hand_state:clean"] == 1
    assert feats["hand_plate:tomato"] + feats["hand_plate:lettuce"] == 2


def test_cells_outside_the_map_are_unknown_and_nothing_is_remembered():
    rules = make_rules("hard", n_agents=2)
    enc = VectorEncoder(rules, 1)
    state = new_state(rules, 0)
    grid, _ = enc.split(enc.encode(state))
    unknown = GRID_CHANNELS.index("unknown")
    assert grid[0, unknown].sum() == 0  # agent 0 at (1, 7): its 3x3 window is inside the map
    # an item seen now is not seen once the agent walks away from it
    steak_ch = GRID_CHANNELS.index("item:steak")
    assert grid[0, steak_ch].sum() == 1  # the steak tile (1, 8) is next to agent 0
    for _ in range(3):
        transition(state, [2, 4])  # walk left
    grid, _ = enc.split(enc.encode(state))
    assert grid[0, steak_ch].sum() == 0


def test_window_at_the_border_reads_unknown_outside():
    rules = make_rules("easy", n_agents=1)
    enc = VectorEncoder(rules, 3)
    state = new_state(rules, 0)  # agent at (1, 1): two rows/cols beyond the top-left edge
    grid, _ = enc.split(enc.encode(state))
    unknown = grid[0, GRID_CHANNELS.index("unknown")]
    assert unknown[:2].all() and unknown[:, :2].all() and unknown[2:, 2:].sum() == 0
    assert grid[0, GRID_CHANNELS.index("agent:self"), 3, 3] == 1


def test_observations_respect_their_bounds_and_batch_equals_single():
    rules = make_rules("hard", n_agents=2)
    for radius in (0, 2):
        enc = VectorEncoder(rules, radius, comm_vocab=3)
        states = rollout_states(rules, 3, 120)[::7]
        rec = np.random.default_rng(0).integers(-1, 3, size=(len(states), 2, 1))
        many = enc.encode_many(states, rec)
        for k, s in enumerate(states):
            one = enc.encode(s, rec[k])
            np.testing.assert_array_equal(many[k], one)
            np.testing.assert_allclose(one, reference(enc, s, rec[k]), atol=1e-6)
        assert (many >= enc.low).all() and (many <= enc.high).all()


def test_feature_names_and_sizes():
    rules = make_rules("hard", n_agents=3)
    enc = VectorEncoder(rules, 2, comm_vocab=4)
    assert enc.grid_shape == (len(GRID_CHANNELS), 5, 5)
    assert enc.size == enc.grid_size + len(enc.feature_names)
    assert sum(name.startswith("msg") for name in enc.feature_names) == 2 * 5
    assert len(ITEM_KINDS) == 5 and len(INGREDIENT_KINDS) == 4


@pytest.mark.parametrize("bad", [-1, 1.5, True, "2"])
def test_bad_radius_is_a_config_error(bad):
    with pytest.raises(ConfigError, match="obs_radius"):
        VectorEncoder(make_rules("easy"), bad)


def test_snapshot_is_an_independent_copy_equal_by_value():
    rules = make_rules("hard", n_agents=2)
    state = new_state(rules, 5)
    snap = snapshot(state)
    assert isinstance(snap, StateSnapshot) and snap == state.copy()
    transition(state, [0, 0])
    assert snap != state and snap.t == 0
    assert snapshot(state) == snapshot(state) and hash(snapshot(state)) == hash(snapshot(state))

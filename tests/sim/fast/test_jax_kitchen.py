"""The JAX kitchen is the same kitchen as ``transition``: a differential property test steps
vmapped JAX kitchens and one reference state per kitchen with the same order draws and
actions, and compares the whole state, rewards, episode ends and every cook's observation
at every step (every preset, whole map and a window, resets, layout switches, burns,
expiries, fixed orders, shared rewards, kitchens of different layouts in one batch)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

from ocplus_plan.agents.greedy import GreedyAgent  # noqa: E402
from ocplus_plan.errors import ConfigError  # noqa: E402
from ocplus_plan.sim import make_rules, new_state, transition  # noqa: E402
from ocplus_plan.sim.codes import Where  # noqa: E402
from ocplus_plan.sim.fast import jax_kitchen as jk  # noqa: E402
from ocplus_plan.sim.fast.jax_observe import N_CHANNELS, observe  # noqa: E402
from ocplus_plan.sim.observe import VectorEncoder  # noqa: E402
from ocplus_plan.sim.orders import draw_order  # noqa: E402

# the numba engine's test draws the same rule variations (short processes and horizons)
from ocplus_plan.sim.processes import PROCESSES  # noqa: E402
from ocplus_plan.sim.rules import with_overrides  # noqa: E402
from ocplus_plan.sim.state import geometry_for  # noqa: E402
from tests.sim.fast.test_batch import QUICK, draw_overrides  # noqa: E402
from tests.sim.test_processes import KNEAD, MARINATE, ROAST, SEAR  # noqa: E402

MAX_ITEMS, MAX_RECIPES = 8, 12  # one padded shape for every preset: few compilations
BATCH = 4  # kitchens per compared batch (one batch size: one compilation per view)


class Draws:
    """Stands in for the reference's order generator: order number k gets the recipe the
    JAX kitchen draws for it (``order_draw``)."""

    def __init__(self, state, key, n_recipes: int) -> None:
        self.state = state
        ids = jax.numpy.arange(512)
        self.table = np.asarray(jax.vmap(lambda k: jk.order_draw(key, k, n_recipes))(ids))

    def integers(self, n: int) -> int:
        return int(self.table[self.state.next_order_id])


def reference_state(rules, key):
    """``new_state`` whose orders come from the JAX kitchen's draws for ``key``."""
    s = new_state(rules, 0)
    s.orders, s.next_order_id = [], 0
    s.rng = Draws(s, key, len(rules.recipes))
    for _ in range(rules.n_orders):
        draw_order(s)
    return s


def unpad(flat: int, cols: int) -> int:
    return (flat // jk.GRID) * cols + flat % jk.GRID


def as_reference(js, e: int, rules) -> dict:
    """Kitchen ``e`` of a batched JAX state, in the reference's indexing."""
    geo = geometry_for(rules)
    cols, n = geo.cols, len(geo.item_kind)
    pad = [jk.pad_cell(f, cols) for f in range(geo.rows * cols)]
    where = js.item_where[e][:n].tolist()
    loc = [unpad(v, cols) if w in (Where.CELL, Where.WAITING) else v
           for w, v in zip(where, js.item_loc[e][:n].tolist())]
    orders = list(zip(*(x[e].tolist() for x in (js.order_id, js.order_recipe,
                                                 js.order_created, js.order_deadline))))
    return dict(
        agent_pos=[unpad(v, cols) for v in js.pos[e].tolist()], agent_hand=js.hand[e].tolist(),
        cell_item=js.cell_item[e][pad].tolist(), item_state=js.item_state[e][:n].tolist(),
        item_progress=js.item_prog[e][:n].tolist(), item_where=where, item_loc=loc,
        item_agent=js.item_owner[e][:n].tolist(), t=int(js.t[e]), layout=int(js.layout[e]),
        next_switch=int(js.next_switch[e]), next_order_id=int(js.next_order_id[e]),
        orders=orders, stats=dict(zip(jk.STAT_NAMES, js.stats[e].tolist())))


def of_reference(s) -> dict:
    rules = s.rules
    return dict(
        agent_pos=s.agent_pos, agent_hand=s.agent_hand, cell_item=s.cell_item,
        item_state=s.item_state, item_progress=s.item_progress, item_where=s.item_where,
        item_loc=s.item_loc, item_agent=s.item_agent, t=s.t, layout=s.layout_index,
        next_switch=s.next_switch, next_order_id=s.next_order_id,
        orders=[(o.order_id, rules.recipes.index(o.recipe), o.created, o.deadline)
                for o in s.orders], stats=s.stats)


def crop(obs: np.ndarray, rules, radius: int, padded: bool) -> np.ndarray:
    """A padded whole-grid observation cut to the map's own cells (a window: as it is)."""
    if radius or not padded:
        return obs
    rows, cols = rules.layout.shape
    cells = jk.GRID * jk.GRID
    grid = obs[:, : N_CHANNELS * cells].reshape(-1, N_CHANNELS, jk.GRID, jk.GRID)
    return np.concatenate([grid[:, :, :rows, :cols].reshape(len(obs), -1),
                           obs[:, N_CHANNELS * cells:]], 1)


@jax.jit
def _step_and_observe(states, actions):
    out = jax.vmap(jk.step, (None, 0, 0))(None, states, actions)
    return out, jax.vmap(observe)(out.state)


@jax.jit
def _reset_and_observe(keys, params):
    s = jax.vmap(jk.reset)(keys, params)
    return s, jax.vmap(observe)(s)


def _set(batch, e: int, one):
    return jax.tree_util.tree_map(lambda b, o: b.at[e].set(o[e]), batch, one)


def compare(rules_list, radius: int, seed: int, steps: int, noise: float = 0.25,
            padded: bool = True) -> dict[str, int]:
    """Step one JAX kitchen per rule set (vmapped) and its reference side by side (greedy
    cooks, a share of random actions); assert equality at every step; returns the summed
    stats of the finished episodes."""
    rules_list = [rules_list[e % len(rules_list)] for e in range(BATCH)]
    n_envs = BATCH
    if padded:
        params = jk.stack_params([jk.kitchen_params(r, radius, max_items=MAX_ITEMS,
                                                    max_recipes=MAX_RECIPES, padded_view=True)
                                  for r in rules_list])
    else:
        params = jk.stack_params([jk.kitchen_params(r, radius) for r in rules_list])
    keys = jax.random.split(jax.random.PRNGKey(seed), n_envs)
    js, obs = _reset_and_observe(keys, params)
    refs = [reference_state(r, keys[e]) for e, r in enumerate(rules_list)]
    encs = [VectorEncoder(r, radius) for r in rules_list]
    cooks = [GreedyAgent(seed + e) for e in range(n_envs)]
    for e in range(n_envs):
        cooks[e].reset(refs[e])
    rng = np.random.default_rng(seed)
    totals: dict[str, int] = {}
    episode = 0
    for _ in range(steps):
        acts = np.array([cooks[e].act(refs[e]) for e in range(n_envs)])
        rand = rng.random(acts.shape) < noise
        acts[rand] = rng.integers(0, 5, size=int(rand.sum()))
        out, obs = _step_and_observe(js, acts)
        js, host, obs = out.state, jax.device_get(out), np.asarray(obs)
        for e in range(n_envs):
            res = transition(refs[e], acts[e].tolist())
            np.testing.assert_allclose(host.rewards[e], res.rewards, rtol=1e-5, atol=1e-4)
            assert (bool(host.terminated[e]), bool(host.truncated[e])) == (res.terminated,
                                                                           res.truncated)
            assert as_reference(host.state, e, rules_list[e]) == of_reference(refs[e])
            # XLA may divide by a loop-invariant divisor through its reciprocal: the
            # normalised features (time, position, progress) may differ in the last bit
            np.testing.assert_allclose(crop(obs[e], rules_list[e], radius, padded),
                                       encs[e].encode(refs[e]), rtol=3e-7, atol=0)
            if res.terminated or res.truncated:
                for k, v in refs[e].stats.items():
                    totals[k] = totals.get(k, 0) + v
                episode += 1
                new_keys = jax.random.split(jax.random.PRNGKey(seed + 1000 * episode), n_envs)
                fresh, _ = _reset_and_observe(new_keys, params)
                js = _set(js, e, fresh)
                refs[e] = reference_state(rules_list[e], new_keys[e])
                cooks[e].reset(refs[e])
                assert as_reference(jax.device_get(js), e, rules_list[e]) == \
                    of_reference(refs[e])
    return totals


@st.composite
def kitchens(draw, presets=("easy", "medium", "hard")):
    preset = draw(st.sampled_from(presets))
    overrides = draw_overrides(draw, preset)
    radius = draw(st.sampled_from([0, 2]))
    # two cooks everywhere (one compilation per view; one cook: test_jax_env.py)
    return make_rules(preset, n_agents=2, **overrides), radius, draw(st.integers(0, 99))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kitchens())
def test_jax_kitchen_is_the_same_kitchen_as_transition(kitchen):
    rules, radius, seed = kitchen
    compare([rules], radius, seed, steps=30)


def test_a_one_cook_kitchen_is_the_same_kitchen_too():
    rules = make_rules("medium", n_agents=1, **dict(QUICK, horizon=20, order_time_limit=8))
    compare([rules], 2, 5, steps=45)


def test_the_differential_run_reaches_every_rule():
    """Not vacuous: these cooks deliver, chop, cook, burn, wash, switch layouts and let
    orders expire; the whole-map view here is the map's own shape, as the reference's."""
    rules = make_rules("hard", **dict(QUICK, horizon=100, order_time_limit=45, burn_time=4))
    totals = compare([rules], 0, 1, steps=200, noise=0.1, padded=False)
    seen = {k for k, v in totals.items() if v}
    assert {"dishes_served", "washes", "chops", "cooks", "burns", "layout_switches",
            "orders_expired"} <= seen, totals


def test_other_process_records_step_the_same_as_transition():
    """The JAX kitchen gathers the records' tables: kitchens with other records (a board
    kneaded by bumps of another verb, a pan with other times; a time-driven board that
    spoils, a bump-driven pan) next to the shipped records, in one batch."""
    hard = make_rules("hard", **dict(QUICK, horizon=40))
    wash = PROCESSES[2]
    kitchens = [with_overrides(hard, processes=(KNEAD, ROAST, wash)), hard,
                with_overrides(hard, processes=(MARINATE, SEAR, wash))]
    totals = compare(kitchens, 0, 3, steps=80, noise=0.2)
    assert totals["chops"] and totals["cooks"] and totals["burns"], totals


def test_one_compiled_step_serves_kitchens_of_different_layouts():
    quick = dict(QUICK, horizon=25)
    layouts = [make_rules("easy", n_agents=2, **quick), make_rules("medium", n_agents=2, **quick),
               make_rules("hard", **quick), make_rules("easy", map="trio_kitchen", n_agents=2,
                                                       **quick)]
    stacked = jk.params_for_many(layouts, 2)
    assert stacked.terrain.shape == (4, 2, jk.CELLS)
    assert {r.layout.shape for r in layouts} == {(5, 7), (7, 7), (9, 9), (8, 10)}
    totals = compare(layouts, 2, 3, steps=60, noise=0.2)
    assert totals["chops"] > 0, totals


def test_a_map_larger_than_the_grid_is_refused_with_the_fix():
    from ocplus_plan.sim.maps import load_map

    easy = load_map("easy_open")  # 5x7; widened with walls to 5x13
    wide = [[int(v) for v in row] + [-1] * 6 for row in easy.grid]
    layout = load_map({"name": "wide", "game_map": wide, "max_n_agent": 2,
                       "agent_spawn_points": [list(p) for p in easy.spawn_points]})
    with pytest.raises(ConfigError, match="pads maps to 12x12"):
        jk.kitchen_params(make_rules("easy", map=layout))


def test_kitchens_of_different_cook_counts_cannot_share_a_batch():
    with pytest.raises(ConfigError, match="n_agents"):
        jk.params_for_many([make_rules("easy"), make_rules("hard")])

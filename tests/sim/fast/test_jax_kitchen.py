"""The JAX kitchen is the same kitchen as ``transition``: a differential property test steps
vmapped JAX kitchens and one reference state per kitchen with the same order draws and
actions, and compares the whole state, rewards, episode ends and every cook's observation
at every step (every preset, whole map and a window, resets, layout switches, burns,
expiries, fixed orders, shared rewards, kitchens of different layouts in one batch, generated
kitchens with drawn process records and menus), through the shared harness
``eval.mirrors.check_mirror``."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

from ocplus_plan.errors import ConfigError  # noqa: E402
from ocplus_plan.eval.mirrors import check_mirror, random_kitchens  # noqa: E402
from ocplus_plan.sim import make_rules  # noqa: E402
from ocplus_plan.sim.fast import jax_kitchen as jk  # noqa: E402
from ocplus_plan.sim.processes import PROCESSES  # noqa: E402
from ocplus_plan.sim.rules import with_overrides  # noqa: E402

# the numba engine's test draws the same rule variations (short processes and horizons)
from tests.sim.fast.test_batch import QUICK, draw_overrides  # noqa: E402
from tests.sim.test_processes import KNEAD, MARINATE, ROAST, SEAR  # noqa: E402

#: one batch of 4 kitchens of one padded shape for every preset (few compilations)
JAX = dict(batch=4, max_items=8, max_recipes=12)


@st.composite
def kitchens(draw, presets=("easy", "medium", "hard")):
    preset = draw(st.sampled_from(presets))
    overrides = draw_overrides(draw, preset)
    radius = draw(st.sampled_from([0, 2]))
    # two cooks everywhere (one compilation per view; one cook: test_jax_env.py)
    if draw(st.booleans()):  # a generated kitchen with drawn process records and menu
        rules = random_kitchens(draw(st.integers(0, 2**20)), 1, presets=(preset,),
                                **overrides)[0]
    else:
        rules = make_rules(preset, n_agents=2, **overrides)
    return rules, radius, draw(st.integers(0, 99))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kitchens())
def test_jax_kitchen_is_the_same_kitchen_as_transition(kitchen):
    rules, radius, seed = kitchen
    check_mirror("jax", [rules], steps=30, seed=seed, radius=radius, **JAX)


def test_a_one_cook_kitchen_is_the_same_kitchen_too():
    rules = make_rules("medium", n_agents=1, **dict(QUICK, horizon=20, order_time_limit=8))
    check_mirror("jax", [rules], steps=45, seed=5, radius=2, **JAX)


def test_the_differential_run_reaches_every_rule():
    """Not vacuous: these cooks deliver, chop, cook, burn, wash, switch layouts and let
    orders expire; the whole-map view here is the map's own shape, as the reference's."""
    rules = make_rules("hard", **dict(QUICK, horizon=100, order_time_limit=45, burn_time=4))
    totals = check_mirror("jax", [rules], steps=200, seed=1, noise=0.1, padded=False, **JAX)
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
    totals = check_mirror("jax", kitchens, steps=80, seed=3, noise=0.2, **JAX)
    assert totals["chops"] and totals["cooks"] and totals["burns"], totals


def test_one_compiled_step_serves_kitchens_of_different_layouts():
    quick = dict(QUICK, horizon=25)
    layouts = [make_rules("easy", n_agents=2, **quick), make_rules("medium", n_agents=2, **quick),
               make_rules("hard", **quick), make_rules("easy", map="trio_kitchen", n_agents=2,
                                                       **quick)]
    stacked = jk.params_for_many(layouts, 2)
    assert stacked.terrain.shape == (4, 2, jk.CELLS)
    assert {r.layout.shape for r in layouts} == {(5, 7), (7, 7), (9, 9), (8, 10)}
    totals = check_mirror("jax", layouts, steps=60, seed=3, radius=2, noise=0.2, **JAX)
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

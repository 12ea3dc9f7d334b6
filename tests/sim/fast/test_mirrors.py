"""The shared mirror harness (``eval.mirrors``) on generated kitchens: every mirror steps
``gen:`` kitchens, with the shipped and with other process records, and drawn kitchens with
drawn records and menus of their own rewards, as the reference does; a mirror that
disagrees is caught and named."""

from __future__ import annotations

import pytest

from ocplus_plan.errors import ConfigError
from ocplus_plan.eval.mirrors import MirrorMismatch, check_mirror, kitchens, random_kitchens
from ocplus_plan.sim.fast import kernels
from ocplus_plan.sim.fast.batch import numba_available
from ocplus_plan.sim.processes import PROCESSES
from ocplus_plan.sim.rules import with_overrides
from tests.sim.test_oven_kitchen import OVEN_MAP
from tests.sim.test_processes import KNEAD, ROAST

GEN = ("gen:open:train:0", "gen:split:train:1", "gen:open:test:2")
QUICK = dict(chop_steps=2, cook_time=3, burn_time=6, wash_steps=2, horizon=25)


def generated(records: bool = False):
    rules = kitchens(GEN, "medium", n_agents=2, **QUICK)
    if records:
        rules = [with_overrides(r, processes=(KNEAD, ROAST, PROCESSES[2])) for r in rules]
    return rules


@pytest.mark.parametrize("mirror", [
    pytest.param("numba", marks=pytest.mark.skipif(not numba_available(),
                                                   reason="numba is not installed")),
    "kernels"])
def test_the_batch_engine_steps_generated_kitchens_as_the_reference(mirror):
    totals = check_mirror(mirror, generated() + generated(records=True), steps=40, seed=5)
    assert totals["chops"] and totals["cooks"], totals


def test_the_jax_kitchen_steps_generated_kitchens_as_the_reference():
    pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")
    oven = kitchens([OVEN_MAP], "medium", n_agents=2, horizon=25)  # an added station
    totals = check_mirror("jax", generated()[:2] + generated(records=True)[:2] + oven,
                          steps=30, seed=5)
    assert totals["chops"], totals


def test_a_mirror_that_disagrees_is_caught_at_its_first_step(monkeypatch):
    def tick(e, it, j, items, stats, rewards, subtasks, proc, rw):  # the pan never heats
        return None

    monkeypatch.setattr(kernels, "tick", tick)
    message = r"kitchen 'gen:open:train:0' \(medium\), step \d+: the state"
    with pytest.raises(MirrorMismatch, match=message):
        check_mirror("kernels", generated()[:1], steps=40, seed=5, noise=0.0)


def test_an_unknown_mirror_is_refused_naming_the_mirrors():
    with pytest.raises(ConfigError, match="numba, kernels, jax"):
        check_mirror("cuda", generated()[:1])


def test_drawn_kitchens_carry_drawn_records_and_menus_and_are_seeded():
    a, b = random_kitchens(0, 4), random_kitchens(0, 4)
    assert [r.layout.name for r in a] == [r.layout.name for r in b]
    assert all(r.layout.name.startswith("gen:") and r.layout.recipes for r in a)
    assert {r.recipes for r in a} == {r.recipes for r in b}
    assert any(p.drive == "time" and p.verb == "chop" for r in a for p in r.processes)
    assert len({v for r in a for v in r.recipe_rewards}) > 2  # the dishes' own rewards


@pytest.mark.parametrize("mirror", [
    pytest.param("numba", marks=pytest.mark.skipif(not numba_available(),
                                                   reason="numba is not installed")),
    "features-kernels"])
def test_the_mirrors_serve_drawn_dishes_as_the_reference(mirror):
    """Not vacuous: the cooks serve dishes of drawn menus, paid their own rewards (the
    harness compares every reward)."""
    rules = random_kitchens(1, 4, horizon=60)
    totals = check_mirror(mirror, rules, steps=61, seed=1, noise=0.1)
    if mirror == "numba":
        assert totals["dishes_served"] and totals["chops"], totals
    else:
        assert totals["shaped"] > 0, totals

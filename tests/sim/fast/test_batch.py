"""The batched engine is the same kitchen as ``transition``: a differential property test
steps a batch and one reference state per kitchen with the same seeds and actions and
compares state hashes, observations, rewards and episode ends at every step (every
preset, radius 0 and a window, resets, layout switches, expiries, fixed orders, shared
rewards; the presets' kitchens and generated ones with drawn process records and menus),
on the compiled kernels (``fast`` extra) and on the plain-Python ones, through the shared
harness ``eval.mirrors.check_mirror``."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocplus_plan.errors import ConfigError, DependencyNotInstalled, InvalidActionError
from ocplus_plan.eval.mirrors import check_mirror, random_kitchens
from ocplus_plan.sim import make_rules, new_state, transition
from ocplus_plan.sim.fast.batch import BatchSim, compile_kernels, kernels, numba_available
from ocplus_plan.sim.observe import VectorEncoder
from ocplus_plan.sim.processes import PROCESSES
from ocplus_plan.sim.rules import with_overrides
from tests.sim.test_processes import KNEAD, MARINATE, ROAST, SEAR

needs_numba = pytest.mark.skipif(not numba_available(),
                                 reason="numba is not installed (the 'fast' extra)")

# short processes, switches and horizons so that a few dozen steps see every rule
QUICK = dict(chop_steps=2, cook_time=3, burn_time=6, wash_steps=2, map_switch_step=4)


def draw_overrides(draw, preset: str) -> dict:
    """Short processes, and a drawn horizon, expiry, reward mode, fixed orders and early stop:
    the rule variations every differential test of a mirror draws from."""
    overrides = dict(QUICK, horizon=draw(st.integers(8, 40)))
    if draw(st.booleans()):
        overrides["order_time_limit"] = draw(st.integers(2, 12))
    if draw(st.booleans()):
        overrides["reward_mode"] = "shared"
    if draw(st.booleans()):
        overrides["fixed_orders"] = True
    if preset == "hard" and draw(st.booleans()):
        overrides["stop_after_orders"] = 1
    return overrides


@st.composite
def kitchens(draw, presets=("easy", "medium", "hard")):
    preset = draw(st.sampled_from(presets))
    overrides = draw_overrides(draw, preset)
    n_agents = draw(st.integers(1, 2)) if preset != "hard" else 2
    radius = draw(st.sampled_from([0, 2]))
    if draw(st.booleans()):  # a generated kitchen with drawn process records and menu
        rules = random_kitchens(draw(st.integers(0, 2**20)), 1, presets=(preset,),
                                n_agents=n_agents, **overrides)[0]
    else:
        rules = make_rules(preset, n_agents=n_agents, **overrides)
    return rules, radius, draw(st.integers(0, 99))

#: the batch engine's mirror: compiled when numba is installed, else its plain kernels
ENGINE = "numba" if numba_available() else "kernels"


@needs_numba
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kitchens())
def test_compiled_batch_is_the_same_kitchen_as_transition(kitchen):
    rules, radius, seed = kitchen
    check_mirror("numba", [rules], steps=45, seed=seed, radius=radius, n_envs=3)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kitchens())
def test_plain_python_batch_is_the_same_kitchen_as_transition(kitchen):
    rules, radius, seed = kitchen
    check_mirror("kernels", [rules], steps=30, seed=seed, radius=radius, n_envs=2)


def test_the_differential_run_reaches_every_rule():
    """The property tests are not vacuous: these cooks deliver, chop, cook, burn, wash,
    switch layouts and let orders expire (compiled when available)."""
    rules = make_rules("hard", **dict(QUICK, horizon=100, order_time_limit=45, burn_time=4))
    totals = check_mirror(ENGINE, [rules], steps=200, seed=1, n_envs=4, noise=0.1)
    seen = {k for k, v in totals.items() if v}
    assert {"dishes_served", "washes", "chops", "cooks", "burns", "layout_switches",
            "orders_expired"} <= seen, totals


@pytest.mark.parametrize("mirror", [pytest.param("numba", marks=needs_numba), "kernels"])
def test_other_process_records_step_the_same_as_transition(mirror):
    """The kernels index the records' tables: a board kneaded by bumps of another verb and
    a pan with other times, then a time-driven board that spoils (marinate) and a
    bump-driven pan (sear), run as in the reference step."""
    hard = make_rules("hard", **dict(QUICK, horizon=40))
    totals = check_mirror(mirror, [with_overrides(hard, processes=(KNEAD, ROAST, PROCESSES[2]))],
                          steps=80, seed=3, n_envs=3, noise=0.2)
    assert totals["chops"] and totals["cooks"] and totals["burns"], totals
    totals = check_mirror(mirror, [with_overrides(hard, processes=(MARINATE, SEAR, PROCESSES[2]))],
                          steps=80, seed=4, n_envs=3, noise=0.3)
    assert totals["chops"] and totals["burns"], totals


@pytest.mark.parametrize("compiled", [pytest.param(True, marks=needs_numba), False])
def test_a_loaded_state_goes_on_as_in_transition(compiled):
    """A kitchen can start from any state: here a cook holding an empty plate by the
    serving window, which is refused (the wrong delivery the greedy cooks never make)."""
    rules = make_rules("hard")
    state = new_state(rules, 7)
    plate = state.geo.item_kind.index(5)
    state.cell_item[state.item_loc[plate]] = -1
    state.agent_hand[0], state.item_where[plate], state.item_loc[plate] = plate, 1, 0
    state.agent_pos[0] = state.geo.flat(4, 1)  # mapC's delivery is at (4, 0)
    sim = BatchSim(rules, 2, compiled=compiled)
    sim.reset()
    sim.load(1, state)
    enc = VectorEncoder(rules)
    np.testing.assert_array_equal(sim.obs[1], enc.encode(state))
    for joint in ([2, 4], [1, 2], [3, 3]):
        out = sim.step(np.array([[4, 4], joint]))
        res = transition(state, joint)
        assert sim.state(1).state_hash() == state.state_hash()
        assert sim.arrays.rewards[1].tolist() == res.rewards
        np.testing.assert_array_equal(out.obs[1], enc.encode(state))
    assert state.stats["wrong_deliveries"] == 1
    with pytest.raises(ConfigError, match="other rules"):
        sim.load(0, new_state(make_rules("easy"), 0))


def test_batch_is_reproducible_from_its_seed_and_kitchens_differ():
    rules = make_rules("easy", n_agents=2)
    a, b = BatchSim(rules, 3, seed=1, compiled=False), BatchSim(rules, 3, seed=1, compiled=False)
    np.testing.assert_array_equal(a.reset(), b.reset())
    assert a.seeds == b.seeds and len(set(a.seeds)) == 3


def test_batch_checks_its_input():
    rules = make_rules("easy", n_agents=2)
    sim = BatchSim(rules, 2, compiled=False)
    with pytest.raises(ConfigError, match="reset"):
        sim.step(np.zeros((2, 2), int))
    sim.reset()
    with pytest.raises(InvalidActionError, match="shape"):
        sim.step(np.zeros((3, 2), int))
    with pytest.raises(InvalidActionError, match="kitchen 1, agent 0: action 7"):
        sim.step(np.array([[0, 0], [7, 0]]))
    with pytest.raises(ConfigError, match="n_envs"):
        BatchSim(rules, 0)


def test_compiled_kernels_without_numba_name_the_extra(monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_numba(name, *args, **kwargs):
        if name == "numba":
            raise ImportError("no numba here")
        return real_import(name, *args, **kwargs)

    compile_kernels.cache_clear()
    monkeypatch.setattr(builtins, "__import__", no_numba)
    try:
        with pytest.raises(DependencyNotInstalled, match=r"ocplus-plan\[fast\]"):
            kernels(True)
    finally:
        monkeypatch.undo()
        compile_kernels.cache_clear()


def test_memory_per_kitchen_is_reported_and_a_window_is_smaller():
    rules = make_rules("hard")
    whole, window = BatchSim(rules, 4, compiled=False), BatchSim(rules, 4, obs_radius=2,
                                                                  compiled=False)
    obs_bytes = 2 * window.encoder.size * 4
    assert obs_bytes < window.memory_per_kitchen() < whole.memory_per_kitchen()


@needs_numba
def test_threads_step_disjoint_kitchens_to_the_same_result():
    rules = make_rules("hard", **QUICK)
    one, two = (BatchSim(rules, 300, seed=4, compiled=True, threads=t) for t in (1, 2))
    one.reset()
    two.reset()
    rng = np.random.default_rng(0)
    for _ in range(40):
        acts = rng.integers(0, 5, size=(300, 2))
        a, b = one.step(acts), two.step(acts)
        np.testing.assert_array_equal(a.obs, b.obs)
    assert [one.state(e).state_hash() for e in (0, 150, 299)] == \
        [two.state(e).state_hash() for e in (0, 150, 299)]
    two.close()
    assert two._pool is None


def test_without_observations_the_kitchens_step_the_same_in_less_memory():
    rules = make_rules("hard", **QUICK)
    seen, blind = (BatchSim(rules, 3, seed=2, compiled=False, observe=o) for o in (True, False))
    seen.reset()
    blind.reset()
    rng = np.random.default_rng(0)
    for _ in range(12):
        acts = rng.integers(0, 5, size=(3, 2))
        seen.step(acts)
        blind.step(acts)
    assert blind.obs.size == 0 and blind.memory_per_kitchen() < 1024
    assert [s.state(e).state_hash() for s in (seen, blind) for e in range(3)] == \
        [seen.state(e).state_hash() for _ in range(2) for e in range(3)]

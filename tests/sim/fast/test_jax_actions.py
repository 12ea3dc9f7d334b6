"""The JAX kitchen refuses non-integer actions when traced, and its checked mode refuses
integers outside 0..4 (which the jitted step, unchecked, plays as stay: documented)."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

import ocplus_plan  # noqa: E402
from ocplus_plan.errors import InvalidActionError  # noqa: E402
from ocplus_plan.sim.fast import jax_kitchen as jk  # noqa: E402


@pytest.fixture(scope="module")
def envs():
    plain = ocplus_plan.make_jax_env("easy", n_agents=2)
    checked = ocplus_plan.make_jax_env("easy", n_agents=2, checked=True)
    _, state = plain.reset(jax.random.PRNGKey(0))
    return plain, checked, state


@pytest.mark.parametrize("bad", [(1.7, 0), (float("nan"), 0), (True, False)])
def test_a_float_or_bool_action_is_refused_under_jit(envs, bad):
    plain, _, state = envs
    with pytest.raises(InvalidActionError, match="integers"):
        plain.step(jax.random.PRNGKey(1), state, {"agent_0": bad[0], "agent_1": bad[1]})


@pytest.mark.parametrize("bad", [5, 6, 7, -1, 2**31 - 1])
def test_out_of_range_acts_as_stay_unchecked_and_is_refused_checked(envs, bad):
    plain, checked, state = envs
    key = jax.random.PRNGKey(1)
    moved = plain.step(key, state, {"agent_0": bad, "agent_1": 0})  # one compiled step
    stayed = plain.step(key, state, {"agent_0": 4, "agent_1": 0})
    assert all(np.array_equal(a, b) for a, b in zip(jax.tree_util.tree_leaves(moved),
                                                     jax.tree_util.tree_leaves(stayed)))
    with pytest.raises(InvalidActionError, match=f"agent_0: action {bad} is out of range"):
        checked.step(key, state, {"agent_0": bad, "agent_1": 0})  # refused on the host
    with pytest.raises(InvalidActionError, match="out of range"):
        checked.step_env(key, state, {"agent_0": bad, "agent_1": 0})


def test_checked_mode_passes_good_actions_through(envs):
    _, checked, _ = envs
    checked._check({"agent_0": 1, "agent_1": np.int32(4)})  # the host check alone
    assert checked.step == checked._checked_step and checked.checked


def test_check_actions_on_batches():
    assert jk.check_actions(np.zeros((8, 2), np.int32), 2).shape == (8, 2)
    with pytest.raises(InvalidActionError, match="expected 2"):
        jk.check_actions(np.zeros((8, 3), np.int32), 2)
    with pytest.raises(InvalidActionError, match="dtype float"):
        jk.check_actions(np.array([0.5, 1.0]))

"""The JAX trainer's potential-based shaping: a loop earns nothing, each stage of a dish
pays as it is reached, an episode's discounted shaping does not depend on the actions; the
separate critic and the desynchronised clocks."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

import jax.numpy as jnp  # noqa: E402

import ocplus_plan  # noqa: E402
from ocplus_plan.rl.fast.jax_ppo import desync, forward, init_params, save_npz  # noqa: E402
from ocplus_plan.rl.fast.jax_shaping import potential, shaping_step, tables  # noqa: E402

R, D, L, U, STAY = 0, 1, 2, 3, 4
# easy_open, one cook from (1,1): the onion lies at (4,4), a board at (3,6), the plate at
# (2,0), the serving window at (4,2)
TO_ONION = [D, D, R, R, R]
PICK, PUT = D, D
G = 0.99  # the learner's discount


def discounted(f):
    return float(sum(x * G ** t for t, x in enumerate(f)))


def play(env, actions):
    """Per step: (shaping F, the rules' reward) of ``actions`` from the first state."""
    near = jax.tree_util.tree_map(jnp.asarray, tables(env.params))

    @jax.jit
    def one(state, a):
        _, after, rew, done, _ = env.step_env(jax.random.PRNGKey(0), state,
                                              {"agent_0": jnp.int32(a)})
        return after, (shaping_step(env, state, after, done["__all__"], near, G),
                       rew["agent_0"])

    _, state = env.reset(jax.random.PRNGKey(0))
    out = []
    for a in actions:
        state, (f, r) = one(state, a)
        out.append((float(f), float(r)))
    return out


@pytest.fixture(scope="module")
def onion_env():
    return ocplus_plan.make_jax_env("easy", n_agents=1, recipes=[["onion"]], horizon=40)


def test_picking_up_and_putting_back_an_onion_earns_0_in_total(onion_env):
    """0 beyond what standing still earns, as the learner counts it (discounted)."""
    steps = play(onion_env, TO_ONION + [PICK, PUT, PICK, PUT])
    waits = play(onion_env, TO_ONION + [STAY] * 4)
    pick, put = steps[5][0], steps[6][0]
    assert pick > 0  # an order needs onions: holding one is a step towards a dish
    assert put < 0
    loop = [f for f, _ in steps[5:]]
    assert discounted(loop) == pytest.approx(discounted([f for f, _ in waits[5:]]), abs=1e-5)
    assert discounted(loop[:2]) == pytest.approx(discounted([f for f, _ in waits[5:7]]),
                                                 abs=1e-5)
    assert sum(loop) <= 0


def test_each_stage_of_an_onion_dish_pays_and_serving_it_pays_the_rest(onion_env):
    route = (TO_ONION + [PICK, R, R, R, R, R]  # to (3,5), put it on the board, chop x3
             + [L, L, L, L, U, L]  # to (2,1), take the plate
             + [D, R, R, R, R, R]  # to (3,5), the onion onto the plate
             + [L, L, L, D])  # to (3,2), serve
    steps = play(onion_env, route)
    f = [s[0] for s in steps]
    assert f[5] > 0 and f[7] > 0  # picked, put on the board
    assert all(x > 0 for x in f[8:11])  # each chop
    assert f[16] > 0 and f[22] > 0  # the plate taken, the onion on it
    assert all(x > 0 for x in f[23:26])  # carrying the dish towards the window
    served_f, served_r = steps[26]
    assert served_r > 190  # the dish's reward
    assert served_f < 0 and served_r + served_f > 0  # the potential is given back


def test_an_onion_no_order_needs_costs_to_hold(onion_env):
    env = ocplus_plan.make_jax_env("easy", n_agents=1, recipes=[["tomato"]], horizon=40)
    steps = play(env, TO_ONION + [PICK, PUT])
    waits = play(env, TO_ONION + [STAY, STAY])
    assert steps[5][0] < 0
    assert discounted([steps[5][0], steps[6][0]]) == pytest.approx(
        discounted([waits[5][0], waits[6][0]]), abs=1e-5)


def test_an_episodes_discounted_shaping_is_the_same_whatever_the_actions():
    env = ocplus_plan.make_jax_env("medium", n_agents=2, horizon=25)
    near = jax.tree_util.tree_map(jnp.asarray, tables(env.params))

    @jax.jit
    def episode(key):
        _, state = env.reset(key)

        def one(carry, k):
            state = carry
            acts = jax.random.randint(k, (2,), 0, 5)
            _, after, _, done, _ = env.step(k, state, {"agent_0": acts[0], "agent_1": acts[1]})
            return after, (shaping_step(env, state, after, done["__all__"], near, G),
                           done["__all__"], potential(env.kitchen_state(state), near))

        return jax.lax.scan(one, state, jax.random.split(key, 50))[1]

    for seed in range(3):
        f, done, phi = (np.asarray(x) for x in episode(jax.random.PRNGKey(seed)))
        ends = np.flatnonzero(done)
        assert list(ends) == [24, 49]
        # -phi(first state): the same for every policy (the cooks' distances to what they
        # fetch first; the items start on their spawn tiles)
        assert discounted(f[:25]) == pytest.approx(-phi[0], abs=1e-3)
        assert discounted(f[25:]) == pytest.approx(-phi[25], abs=1e-3)
        assert np.abs(f).max() > 0  # random cooks do move things


def test_desynchronised_kitchens_start_at_different_steps():
    env = ocplus_plan.make_jax_env("easy", n_agents=1, horizon=50)
    _, state = jax.vmap(env.reset)(jax.random.split(jax.random.PRNGKey(0), 16))
    obs, state = desync(env, state, jax.random.PRNGKey(1))
    t = np.asarray(state.t)
    assert t.min() >= 0 and t.max() < 50 and len(set(t.tolist())) > 8
    assert np.allclose(np.asarray(obs["agent_0"]), np.asarray(jax.vmap(env.get_obs)(state)
                                                               ["agent_0"]))


def test_the_critic_is_its_own_network_and_the_saved_policy_is_the_actor(tmp_path):
    params = init_params(jax.random.PRNGKey(0), 7, 8, critic=True)
    x = jnp.ones((3, 7))
    logits, value = forward(params, x)
    moved = params | {"c2": params["c2"] + 1.0}
    logits2, value2 = forward(moved, x)
    np.testing.assert_array_equal(np.asarray(logits), np.asarray(logits2))
    np.testing.assert_allclose(np.asarray(value2), np.asarray(value) + 1.0, rtol=1e-6)
    save_npz(str(tmp_path / "policy.npz"), params)
    assert set(np.load(tmp_path / "policy.npz")) == {"w0", "b0", "w1", "b1", "w2", "b2"}


def test_the_subtask_payment_is_annealed_to_0_over_its_fraction_of_the_run():
    from ocplus_plan.rl.fast.jax_ppo import PPOConfig, subtask_weight

    config = PPOConfig(n_updates=100, subtask_anneal=0.5)
    weights = [float(subtask_weight(config, u)) for u in (0, 25, 50, 99)]
    assert weights == pytest.approx([1.0, 0.5, 0.0, 0.0])
    assert float(subtask_weight(config._replace(subtask_reward=True), 99)) == 1.0
    assert float(subtask_weight(config._replace(subtask_anneal=0.0), 0)) == 0.0

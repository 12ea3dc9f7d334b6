"""The JAX trainer's order curriculum: the recipes served least are drawn more, uniform
when every recipe is served alike; a step's served and new orders are counted per recipe;
only new orders are redrawn, fixed orders never; and the shaping potential is the same for
the same progress on either order."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")

import jax.numpy as jnp  # noqa: E402

import ocplus_plan  # noqa: E402
from ocplus_plan.rl.fast import jax_orders  # noqa: E402
from ocplus_plan.rl.fast.jax_ppo import PPOConfig, train_to_folder  # noqa: E402
from ocplus_plan.rl.fast.jax_shaping import potential, tables  # noqa: E402

TOMATO, LETTUCE, ONION = 0, 1, 2  # easy's recipes, in order


def test_the_draw_leans_to_the_recipe_served_least():
    served, drawn = jnp.array([5.0, 5.0, 0.0, 0.0]), jnp.array([5.0, 5.0, 5.0, 0.0])
    p = np.asarray(jax_orders.draw_probs(served, drawn, 3, 0.5))
    np.testing.assert_allclose(p, [1 / 6, 1 / 6, 1 / 6 + 0.5, 0.0], atol=1e-6)
    assert p.sum() == pytest.approx(1.0)


def test_the_draw_is_uniform_when_every_recipe_is_served_alike_or_none_is():
    for served in ([3.0, 3.0, 3.0], [0.0, 0.0, 0.0]):
        p = jax_orders.draw_probs(jnp.array(served), jnp.array([6.0, 6.0, 6.0]), 3, 1.0)
        np.testing.assert_allclose(np.asarray(p), [1 / 3] * 3, atol=1e-6)
    p = jax_orders.draw_probs(jnp.array([4.0, 0.0, 0.0]), jnp.array([4.0, 4.0, 4.0]), 3, 0.0)
    np.testing.assert_allclose(np.asarray(p), [1 / 3] * 3, atol=1e-6)


@pytest.fixture(scope="module")
def easy():
    env = ocplus_plan.make_jax_env("easy", n_agents=1)
    return env, env.reset(jax.random.PRNGKey(0))[1]


def test_a_served_order_and_its_replacement_are_counted_per_recipe(easy):
    env, s = easy
    before = s._replace(order_id=jnp.array([0, 1]), order_recipe=jnp.array([ONION, TOMATO]))
    after = s._replace(order_id=jnp.array([1, 2]), order_recipe=jnp.array([TOMATO, LETTUCE]))
    served, drawn = jax_orders.served_and_drawn(before, after, jnp.bool_(False), 3)
    assert served.tolist() == [0, 0, 1] and drawn.tolist() == [0, 1, 0]
    served, drawn = jax_orders.served_and_drawn(before, before, jnp.bool_(False), 3)
    assert served.tolist() == [0, 0, 0] and drawn.tolist() == [0, 0, 0]
    # an episode that restarts serves nothing and opens all its orders
    served, drawn = jax_orders.served_and_drawn(before, after, jnp.bool_(True), 3)
    assert served.tolist() == [0, 0, 0] and drawn.tolist() == [1, 1, 0]


def test_only_new_orders_are_redrawn_and_fixed_orders_never(easy):
    env, s = easy
    s = s._replace(order_recipe=jnp.array([TOMATO, TOMATO]))
    only_onion = jnp.array([0.0, 0.0, 1.0])
    new = jnp.array([False, True])
    out = jax_orders.redraw(jax.random.PRNGKey(1), s, new, only_onion, env.params)
    assert np.asarray(out.order_recipe).tolist() == [TOMATO, ONION]
    fixed = ocplus_plan.make_jax_env("easy", n_agents=1, fixed_orders=[["tomato"]])
    out = jax_orders.redraw(jax.random.PRNGKey(1), s, new, only_onion, fixed.params)
    assert np.asarray(out.order_recipe).tolist() == [TOMATO, TOMATO]


def test_the_potential_is_the_same_for_equal_progress_on_either_order():
    """One cook holds a fresh tomato at (1,2) (both orders ask for tomato) or a fresh onion
    at (3,2) (both ask for onion), three steps from a board either way: the same stage of
    either chain is worth the same."""
    env = ocplus_plan.make_jax_env("easy", n_agents=1, recipes=[["tomato"], ["onion"]],
                                   horizon=40)
    near = jax.tree_util.tree_map(jnp.asarray, tables(env.params))
    step = jax.jit(lambda s, a: env.step_env(jax.random.PRNGKey(0), s, {"agent_0": a})[1])
    phi = jax.jit(lambda s: potential(env.kitchen_state(s), near))
    first = env.reset(jax.random.PRNGKey(0))[1]
    values = []
    for recipe, route in ((0, [0, 3]), (1, [1, 1, 0, 0, 0, 1, 2, 2])):  # R,U / D,D,R,R,R,D,L,L
        state = first._replace(order_recipe=jnp.full_like(first.order_recipe, recipe))
        for a in route:
            state = step(state, jnp.int32(a))
        assert int(state.hand[0]) >= 0  # it holds the vegetable
        values.append(float(phi(state)))
    assert values[0] == pytest.approx(values[1]) and values[0] > 0


def test_a_curriculum_run_logs_served_orders_and_the_draw_per_recipe(tmp_path: Path):
    env = ocplus_plan.make_jax_env("easy", n_agents=1, obs_radius=1, horizon=8)
    config = PPOConfig(n_envs=2, n_steps=4, n_updates=2, n_epochs=1, n_minibatches=2,
                       hidden=8, order_curriculum=0.5)
    summary = train_to_folder(env, config, str(tmp_path), chunk=2)
    assert summary["recipes"] == ["tomato", "lettuce", "onion"]
    probs = summary["order_probs_by_update"]
    assert len(probs) == 2 and all(sum(p) == pytest.approx(1.0, abs=1e-3) for p in probs)
    assert len(summary["served_by_recipe_by_update"][0]) == 3
    assert json.loads((tmp_path / "train.json").read_text())["config"]["order_curriculum"] \
        == 0.5


def test_the_order_curriculum_is_refused_outside_the_jax_engine(tmp_path: Path, capsys):
    from ocplus_plan.cli import main

    code = main(["train", "--preset", "easy", "--timesteps", "64", "--engine", "loop",
                 "--order-curriculum", "0.5", "--out", str(tmp_path / "run")])
    assert code == 2
    assert "--engine jax" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()

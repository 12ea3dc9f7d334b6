"""An order curriculum for the JAX trainer (:mod:`ocplus_plan.rl.fast.jax_ppo`; the ``jax``
extra), used only while training.

A learner that first learns one recipe's chain (on easy, tomato soup) keeps serving that
recipe: the orders it cannot serve then stay open, and with two open orders an episode
soon asks only for what it never learned. With the curriculum the kitchens draw the
recipes the learner serves least more often: each new order (an order that replaces a
served or expired one, and every order of an episode that restarts) gets recipe ``r``
with probability::

    p_r = (1 - strength) / R + strength * gap_r / sum(gap)      gap_r = max(s) - s_r

(uniform while the gaps are all 0), where ``s_r`` is the share of recipe ``r``'s orders
that were served, a running average over the updates (:func:`update_rates`). A recipe no
run has served yet is then drawn most, and once the learner serves every recipe alike the
draw is uniform again, as in evaluation. Fixed orders (``Rules.fixed_orders``) are kept.
"""

from __future__ import annotations

from typing import Any

from ...sim.fast.jax_kitchen import P_FIXED, P_N_RECIPES, jax, jnp


def draw_probs(served: Any, drawn: Any, n_recipes: int, strength: float) -> Any:
    """``p_r`` above (``(R_max,)``, 0 past ``n_recipes``) from the running counts of
    served and drawn orders per recipe."""
    valid = jnp.arange(served.shape[0]) < n_recipes
    share = jnp.where(valid, served / jnp.maximum(drawn, 1e-6), 0.0)
    top = jnp.max(jnp.where(valid, share, -1.0))
    gap = jnp.where(valid, top - share, 0.0)
    uniform = valid / n_recipes
    lean = jnp.where(gap.sum() > 0, gap / jnp.maximum(gap.sum(), 1e-12), uniform)
    return (1.0 - strength) * uniform + strength * lean


def served_and_drawn(before: Any, after: Any, done: Any, n_recipes_max: int) -> tuple[Any, Any]:
    """Per recipe (``(R_max,)``), the orders one kitchen step served and the new orders it
    opened (``before``/``after``: one kitchen's states, ``after`` after the restart where
    ``done``). An order that left before its deadline was served; the orders open when an
    episode ends count as drawn, not served."""
    kept = jnp.any(before.order_id[:, None] == after.order_id[None, :], 1) & ~done
    expired = (before.order_deadline >= 0) & (before.order_deadline <= before.t + 1)
    served = ~kept & ~expired & ~done
    new = new_orders(before, after, done)
    recipes = jnp.arange(n_recipes_max)
    per = lambda mask, rec: jnp.sum(mask[:, None] & (rec[:, None] == recipes), 0)  # noqa: E731
    return per(served, before.order_recipe), per(new, after.order_recipe)


def redraw(key: Any, state: Any, new: Any, probs: Any, params: Any) -> Any:
    """``state`` (one kitchen) with the orders marked ``new`` given recipes drawn from
    ``probs``; unchanged where the kitchen's orders are fixed."""
    drawn = jax.random.choice(key, probs.shape[0], new.shape, p=probs).astype(
        state.order_recipe.dtype)
    keep = ~new | (params.ints[P_FIXED] > 0)
    return state._replace(order_recipe=jnp.where(keep, state.order_recipe, drawn))


def new_orders(before: Any, after: Any, done: Any) -> Any:
    """Which of ``after``'s order slots hold an order ``before`` did not have (all of them
    where the episode restarted)."""
    return ~jnp.any(after.order_id[:, None] == before.order_id[None, :], 1) | done


def batch_step(env: Any, active: bool) -> Any:
    """``f(key, before, after, done, obs, probs) -> (after, obs, served, drawn)`` over a
    batch of kitchens of ``env`` just stepped (``after`` restarted where ``done``): the
    served and new orders per recipe summed over the kitchens, and with ``active`` the
    new orders redrawn from ``probs`` and the observations made again."""
    r_max = int(env.params.recipes.shape[0])
    count = jax.vmap(lambda b, a, d: served_and_drawn(b, a, d, r_max))
    again = jax.vmap(lambda k, s, m, p: redraw(k, s, m, p, env.params), (0, 0, 0, None))

    def step(key: Any, before: Any, after: Any, done: Any, obs: Any, probs: Any) -> tuple:
        served, drawn = count(before, after, done)
        if active:  # (the step's own observations are then unused, and not computed)
            new = jax.vmap(new_orders)(before, after, done)
            after = again(jax.random.split(key, done.shape[0]), after, new, probs)
            obs = jax.vmap(env.get_obs)(after)
        return after, obs, served.sum(0), drawn.sum(0)

    return step


def update_rates(rates: tuple[Any, Any], served: Any, drawn: Any, decay: float = 0.9,
                 ) -> tuple[Any, Any]:
    """The running (served, drawn) counts after one update's counts."""
    return decay * rates[0] + served, decay * rates[1] + drawn


def n_recipes(params: Any) -> int:
    """The number of recipes of a (single-kitchen) ``Params``."""
    return int(params.ints[P_N_RECIPES])


__all__ = ["batch_step", "draw_probs", "n_recipes", "new_orders", "redraw", "served_and_drawn",
           "update_rates"]

"""Which recipes does a JAX-trained policy serve? Plays it on JAX kitchens, counts per recipe.

    python experiments/jax_served_by_recipe.py runs/jax_easy/.../policy.npz --preset easy

plays ``policy.npz`` (``ocplus train --engine jax``; 1 cook) on ``--kitchens`` JAX kitchens
of the preset for ``--horizon`` steps, actions sampled with ``--seed``, orders drawn as in
evaluation (no curriculum), and prints one JSON line: the recipes, the orders served per
recipe per episode (mean over the kitchens), the dishes per episode, how many of the
orders still open at the end ask for each recipe, and where the cook spends the episode:
the share of its steps with something in its hand, the share in which it moved, the
distinct cells it stood on and the share of its steps on its most visited cell. A policy that serves one recipe and never
another leaves the other's orders open: that is what the order curriculum
(``ocplus_plan/rl/fast/jax_orders.py``) is for.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("policy", type=Path)
    ap.add_argument("--preset", default="easy")
    ap.add_argument("--kitchens", type=int, default=32)
    ap.add_argument("--horizon", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    import jax
    import jax.numpy as jnp
    import numpy as np

    import ocplus_plan
    from ocplus_plan.rl.fast import jax_orders
    from ocplus_plan.rl.fast.jax_ppo import forward

    env = ocplus_plan.make_jax_env(args.preset, n_agents=1, horizon=args.horizon)
    with np.load(args.policy, allow_pickle=False) as saved:
        params = {k: jnp.asarray(saved[k]) for k in saved.files}
    e, r_max = args.kitchens, int(env.params.recipes.shape[0])
    count = jax.vmap(lambda b, a: jax_orders.served_and_drawn(b, a, jnp.bool_(False), r_max))

    def play(key):
        k0, key = jax.random.split(key)
        obs, state = jax.vmap(env.reset)(jax.random.split(k0, e))

        def one(carry, k):
            state, obs = carry
            k_act, k_step = jax.random.split(k)
            x = jnp.concatenate([obs[env.agents[0]], jnp.ones((e, 1))], 1)
            act = jax.random.categorical(k_act, forward(params, x)[0])
            after = jax.vmap(env.step_env)(jax.random.split(k_step, e), state,
                                           {env.agents[0]: act})
            where = (state.pos[:, 0], state.hand[:, 0] >= 0)
            return (after[1], after[0]), (count(state, after[1])[0], where)

        (state, _), (served, (pos, held)) = jax.lax.scan(
            one, (state, obs), jax.random.split(key, args.horizon))
        return served.sum(0), state.order_recipe, pos, held

    served, open_, pos, held = (np.asarray(x) for x in
                                jax.jit(play)(jax.random.PRNGKey(args.seed)))
    top = [np.bincount(pos[:, k]).max() / args.horizon for k in range(e)]
    n_rec = jax_orders.n_recipes(env.params)
    names = ["+".join(i.name.lower() for i in r) for r in env.rules.recipes]
    print(json.dumps({
        "policy": str(args.policy), "preset": args.preset, "kitchens": e,
        "horizon": args.horizon, "seed": args.seed, "recipes": names,
        "served_per_episode": [round(float(x), 3) for x in served.mean(0)[:n_rec]],
        "dishes_per_episode": round(float(served.sum(1).mean()), 3),
        "open_at_end": np.bincount(open_.ravel(), minlength=n_rec)[:n_rec].tolist(),
        "holding_share": round(float(held.mean()), 3),
        "moved_share": round(float((pos[1:] != pos[:-1]).mean()), 3),
        "cells_visited": round(float(np.mean([len(set(pos[:, k])) for k in range(e)])), 2),
        "top_cell_share": round(float(np.mean(top)), 3)}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

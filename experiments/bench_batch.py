"""Batched kitchens: env-steps/s against the number of kitchens, ours beside JaxMARL.

Ours: :class:`ocplus_plan.sim.fast.batch.BatchSim` (hard preset, MapC, 2 cooks, whole-map vector
observations of every cook kept up to date), compiled with numba (the ``fast`` extra), and
the Gymnasium vector env over it (``make_vec(..., vectorization_mode="vector_entry_point")``,
``copy=True`` and ``copy=False``). JaxMARL Overcooked V1 and V2 (the ``compare`` extra, CPU
jax): ``jit(vmap(step))`` inside ``lax.scan`` over random actions, compile time excluded;
each step's observations are summed into the scan output so XLA cannot drop them.
``ours_jax``: the kitchen in JAX (:mod:`ocplus_plan.sim.fast.jax_kitchen`, the ``jax``
extra) behind JaxMARL's interface, timed exactly as JaxMARL's envs on whatever device JAX
sees (``--kitchens 1024 16384 65536 262144`` on a GPU).
``ours_batch_features``: what the trainer's batched engine does per step (the step
without vector observations, the shaped rewards and every cook's ``features`` observation,
:class:`ocplus_plan.rl.fast.features_batch.BatchFeatures`).
Random uniform actions everywhere; medians of ``--runs`` rounds. One JSON line per
measurement. ``--memory`` prints instead the bytes held per kitchen (state, observations
and bookkeeping) for each observation the engine can keep.

    python experiments/bench_batch.py                      # all systems, 1 ... 4096 kitchens
    python experiments/bench_batch.py --plot experiments/figures/batch_scaling.png
    python experiments/bench_batch.py --memory
    python experiments/bench_batch.py --systems ours_jax jaxmarl_overcooked ours_batchsim \\
        --kitchens 1024 16384 65536 262144 --runs 3
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from typing import Any

import numpy as np

from ocplus_plan.sim import make_rules

KITCHENS = (1, 4, 16, 64, 256, 1024, 4096)


def _load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def bench_ours(n_envs: int, env_steps: int, runs: int, system: str) -> dict[str, Any]:
    from ocplus_plan.sim.fast.batch import BatchSim

    rules = make_rules("hard", n_agents=2)
    steps = max(20, env_steps // n_envs)
    actions = np.random.default_rng(0).integers(0, 5, size=(64, n_envs, 2))
    if system == "ours_batchsim":
        sim = BatchSim(rules, n_envs, seed=0, compiled=True)
        sim.reset()
        step, memory = sim.step, sim.memory_per_kitchen()
    elif system == "ours_batch_features":
        sim, feats = _features_batch(rules, n_envs)

        def step(acts: np.ndarray) -> None:
            ended = np.flatnonzero(np.logical_or(*sim.step_active(acts)))
            feats.rewards(1.0, True)
            if len(ended):
                sim.reset_envs(ended)
                feats.reset(ended)
            feats.encode()

        memory = sim.memory_per_kitchen() + feats.memory_per_kitchen()
    else:
        import gymnasium as gym

        import ocplus_plan.env  # noqa: F401

        venv = gym.make_vec("OvercookedPlus-v0", num_envs=n_envs,
                            vectorization_mode="vector_entry_point", preset="hard",
                            n_agents=2, copy=system == "ours_vector_env_copy", compiled=True)
        venv.reset(seed=0)
        step, memory = venv.step, venv.sim.memory_per_kitchen()
    step(actions[0])  # compiled kernels load from the cache (or compile) here
    rates = []
    for _ in range(runs):
        t0 = time.perf_counter()
        for i in range(steps):
            step(actions[i % 64])
        rates.append(steps * n_envs / (time.perf_counter() - t0))
    return {"bench": "batch", "system": system, "preset": "hard", "map": rules.layout.name,
            "n_agents": 2, "n_envs": n_envs, "env_steps": steps * n_envs, "runs": runs,
            "env_steps_per_s_median": round(statistics.median(rates)),
            "bytes_per_kitchen": memory, "load": _load(), "python": platform.python_version()}


def _features_batch(rules: Any, n_envs: int) -> tuple[Any, Any]:
    from ocplus_plan.rl.fast.features_batch import BatchFeatures
    from ocplus_plan.sim.fast.batch import BatchSim

    sim = BatchSim(rules, n_envs, seed=0, compiled=True, observe=False)
    sim.reset()
    feats = BatchFeatures(sim)
    feats.reset(np.arange(n_envs))
    feats.encode()
    return sim, feats


def memory_rows(n_envs: int = 64) -> list[dict[str, Any]]:
    """Bytes per kitchen (hard, MapC, 2 cooks) for each observation the engine keeps."""
    from ocplus_plan.sim.fast.batch import BatchSim

    rules = make_rules("hard", n_agents=2)
    rows = []
    for label, radius in (("vector, whole map", 0), ("vector, obs_radius=2", 2)):
        sim = BatchSim(rules, n_envs, obs_radius=radius, compiled=False)
        rows.append({"observation": label, "obs_bytes": sim.obs.nbytes // n_envs,
                     "bytes_per_kitchen": sim.memory_per_kitchen()})
    sim = BatchSim(rules, n_envs, compiled=False, observe=False)
    rows.append({"observation": "none (state only)", "obs_bytes": 0,
                 "bytes_per_kitchen": sim.memory_per_kitchen()})
    from ocplus_plan.rl.fast.features_batch import BatchFeatures

    feats = BatchFeatures(sim)
    rows.append({"observation": "features + shaping (the trainer's)",
                 "obs_bytes": feats.obs.nbytes // n_envs,
                 "bytes_per_kitchen": sim.memory_per_kitchen() + feats.memory_per_kitchen()})
    return [{"bench": "batch_memory", "preset": "hard", "n_agents": 2, **r} for r in rows]


def _jax_rollout(env: Any, n_envs: int, steps: int) -> Any:
    """``jit(vmap(step))`` inside ``lax.scan`` over uniform random actions for any
    JaxMARL-style env (ours or JaxMARL's); every step's observations and first reward
    are summed into the scan output so that XLA computes them."""
    import jax
    import jax.numpy as jnp

    n_actions = env.action_space(env.agents[0]).n

    def rollout(key: Any) -> Any:
        keys = jax.random.split(key, n_envs + 1)
        _, state = jax.vmap(env.reset)(keys[1:])

        def body(carry: Any, _: Any) -> Any:
            state, key = carry
            key, k_act, k_step = jax.random.split(key, 3)
            acts = {a: jax.random.randint(jax.random.fold_in(k_act, i), (n_envs,), 0, n_actions)
                    for i, a in enumerate(env.agents)}
            obs, state, rew, done, _ = jax.vmap(env.step)(jax.random.split(k_step, n_envs),
                                                          state, acts)
            used = sum(jnp.sum(o, dtype=jnp.float32) for o in obs.values())
            return (state, key), used + rew[env.agents[0]].sum()

        return jax.lax.scan(body, (state, keys[0]), None, length=steps)[1]

    return jax.jit(rollout)


def _time_rollout(run: Any, runs: int) -> tuple[list[float], float]:
    import jax

    t0 = time.perf_counter()
    run(jax.random.PRNGKey(0)).block_until_ready()  # compile
    compile_s = time.perf_counter() - t0
    times = []
    for r in range(runs):
        t0 = time.perf_counter()
        run(jax.random.PRNGKey(r + 1)).block_until_ready()
        times.append(time.perf_counter() - t0)
    return times, compile_s


def bench_jaxmarl(name: str, n_envs: int, env_steps: int, runs: int) -> dict[str, Any]:
    import jax
    import jaxmarl

    env = jaxmarl.make(name)
    steps = max(20, env_steps // n_envs)
    times, _ = _time_rollout(_jax_rollout(env, n_envs, steps), runs)
    _, state = env.reset(jax.random.PRNGKey(0))
    state_bytes = sum(x.nbytes for x in jax.tree_util.tree_leaves(state))
    obs, _ = env.reset(jax.random.PRNGKey(0))
    obs_bytes = sum(o.nbytes for o in obs.values())
    return {"bench": "batch", "system": f"jaxmarl_{name}", "n_agents": 2, "n_envs": n_envs,
            "env_steps": steps * n_envs, "runs": runs,
            "env_steps_per_s_median": round(steps * n_envs / statistics.median(times)),
            "bytes_per_kitchen": state_bytes + obs_bytes, "jax": jax.__version__,
            "device": str(jax.devices()[0].device_kind),
            "jaxmarl": getattr(jaxmarl, "__version__", "?"), "load": _load()}


def bench_ours_jax(n_envs: int, env_steps: int, runs: int, radius: int = 0) -> dict[str, Any]:
    """Ours in JAX (:func:`ocplus_plan.make_jax_env`, hard, MapC, 2 cooks, vector
    observations of every cook (whole map, or ``radius``), auto-reset), timed exactly as
    JaxMARL's envs."""
    import jax

    import ocplus_plan

    env = ocplus_plan.make_jax_env("hard", n_agents=2, obs_radius=radius)
    steps = max(20, env_steps // n_envs)
    times, compile_s = _time_rollout(_jax_rollout(env, n_envs, steps), runs)
    obs, state = env.reset(jax.random.PRNGKey(0))
    state_bytes = sum(x.nbytes for x in jax.tree_util.tree_leaves(state))
    obs_bytes = sum(o.nbytes for o in obs.values())
    return {"bench": "batch", "system": "ours_jax" + (f"_r{radius}" if radius else ""),
            "preset": "hard", "map": env.rules.layout.name, "obs_size": env.obs_size,
            "n_agents": 2, "n_envs": n_envs, "env_steps": steps * n_envs, "runs": runs,
            "env_steps_per_s_median": round(steps * n_envs / statistics.median(times)),
            "compile_s": round(compile_s, 2), "bytes_per_kitchen": state_bytes + obs_bytes,
            "jax": jax.__version__, "device": str(jax.devices()[0].device_kind),
            "load": _load(), "python": platform.python_version()}


def bench_ours_jax_parts(n_envs: int, env_steps: int, runs: int) -> list[dict[str, Any]]:
    """Where the JAX kitchen's time goes: the step alone (params as constants of the
    compiled step, or carried in every kitchen's state), no observation, no restart."""
    import jax
    import jax.numpy as jnp

    from ocplus_plan.sim.fast import jax_kitchen as jk
    rules = make_rules("hard", n_agents=2)
    params = jk.kitchen_params(rules)
    steps = max(20, env_steps // n_envs)

    def rollout(carried: bool, what: str) -> Any:
        def run(key: Any) -> Any:
            states = jax.vmap(jk.reset, (0, None))(jax.random.split(key, n_envs), params)
            if not carried:
                states = states._replace(params=None)

            def body(carry: Any, _: Any) -> Any:
                states, key = carry
                key, k_act = jax.random.split(key)
                acts = jax.random.randint(k_act, (n_envs, 2), 0, 5)
                full = states if carried else jax.vmap(
                    lambda s: s._replace(params=jax.tree_util.tree_map(jnp.asarray, params)))(states)
                out = jax.vmap(jk.step, (None, 0, 0))(None, full, acts)
                new = out.state if carried else out.state._replace(params=None)
                return (new, key), out.rewards.sum()

            return jax.lax.scan(body, (states, key), None, length=steps)[1]

        return jax.jit(run)

    rows = []
    for label, carried, what in (("ours_jax_step_only", False, "step"),
                                 ("ours_jax_step_only_params_in_state", True, "step")):
        times, compile_s = _time_rollout(rollout(carried, what), runs)
        rows.append({"bench": "batch_parts", "system": label, "n_envs": n_envs,
                     "env_steps": steps * n_envs, "runs": runs,
                     "env_steps_per_s_median": round(steps * n_envs / statistics.median(times)),
                     "compile_s": round(compile_s, 2), "device": str(jax.devices()[0].device_kind),
                     "load": _load()})
    return rows


def plot(rows: list[dict[str, Any]], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for system in dict.fromkeys(r["system"] for r in rows):
        pts = [(r["n_envs"], r["env_steps_per_s_median"]) for r in rows if r["system"] == system]
        ax.plot(*zip(*pts), marker="o", label=system)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.set_xlabel("kitchens stepped together")
    ax.set_ylabel("env-steps / s (2 cooks each)")
    ax.set_title("Batched kitchens on 2 CPU cores (random actions, obs of every cook)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--env-steps", type=int, default=400_000, help="per round and size")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--kitchens", type=int, nargs="+", default=list(KITCHENS))
    ap.add_argument("--systems", nargs="+", default=[
        "ours_batchsim", "ours_vector_env", "ours_vector_env_copy", "jaxmarl_overcooked",
        "jaxmarl_overcooked_v2"])
    ap.add_argument("--plot", default=None, help="write the steps/s plot here (matplotlib)")
    ap.add_argument("--memory", action="store_true", help="print bytes per kitchen and stop")
    args = ap.parse_args()
    if args.memory:
        for row in memory_rows():
            print(json.dumps(row), flush=True)
        return
    rows = []
    for system in args.systems:
        if system.startswith("jaxmarl_"):
            try:
                import jaxmarl  # noqa: F401
            except ImportError as exc:
                print(json.dumps({"bench": "batch", "system": system,
                                  "skipped": f"jaxmarl is not installed ({exc}); "
                                             "pip install 'ocplus-plan[compare]'"}), flush=True)
                continue
        for n_envs in args.kitchens:
            if system == "ours_jax_parts":
                for row in bench_ours_jax_parts(n_envs, args.env_steps, args.runs):
                    print(json.dumps(row), flush=True)
                continue
            if system in ("ours_jax", "ours_jax_r2"):
                row = bench_ours_jax(n_envs, args.env_steps, args.runs,
                                     2 if system.endswith("r2") else 0)
            elif system.startswith("jaxmarl_"):
                row = bench_jaxmarl(system.removeprefix("jaxmarl_"), n_envs, args.env_steps,
                                    args.runs)
            else:
                row = bench_ours(n_envs, args.env_steps, args.runs, system)
            rows.append(row)
            print(json.dumps(row), flush=True)
    if args.plot:
        plot(rows, args.plot)


if __name__ == "__main__":
    main()

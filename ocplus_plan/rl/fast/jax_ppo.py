"""A parameter-shared PPO whose whole update loop is one jitted function, over the JAX
kitchen (:func:`ocplus_plan.make_jax_env`; the ``jax`` extra).

Every cook is one actor of one shared MLP (its observation plus a one-hot of its index);
a rollout steps ``n_envs`` kitchens ``n_steps`` times with ``vmap``, then GAE and
``n_epochs`` passes of clipped-PPO minibatch updates; ``lax.scan`` runs ``n_updates``
such updates inside one ``jit``. The network and Adam are written out in ``jax.numpy``
(no flax or optax). :func:`save_npz` writes the weights as a ``.npz``.

:func:`train_to_folder` (``ocplus train --engine jax``) runs the updates in jitted chunks
(:func:`make_chunks`): after each it prints a progress line (updates, agent-steps,
steps/s, reward per step, dishes per finished episode) and writes a checkpoint
(``OUT/checkpoints/update_NNNNNN.npz`` with its ``train.json``).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...sim.fast.jax_kitchen import jax, jnp


class PPOConfig(NamedTuple):
    n_envs: int = 1024
    n_steps: int = 64
    n_updates: int = 10
    n_epochs: int = 2
    n_minibatches: int = 4
    hidden: int = 128
    lr: float = 5e-4
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip: float = 0.2
    ent_coef: float = 0.01
    vf_coef: float = 0.5
    reward_scale: float = 0.02


def init_params(key: Any, n_in: int, hidden: int, n_actions: int = 5) -> dict[str, Any]:
    sizes = [(n_in, hidden), (hidden, hidden), (hidden, n_actions + 1)]
    keys = jax.random.split(key, len(sizes))
    return {f"w{i}": jax.random.normal(k, s) * jnp.sqrt(1.0 / s[0]) for i, (k, s)
            in enumerate(zip(keys, sizes))} | {f"b{i}": jnp.zeros(s[1]) for i, s in
                                                enumerate(sizes)}


def forward(params: dict[str, Any], x: Any) -> tuple[Any, Any]:
    """(action logits, value) of observations ``x`` (``(..., n_in)``)."""
    h = jnp.tanh(x @ params["w0"] + params["b0"])
    h = jnp.tanh(h @ params["w1"] + params["b1"])
    out = h @ params["w2"] + params["b2"]
    return out[..., :-1], out[..., -1]


def _adam(params: Any, grads: Any, opt: Any, lr: float) -> tuple[Any, Any]:
    m, v, t = opt
    t = t + 1
    m = jax.tree_util.tree_map(lambda a, g: 0.9 * a + 0.1 * g, m, grads)
    v = jax.tree_util.tree_map(lambda a, g: 0.999 * a + 0.001 * g * g, v, grads)
    c1, c2 = 1 - 0.9 ** t, 1 - 0.999 ** t
    params = jax.tree_util.tree_map(
        lambda p, a, b: p - lr * (a / c1) / (jnp.sqrt(b / c2) + 1e-8), params, m, v)
    return params, (m, v, t)


def make_train(env: Any, config: PPOConfig) -> Any:
    """``train(key) -> (params, mean team reward per update)``: the whole run, jittable."""
    init, run = make_chunks(env, config, config.n_updates)

    def train(key: Any) -> tuple[Any, Any]:
        carry, (rewards, _) = run(init(key))
        return carry[0], rewards

    return train


def make_chunks(env: Any, config: PPOConfig, chunk: int) -> tuple[Any, Any]:
    """``(init(key) -> carry, run(carry) -> (carry, (reward per step, dishes per finished
    episode) per update))``: ``run`` does ``chunk`` updates; both jittable, and ``carry[0]``
    is the parameters."""
    n, e, t_len = env.num_agents, config.n_envs, config.n_steps
    agent_ids = jnp.eye(n)

    def actor_inputs(obs: dict[str, Any]) -> Any:  # (E, N, D + N)
        x = jnp.stack([obs[a] for a in env.agents], 1)
        return jnp.concatenate([x, jnp.broadcast_to(agent_ids, (x.shape[0], n, n))], 2)

    def rollout(carry: tuple, _: Any) -> tuple:
        params, state, obs, key = carry
        key, k_act, k_step = jax.random.split(key, 3)
        x = actor_inputs(obs)
        logits, value = forward(params, x)
        act = jax.random.categorical(k_act, logits)
        logp = jnp.take_along_axis(jax.nn.log_softmax(logits), act[..., None], -1)[..., 0]
        acts = {a: act[:, i] for i, a in enumerate(env.agents)}
        obs, state, rew, dones, info = jax.vmap(env.step)(jax.random.split(k_step, e), state,
                                                          acts)
        r = rew[env.agents[0]] * config.reward_scale
        step = (x, act, logp, value, r, dones["__all__"], info["dishes"][:, 0])
        return (params, state, obs, key), step

    def gae(values: Any, rewards: Any, dones: Any, last: Any) -> tuple[Any, Any]:
        def back(carry: tuple, xs: tuple) -> tuple:
            adv, next_v = carry
            v, r, d = xs
            nonterminal = 1.0 - d[:, None]
            delta = r[:, None] + config.gamma * next_v * nonterminal - v
            adv = delta + config.gamma * config.gae_lambda * nonterminal * adv
            return (adv, v), adv

        _, adv = jax.lax.scan(back, (jnp.zeros_like(last), last), (values, rewards, dones),
                              reverse=True)
        return adv, adv + values

    def loss(params: Any, batch: tuple) -> Any:
        x, act, old_logp, adv, ret = batch
        logits, value = forward(params, x)
        logp_all = jax.nn.log_softmax(logits)
        logp = jnp.take_along_axis(logp_all, act[..., None], -1)[..., 0]
        ratio = jnp.exp(logp - old_logp)
        adv = (adv - adv.mean()) / (adv.std() + 1e-8)
        pg = -jnp.minimum(ratio * adv, jnp.clip(ratio, 1 - config.clip, 1 + config.clip) * adv)
        entropy = -(jnp.exp(logp_all) * logp_all).sum(-1)
        return pg.mean() + config.vf_coef * ((value - ret) ** 2).mean() \
            - config.ent_coef * entropy.mean()

    def update(carry: tuple, _: Any) -> tuple:
        params, opt, state, obs, key = carry
        (params, state, obs, key), traj = jax.lax.scan(
            rollout, (params, state, obs, key), None, length=t_len)
        x, act, logp, value, r, done, dishes = traj
        _, last = forward(params, actor_inputs(obs))
        adv, ret = gae(value, r, done.astype(jnp.float32), last)
        flat = [a.reshape(t_len * e * n, *a.shape[3:]) for a in (x, act, logp, adv, ret)]
        size = t_len * e * n
        mb = size // config.n_minibatches

        def epoch(carry: tuple, _: Any) -> tuple:
            params, opt, key = carry
            key, k_perm = jax.random.split(key)
            perm = jax.random.permutation(k_perm, size)[: mb * config.n_minibatches]
            batches = [f[perm].reshape(config.n_minibatches, mb, *f.shape[1:]) for f in flat]

            def minibatch(carry: tuple, batch: tuple) -> tuple:
                params, opt = carry
                grads = jax.grad(loss)(params, batch)
                return _adam(params, grads, opt, config.lr), None

            (params, opt), _ = jax.lax.scan(minibatch, (params, opt), tuple(batches))
            return (params, opt, key), None

        (params, opt, key), _ = jax.lax.scan(epoch, (params, opt, key), None,
                                             length=config.n_epochs)
        ended = done.sum()
        served = jnp.where(ended > 0, (dishes * done).sum() / jnp.maximum(ended, 1), jnp.nan)
        return (params, opt, state, obs, key), (r.mean() / config.reward_scale, served)

    def init(key: Any) -> tuple:
        k_init, k_reset, key = jax.random.split(key, 3)
        obs, state = jax.vmap(env.reset)(jax.random.split(k_reset, e))
        params = init_params(k_init, env.obs_size + n, config.hidden)
        zeros = jax.tree_util.tree_map(jnp.zeros_like, params)
        return (params, (zeros, zeros, 0), state, obs, key)

    def run(carry: tuple) -> tuple:
        return jax.lax.scan(update, carry, None, length=chunk)

    return init, run


def agent_steps(config: PPOConfig, n_agents: int) -> int:
    """Agent-steps one ``train`` call collects."""
    return config.n_updates * config.n_steps * config.n_envs * n_agents


def save_npz(path: str, params: dict[str, Any]) -> None:
    np.savez(path, **{k: np.asarray(v) for k, v in params.items()})


def train_to_folder(env: Any, config: PPOConfig, out: str, seed: int = 0,
                    command: str | None = None, chunk: int | None = None,
                    stream: Any = None) -> dict[str, Any]:
    """Train in jitted chunks of ``chunk`` updates (default: about ten chunks), printing a
    progress line to ``stream`` and writing ``OUT/checkpoints/update_NNNNNN.npz`` after
    each; then ``OUT/policy.npz`` and ``OUT/train.json``. Returns the summary
    (``ocplus train --engine jax``)."""
    import json
    import time
    from pathlib import Path

    folder = Path(out)
    (folder / "checkpoints").mkdir(parents=True, exist_ok=True)
    chunk = max(1, min(chunk or -(-config.n_updates // 10), config.n_updates))
    per_update = agent_steps(config._replace(n_updates=1), env.num_agents)
    record = {"engine": "jax", "preset": env.rules.preset, "map": env.rules.layout.name,
              "n_agents": env.num_agents, "obs_size": env.obs_size,
              "obs_radius": env.obs_radius, "config": config._asdict(), "command": command}
    (folder / "checkpoints" / "train.json").write_text(json.dumps(record, indent=2) + "\n")
    t0 = time.perf_counter()
    init, run = make_chunks(env, config, chunk)
    carry = jax.jit(init)(jax.random.PRNGKey(seed))
    run = jax.jit(run)
    rewards: list[float] = []
    dishes: list[float] = []
    done = 0
    while done < config.n_updates:
        carry, (r, d) = jax.block_until_ready(run(carry))
        done += chunk
        rewards += [float(x) for x in np.asarray(r)]
        dishes += [float(x) for x in np.asarray(d)]
        save_npz(str(folder / "checkpoints" / f"update_{done:06d}.npz"), carry[0])
        if stream is not None:
            wall = time.perf_counter() - t0
            recent = [x for x in dishes[-chunk:] if x == x]
            print(f"update {done}/{config.n_updates * 1}  {done * per_update} agent-steps  "
                  f"{done * per_update / wall:.0f} steps/s  reward/step {rewards[-1]:.3f}  "
                  f"dishes/episode {np.mean(recent) if recent else float('nan'):.2f}  "
                  f"{wall:.0f}s", file=stream, flush=True)
    wall = time.perf_counter() - t0
    save_npz(str(folder / "policy.npz"), carry[0])
    steps = done * per_update
    summary = {
        **record, "policy": str(folder / "policy.npz"), "timesteps": steps,
        "wall_time_s": round(wall, 1), "steps_per_s": round(steps / wall, 1),
        "team_reward_per_step_by_update": [round(r, 4) for r in rewards],
        "dishes_per_episode_by_update": [None if d != d else round(d, 3) for d in dishes],
        "device": str(jax.devices()[0].device_kind),
    }
    (folder / "train.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


__all__ = ["PPOConfig", "agent_steps", "forward", "init_params", "make_chunks", "make_train",
           "save_npz",
           "train_to_folder"]

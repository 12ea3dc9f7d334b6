"""A parameter-shared PPO whose whole update loop is one jitted function, over the JAX
kitchen (:func:`ocplus_plan.make_jax_env`; the ``jax`` extra).

Every cook is one actor of one shared policy MLP (its observation plus a one-hot of its
index), valued by a separate critic MLP (``PPOConfig.critic``). The reward it learns from
is the rules' reward without the subtask payment plus potential-based shaping
(:mod:`ocplus_plan.rl.fast.jax_shaping`); the kitchens' clocks start at different steps
(:func:`desync`), the learning rate decays linearly to ``lr_final``, and while training
new orders lean towards the recipes the policy serves least (``order_curriculum``,
:mod:`ocplus_plan.rl.fast.jax_orders`), and a learner that has served no order in a fifth
of the run (since it started or since its last order) is started again with fresh weights
and kitchens (``restart_after``, :func:`should_restart`). A rollout steps ``n_envs`` kitchens ``n_steps``
times with ``vmap``, then GAE and ``n_epochs`` passes of clipped-PPO minibatch updates;
``lax.scan`` runs ``n_updates`` such updates inside one ``jit``. The network and Adam are
written out in ``jax.numpy`` (no flax or optax). :func:`save_npz` writes the weights as a ``.npz``.

:func:`train_to_folder` (``ocplus train --engine jax``) runs the updates in jitted chunks
(:func:`make_chunks`): after each it prints a progress line (updates, agent-steps,
steps/s, reward per step, dishes per finished episode, subtasks per episode, policy
entropy, orders served per recipe) and writes a checkpoint
(``OUT/checkpoints/update_NNNNNN.npz`` with its ``train.json``).
"""

from __future__ import annotations

from functools import partial
from typing import Any, NamedTuple

import numpy as np

from ...sim.fast.jax_kitchen import P_HORIZON, jax, jnp
from . import jax_orders
from .jax_shaping import shaping_step, tables


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
    #: the learning rate decays linearly to this fraction of ``lr`` over ``n_updates``
    lr_final: float = 0.1
    #: weight of the potential-based shaping (rl/fast/jax_shaping.py); 0: none
    shaping: float = 1.0
    #: keep the rules' subtask payment (``infos["shaped_reward"]``) in the training reward
    subtask_reward: bool = False
    #: otherwise pay it at first, its weight falling linearly from 1 to 0 over this
    #: fraction of the updates (:func:`subtask_weight`); 0: never (on easy it rescued one
    #: training seed and lost another: docs/rl.md)
    subtask_anneal: float = 0.0
    #: start the kitchens' clocks at different steps (:func:`desync`), so one rollout
    #: does not see every kitchen at the same phase of its episode
    desync: bool = True
    #: a separate value network (not saved: the policy.npz holds the actor)
    critic: bool = True
    #: the order curriculum's strength (rl/fast/jax_orders.py): new orders lean this much
    #: towards the recipes served least; 0: drawn as in evaluation
    order_curriculum: float = 0.5
    #: a learner that has served no order in this fraction of the run's updates (since
    #: it started or since its last order) is started again (:func:`should_restart`):
    #: fresh weights drawn with a new key, fresh Adam, its own learning-rate decay over the
    #: updates left, fresh kitchens; 0: never
    restart_after: float = 0.2
    #: the advantages add this weight of the shaping's own GAE, without a baseline
    #: (:func:`_advantages`): a critic that has learned the shaped returns
    #: (``V = ... - phi``) cancels the potential in GAE, and a learner not serving yet
    #: then has no signal left; 0: none
    shaping_bonus: float = 0.5


def init_params(key: Any, n_in: int, hidden: int, n_actions: int = 5,
                critic: bool = False) -> dict[str, Any]:
    """The MLP ``w0 b0 w1 b1 w2 b2`` (logits, then a value column); with ``critic`` also a
    separate value MLP ``v0 c0 v1 c1 v2 c2``, which :func:`forward` then reads the value
    from (the actor's value column stays unused)."""
    params = _dense(key, [(n_in, hidden), (hidden, hidden), (hidden, n_actions + 1)], "w", "b")
    if critic:
        params |= _dense(jax.random.fold_in(key, 1),
                         [(n_in, hidden), (hidden, hidden), (hidden, 1)], "v", "c")
    return params


def _dense(key: Any, sizes: list[tuple[int, int]], w: str, b: str) -> dict[str, Any]:
    """Layers ``{w}i`` (scaled normal) and ``{b}i`` (zeros) of the given sizes."""
    keys = jax.random.split(key, len(sizes))
    return {f"{w}{i}": jax.random.normal(k, s) * jnp.sqrt(1.0 / s[0])
            for i, (k, s) in enumerate(zip(keys, sizes))} | {
                f"{b}{i}": jnp.zeros(s[1]) for i, s in enumerate(sizes)}


def _mlp(params: dict[str, Any], x: Any, w: str, b: str) -> Any:
    h = jnp.tanh(x @ params[f"{w}0"] + params[f"{b}0"])
    h = jnp.tanh(h @ params[f"{w}1"] + params[f"{b}1"])
    return h @ params[f"{w}2"] + params[f"{b}2"]


def forward(params: dict[str, Any], x: Any) -> tuple[Any, Any]:
    """(action logits, value) of observations ``x`` (``(..., n_in)``)."""
    out = _mlp(params, x, "w", "b")
    value = _mlp(params, x, "v", "c")[..., 0] if "v0" in params else out[..., -1]
    return out[..., :-1], value


def _adam(params: Any, grads: Any, opt: Any, lr: float) -> tuple[Any, Any]:
    m, v, t = opt
    t = t + 1
    m = jax.tree_util.tree_map(lambda a, g: 0.9 * a + 0.1 * g, m, grads)
    v = jax.tree_util.tree_map(lambda a, g: 0.999 * a + 0.001 * g * g, v, grads)
    c1, c2 = 1 - 0.9 ** t, 1 - 0.999 ** t
    params = jax.tree_util.tree_map(
        lambda p, a, b: p - lr * (a / c1) / (jnp.sqrt(b / c2) + 1e-8), params, m, v)
    return params, (m, v, t)


def _gae(config: PPOConfig, values: Any, rewards: Any, dones: Any, last: Any,
         ) -> tuple[Any, Any]:
    """(advantages, returns) by GAE over a rollout (a done step bootstraps nothing)."""
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


def _advantages(config: PPOConfig, values: Any, reward: Any, shaped: Any, dones: Any,
                last: Any) -> tuple[Any, Any]:
    """(advantages, returns) of a rollout whose reward is ``reward + shaped`` (times
    ``reward_scale``): GAE over the sum, the critic's targets its returns; the advantages
    add ``shaping_bonus`` times the shaping's GAE with a value of 0, the lambda-discounted
    rise of the potential ahead, which no critic cancels."""
    scale = config.reward_scale
    adv, ret = _gae(config, values, (reward + shaped) * scale, dones, last)
    if not config.shaping_bonus:
        return adv, ret
    bonus, _ = _gae(config, jnp.zeros_like(values), shaped * scale, dones,
                    jnp.zeros_like(last))
    return adv + config.shaping_bonus * bonus, ret


def _loss(config: PPOConfig, params: Any, batch: tuple) -> Any:
    """Clipped PPO loss of one minibatch, advantages normalised within it."""
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


def subtask_weight(config: PPOConfig, update: Any) -> Any:
    """The share of the rules' subtask payment in the training reward at ``update``: 1
    with ``subtask_reward``; else falling linearly from 1 to 0 over the first
    ``subtask_anneal`` of the updates (it pays the first chops, cooks and washes a policy
    stumbles on, which the potential alone, paid back when the episode ends, does not;
    from then on the learner's objective is the rules' reward and the potential's)."""
    if config.subtask_reward:
        return jnp.float32(1.0)
    span = config.subtask_anneal * config.n_updates
    if span <= 0:
        return jnp.float32(0.0)
    return jnp.clip(1.0 - update / span, 0.0, 1.0).astype(jnp.float32)


def _learning_rate(config: PPOConfig, t: Any, start: Any = 0) -> Any:
    """The rate at the learner's Adam step ``t``: linear decay to ``lr_final x lr`` over
    the updates from ``start`` (the update the learner started at) to the run's end."""
    per = config.n_epochs * config.n_minibatches
    whole = max(1, config.n_updates * per)
    # the first learner's fraction as a division by the constant: XLA then computes the
    # rates it always did (a division by a traced count differs in the last bit, and a run
    # amplifies that into another run)
    left = jnp.maximum(1, (config.n_updates - start) * per)
    done = jnp.where(start == 0, t / whole, t / left)
    return config.lr * (1.0 - (1.0 - config.lr_final) * jnp.minimum(1.0, done))


def should_restart(config: PPOConfig, update: Any, idle_from: Any) -> Any:
    """Whether the learner is started again before ``update``, having served no order
    since update ``idle_from`` (the update it started at, or the one after its last
    order): ``restart_after`` of the run's updates have passed since. (With the
    potential-based shaping alone a learner that is not serving by the time its critic
    has learned ``V = ... - phi`` has no signal left: the shaping cancels in its
    advantages. On easy the runs that learn serve their first order within 17-127
    updates of 732 and are never idle for 147; docs/rl.md.)"""
    span = jnp.ceil(config.restart_after * config.n_updates)
    return (config.restart_after > 0) & (update - idle_from >= span)


def _restart(config: PPOConfig, n_in: int, kitchens: Any, learner: tuple, life: tuple,
             ) -> tuple:
    """(``learner``, life) as they are, or a fresh learner where :func:`should_restart`
    says so: ``learner`` is (params, Adam state, kitchen states, observations); the fresh
    one has weights drawn with ``fold_in(init key, restarts + 1)``, a fresh Adam, and
    ``kitchens(key)``'s fresh kitchens (so no order a learner served is one its predecessor
    left half made). ``life``: the update, the learner's first update, the update it has not
    served an order since (:func:`should_restart`), the restarts so far, the run's init
    key."""
    u, start, idle_from, restarts, k_init = life
    again = should_restart(config, u, idle_from)

    def fresh(old: tuple) -> tuple:
        key = jax.random.fold_in(k_init, restarts + 1)
        params = init_params(key, n_in, config.hidden, critic=config.critic)
        opt = jax.tree_util.tree_map(jnp.zeros_like, old[1])
        return (params, opt, *kitchens(jax.random.fold_in(key, 1)))

    learner = jax.lax.cond(again, fresh, lambda old: old, learner)
    return learner, (u, jnp.where(again, u, start), jnp.where(again, u, idle_from),
                     restarts + again.astype(restarts.dtype), k_init)


def _epochs(config: PPOConfig, params: Any, opt: Any, key: Any, flat: list, start: Any,
            ) -> tuple:
    """``n_epochs`` passes of minibatch updates over one rollout's ``flat`` samples (the
    learner started at update ``start``)."""
    size = flat[0].shape[0]
    mb = size // config.n_minibatches

    def epoch(carry: tuple, _: Any) -> tuple:
        params, opt, key = carry
        key, k_perm = jax.random.split(key)
        perm = jax.random.permutation(k_perm, size)[: mb * config.n_minibatches]
        batches = [f[perm].reshape(config.n_minibatches, mb, *f.shape[1:]) for f in flat]

        def minibatch(carry: tuple, batch: tuple) -> tuple:
            params, opt = carry
            grads = jax.grad(partial(_loss, config))(params, batch)
            return _adam(params, grads, opt, _learning_rate(config, opt[2], start)), None

        (params, opt), _ = jax.lax.scan(minibatch, (params, opt), tuple(batches))
        return (params, opt, key), None

    (params, opt, key), _ = jax.lax.scan(epoch, (params, opt, key), None,
                                         length=config.n_epochs)
    return params, opt, key


def make_train(env: Any, config: PPOConfig) -> Any:
    """``train(key) -> (params, mean team reward per update)``: the whole run, jittable."""
    init, run = make_chunks(env, config, config.n_updates)

    def train(key: Any) -> tuple[Any, Any]:
        carry, metrics = run(init(key))
        return carry[0], metrics["reward"]

    return train


def make_chunks(env: Any, config: PPOConfig, chunk: int) -> tuple[Any, Any]:
    """``(init(key) -> carry, run(carry) -> (carry, (reward per step, dishes per finished
    episode) per update))``: ``run`` does ``chunk`` updates; both jittable, and ``carry[0]``
    is the parameters."""
    n, e, t_len = env.num_agents, config.n_envs, config.n_steps
    horizon = int(env.params.ints[P_HORIZON])
    subtask_value = float(env.rules.rewards.subtask_finished) or 1.0
    agent_ids = jnp.eye(n)

    def actor_inputs(obs: dict[str, Any]) -> Any:  # (E, N, D + N)
        x = jnp.stack([obs[a] for a in env.agents], 1)
        return jnp.concatenate([x, jnp.broadcast_to(agent_ids, (x.shape[0], n, n))], 2)

    near = jax.tree_util.tree_map(jnp.asarray, tables(env.params))
    shape = jax.vmap(lambda b, a, d: shaping_step(env, b, a, d, near, config.gamma))
    n_rec, r_max = jax_orders.n_recipes(env.params), int(env.params.recipes.shape[0])
    orders = jax_orders.batch_step(env, config.order_curriculum > 0)

    def rollout(carry: tuple, _: Any) -> tuple:
        params, state, obs, key, (probs, keep) = carry
        key, k_act, k_step, k_draw = jax.random.split(key, 4)
        x = actor_inputs(obs)
        logits, value = forward(params, x)
        act = jax.random.categorical(k_act, logits)
        logp_all = jax.nn.log_softmax(logits)
        logp = jnp.take_along_axis(logp_all, act[..., None], -1)[..., 0]
        acts = {a: act[:, i] for i, a in enumerate(env.agents)}
        before = state
        obs, state, rew, dones, info = jax.vmap(env.step)(jax.random.split(k_step, e), state,
                                                          acts)
        state, obs, served, drawn = orders(k_draw, before, state, dones["__all__"], obs, probs)
        game = rew[env.agents[0]]
        subtask = info["shaped_reward"][env.agents[0]]
        shaped = shape(before, state, dones["__all__"]) if config.shaping else 0.0 * game
        r = game - (1.0 - keep) * subtask
        entropy = -(jnp.exp(logp_all) * logp_all).sum(-1).mean()
        step = (x, act, logp, value, r, config.shaping * shaped, dones["__all__"],
                info["dishes"][:, 0], (game, subtask, shaped, entropy, served, drawn))
        return (params, state, obs, key, (probs, keep)), step

    def update(carry: tuple, _: Any) -> tuple:
        params, opt, state, obs, key, rates, life = carry
        (params, opt, state, obs), life = _restart(
            config, env.obs_size + n, kitchens, (params, opt, state, obs), life)
        probs = jax_orders.draw_probs(*rates, n_rec, config.order_curriculum)
        keep = subtask_weight(config, opt[2] // (config.n_epochs * config.n_minibatches))
        (params, state, obs, key, _), traj = jax.lax.scan(
            rollout, (params, state, obs, key, (probs, keep)), None, length=t_len)
        x, act, logp, value, r, f, done, dishes, (game, subtask, shaped, entropy,
                                                  served, drawn) = traj
        rates = jax_orders.update_rates(rates, served.sum(0), drawn.sum(0))
        u, start, idle_from, restarts, k_init = life
        _, last = forward(params, actor_inputs(obs))
        adv, ret = _advantages(config, value, r, f, done.astype(jnp.float32), last)
        flat = [a.reshape(t_len * e * n, *a.shape[3:]) for a in (x, act, logp, adv, ret)]
        params, opt, key = _epochs(config, params, opt, key, flat, start)
        ended = done.sum()

        def per_episode(v: Any) -> Any:
            return jnp.where(ended > 0, (v * done).sum() / jnp.maximum(ended, 1), jnp.nan)

        # subtasks (chops, cooks, washes) finished per horizon of steps, at this rollout's rate
        metrics = {"reward": game.mean(), "dishes": per_episode(dishes),
                   "subtasks": subtask.mean() * horizon / subtask_value,
                   "shaping": shaped.mean(), "entropy": entropy.mean(),
                   # per recipe: orders served per horizon of steps, and the draw's p_r
                   "served_by_recipe": served.sum(0)[:n_rec] * horizon / (t_len * e),
                   "order_probs": probs[:n_rec], "subtask_weight": keep,
                   # the critic before this update's passes: how much of the returns'
                   # variance it explains, and the returns' mean (reward_scale units)
                   "explained_variance": 1.0 - jnp.var(ret - value) / (jnp.var(ret) + 1e-8),
                   "return_mean": ret.mean(), "restarts": restarts}
        life = (u + 1, start, jnp.where(served.sum() > 0, u + 1, idle_from), restarts, k_init)
        return (params, opt, state, obs, key, rates, life), metrics

    def kitchens(k_reset: Any, k_warm: Any = None) -> tuple:  # (states, observations)
        if k_warm is None:
            k_reset, k_warm = jax.random.split(k_reset)
        obs, state = jax.vmap(env.reset)(jax.random.split(k_reset, e))
        if config.desync:
            obs, state = desync(env, state, k_warm)
        return state, obs

    def init(key: Any) -> tuple:
        k_init, k_reset, k_warm, key = jax.random.split(key, 4)
        state, obs = kitchens(k_reset, k_warm)
        params = init_params(k_init, env.obs_size + n, config.hidden,
                             critic=config.critic)
        zeros = jax.tree_util.tree_map(jnp.zeros_like, params)
        rates = (jnp.zeros(r_max), jnp.zeros(r_max))
        # update, the learner's first update, the update it has served nothing since,
        # restarts, the run's init key
        life = (jnp.int32(0), jnp.int32(0), jnp.int32(0), jnp.int32(0), k_init)
        return (params, (zeros, zeros, jnp.int32(0)), state, obs, key, rates, life)

    def run(carry: tuple) -> tuple:
        return jax.lax.scan(update, carry, None, length=chunk)

    return init, run


def desync(env: Any, state: Any, key: Any) -> tuple[Any, Any]:
    """(observations, states) of a batch of fresh kitchens whose clocks start at
    ``offset_e`` (drawn in 0 .. horizon - 1; the open orders and the next layout switch
    shifted with them), so their first episodes are cut short and the kitchens' episodes
    end at different steps of a rollout."""
    horizon = int(env.params.ints[P_HORIZON])
    offset = jax.random.randint(key, state.t.shape, 0, horizon).astype(state.t.dtype)
    col = offset[:, None]
    state = state._replace(
        t=state.t + offset, next_switch=state.next_switch + offset,
        order_created=state.order_created + col,
        order_deadline=jnp.where(state.order_deadline >= 0, state.order_deadline + col, -1))
    return jax.vmap(env.get_obs)(state), state


def agent_steps(config: PPOConfig, n_agents: int) -> int:
    """Agent-steps one ``train`` call collects."""
    return config.n_updates * config.n_steps * config.n_envs * n_agents


def save_npz(path: str, params: dict[str, Any]) -> None:
    """The actor's weights ``w0 b0 w1 b1 w2 b2`` as a ``.npz`` (a separate critic is left
    out: playing needs only the actor)."""
    np.savez(path, **{k: np.asarray(v) for k, v in params.items() if k[0] in "wb"})


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
    cpu0 = time.process_time()
    planned = -(-config.n_updates // chunk) * chunk  # whole chunks: may pass n_updates
    log: dict[str, list[Any]] = {}
    done = 0
    while done < config.n_updates:
        carry, metrics = jax.block_until_ready(run(carry))
        done += chunk
        for name, values in metrics.items():
            log.setdefault(name, []).extend(np.asarray(values, np.float64).tolist())
        save_npz(str(folder / "checkpoints" / f"update_{done:06d}.npz"), carry[0])
        if stream is not None:
            wall = time.perf_counter() - t0
            recent = [x for x in log["dishes"][-chunk:] if x == x]
            print(f"update {done}/{planned}  {done * per_update} agent-steps  "
                  f"{done * per_update / wall:.0f} steps/s  reward/step {log['reward'][-1]:.3f}  "
                  f"dishes/episode {np.mean(recent) if recent else float('nan'):.2f}  "
                  f"subtasks/episode {log['subtasks'][-1]:.2f}  "
                  f"entropy {log['entropy'][-1]:.2f}  served by recipe "
                  f"{'/'.join(f'{x:.1f}' for x in log['served_by_recipe'][-1])}  "
                  f"restarts {log['restarts'][-1]:.0f}  {wall:.0f}s", file=stream, flush=True)
    wall = time.perf_counter() - t0
    save_npz(str(folder / "policy.npz"), carry[0])
    steps = done * per_update

    def rounded(values: list[float]) -> list[float | None]:
        return [None if v != v else round(v, 4) for v in values]

    summary = {
        **record, "policy": str(folder / "policy.npz"), "timesteps": steps,
        "wall_time_s": round(wall, 1), "cpu_time_s": round(time.process_time() - cpu0, 1),
        "steps_per_s": round(steps / wall, 1),
        "team_reward_per_step_by_update": rounded(log["reward"]),
        "dishes_per_episode_by_update": rounded(log["dishes"]),
        "subtasks_per_episode_by_update": rounded(log["subtasks"]),
        "shaping_per_step_by_update": rounded(log["shaping"]),
        "entropy_by_update": rounded(log["entropy"]),
        "subtask_weight_by_update": rounded(log["subtask_weight"]),
        "explained_variance_by_update": rounded(log["explained_variance"]),
        "return_mean_by_update": rounded(log["return_mean"]),
        # learners started again for serving nothing (config restart_after), and the
        # update the kept learner started at
        "restarts": int(carry[6][3]), "learner_start_update": int(carry[6][1]),
        "recipes": ["+".join(i.name.lower() for i in r) for r in env.rules.recipes],
        "served_by_recipe_by_update": [rounded(v) for v in log["served_by_recipe"]],
        "order_probs_by_update": [rounded(v) for v in log["order_probs"]],
        "device": str(jax.devices()[0].device_kind),
    }
    (folder / "train.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


__all__ = ["PPOConfig", "agent_steps", "forward", "init_params", "make_chunks", "make_train",
           "save_npz", "subtask_weight", "train_to_folder"]

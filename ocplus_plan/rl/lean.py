"""A lean PPO loop over the kitchens (``ocplus train --algo lean``).

The same algorithm and network as the stable-baselines3 trainer, read from the SB3 ``PPO``
object that :func:`ocplus_plan.rl.train.build` makes (its policy, optimiser, clip range,
value-loss weight, gradient-norm limit, advantage normalisation and learning-rate
schedule), without SB3's per-step machinery: the rollout lives in preallocated torch
tensors, one forward pass per rollout step acts for every agent of every kitchen (under
``torch.inference_mode``), GAE runs over all slots at once, and the update draws its
minibatches from the flat rollout. It trains ``model.policy`` in place, so ``model.save``
writes the usual checkpoint (``ocplus eval --agents ppo:...`` loads it like any other).

``precision="bf16"`` runs the forward and backward matrix products in bfloat16 under
``torch.autocast`` (the weights, the optimiser, the losses and GAE stay float32): about
twice the throughput on CPUs with AVX-512 BF16, at the cost of rounding in the network.

:class:`LeanPPO` keeps where its time went (:attr:`LeanPPO.seconds`):
``env`` (kitchens, encoding, shaping), ``forward`` (the rollout's forward passes),
``rollout_other`` (sampling, storing, GAE) and ``update`` (minibatch forward, backward and
optimiser steps).
"""

from __future__ import annotations

import time
from contextlib import nullcontext
from typing import Any

import numpy as np

PRECISIONS = ("fp32", "bf16")


def gae(rewards: Any, values: Any, dones: Any, last_values: Any, gamma: float,
        lam: float) -> tuple[Any, Any]:
    """Generalised advantage estimates and returns for ``(T, N)`` tensors.

    ``dones[t]``: the slot's episode ended with step ``t`` (its next value is not
    bootstrapped; the trainer's episodes end at the horizon, which the observation's clock
    shows, and SB3 treats them the same way). ``last_values``: ``(N,)`` values of the
    observations after the last step.
    """
    import torch

    steps = rewards.shape[0]
    advantages = torch.empty_like(rewards)
    running = torch.zeros_like(last_values)
    next_values = last_values
    alive = 1.0 - dones.float()
    for t in range(steps - 1, -1, -1):
        delta = rewards[t] + gamma * next_values * alive[t] - values[t]
        running = delta + gamma * lam * alive[t] * running
        advantages[t] = running
        next_values = values[t]
    return advantages, advantages + values


class LeanPPO:
    """The PPO of ``model`` (an SB3 ``PPO``: its policy, optimiser and settings, n_steps,
    batch_size and n_epochs included) over ``venv`` (a
    :class:`~ocplus_plan.rl.vec_env.KitchenVecEnv`), with the network's matrix products in
    ``precision`` and actions and minibatches drawn from a generator seeded ``seed``.

    :meth:`learn` has the signature and step counting of SB3's ``PPO.learn`` (whole
    rollouts; ``model.num_timesteps`` advances; the callback sees the same hooks), so
    :func:`ocplus_plan.rl.train.train` drives either the same way.
    """

    def __init__(self, model: Any, venv: Any, precision: str = "fp32", seed: int = 0) -> None:
        import torch

        self.model, self.venv, self.precision = model, venv, precision
        self.policy = model.policy
        self.params = list(self.policy.parameters())
        self.generator = torch.Generator().manual_seed(seed)
        slots, steps = venv.num_envs, model.n_steps
        f32 = torch.float32
        self.obs = torch.zeros((steps, slots, venv.obs_size), dtype=f32)
        self.actions = torch.zeros((steps, slots), dtype=torch.int64)
        self.logits = torch.zeros((steps, slots, int(venv.action_space.n)), dtype=f32)
        self.values = torch.zeros((steps, slots), dtype=f32)
        self.rewards = torch.zeros((steps, slots), dtype=f32)
        self.dones = torch.zeros((steps, slots), dtype=torch.bool)
        # computed from the whole rollout at its end (_collect)
        self.log_probs: Any = None
        self.advantages: Any = None
        self.returns: Any = None
        self._last_obs: np.ndarray | None = None
        self._total = 0
        self._clip = 0.0
        self.seconds = dict.fromkeys(("env", "forward", "rollout_other", "update"), 0.0)

    # ------------------------------------------------------------ network
    def _autocast(self) -> Any:
        import torch

        if self.precision == "bf16":
            return torch.autocast("cpu", dtype=torch.bfloat16)
        return nullcontext()

    def _forward(self, obs: Any) -> tuple[Any, Any]:
        """Action logits and values (float32) of the SB3 policy's two heads."""
        p = self.policy
        with self._autocast():
            logits = p.action_net(p.mlp_extractor.policy_net(obs))
            values = p.value_net(p.mlp_extractor.value_net(obs))
        return logits.float(), values.float().squeeze(-1)

    # ------------------------------------------------------------ loop
    def learn(self, total_timesteps: int, callback: Any = None,
              reset_num_timesteps: bool = True) -> LeanPPO:
        model = self.model
        if reset_num_timesteps:
            model.num_timesteps = 0
        self._total = total_timesteps + model.num_timesteps
        if self._last_obs is None:
            self._last_obs = self.venv.reset()
        if callback is not None:
            callback.init_callback(model)
        while model.num_timesteps < self._total:
            if not self._collect(callback):
                break
            self._update()
        if callback is not None:
            callback.on_training_end()
        return self

    def _collect(self, callback: Any) -> bool:
        """One rollout of ``n_steps`` for every slot; False when the callback stops it."""
        import torch

        clock = time.perf_counter
        venv, model, sec = self.venv, self.model, self.seconds
        if callback is not None:
            callback.on_rollout_start()
        # Gumbel-max: argmax(logits + Gumbel noise) samples the policy's categorical; the
        # noise for the whole rollout is drawn at once, the log-probabilities computed after
        u = torch.rand(self.logits.shape, generator=self.generator).clamp_(min=1e-12)
        gumbel = -torch.log(-torch.log(u))
        going = True
        for t in range(self.model.n_steps):
            t0 = clock()
            obs = self.obs[t]
            obs.copy_(torch.from_numpy(self._last_obs))
            with torch.inference_mode():
                t1 = clock()
                logits, values = self._forward(obs)
                t2 = clock()
                self.logits[t] = logits
                self.values[t] = values
                torch.argmax(logits + gumbel[t], dim=1, out=self.actions[t])
            t3 = clock()
            venv.step_async(self.actions[t].numpy())
            self._last_obs, reward, done, _ = venv.step_wait()
            t4 = clock()
            self.rewards[t] = torch.from_numpy(reward)
            self.dones[t] = torch.from_numpy(done)
            model.num_timesteps += venv.num_envs
            if callback is not None and not callback.on_step():
                going = False
            sec["forward"] += t2 - t1
            sec["env"] += t4 - t3
            sec["rollout_other"] += (t1 - t0) + (t3 - t2) + (clock() - t4)
            if not going:
                break
        t0 = clock()
        with torch.inference_mode():
            last = self._forward(torch.from_numpy(self._last_obs))[1]
            log_p = torch.log_softmax(self.logits, dim=2)
            self.log_probs = log_p.gather(2, self.actions[..., None]).squeeze(2)
        self.advantages, self.returns = gae(
            self.rewards, self.values, self.dones, last, self.model.gamma,
            self.model.gae_lambda)
        sec["rollout_other"] += clock() - t0
        return going

    def _update(self) -> None:
        import torch

        t0 = time.perf_counter()
        # SB3's progress and schedule (train._lr_schedule), as PPO.train applies them
        progress_remaining = 1.0 - self.model.num_timesteps / self._total
        for group in self.policy.optimizer.param_groups:
            group["lr"] = self.model.lr_schedule(progress_remaining)
        self._clip = self.model.clip_range(progress_remaining)
        flat = {k: getattr(self, k).reshape(-1, *getattr(self, k).shape[2:])
                for k in ("obs", "actions", "log_probs", "advantages", "returns")}
        n = flat["actions"].shape[0]
        size = self.model.batch_size
        for _ in range(self.model.n_epochs):
            order = torch.randperm(n, generator=self.generator)
            for start in range(0, n, size):  # the last minibatch may be short, as in SB3
                idx = order[start:start + size]
                self._minibatch(*(flat[k][idx] for k in (
                    "obs", "actions", "log_probs", "advantages", "returns")))
        self.seconds["update"] += time.perf_counter() - t0

    def _minibatch(self, obs: Any, actions: Any, old_log_p: Any, adv: Any, ret: Any) -> None:
        """One gradient step, as SB3's ``PPO.train`` takes it on a minibatch."""
        import torch

        ppo = self.model
        logits, values = self._forward(obs)
        log_p_all = torch.log_softmax(logits, dim=1)
        log_p = log_p_all.gather(1, actions[:, None]).squeeze(1)
        entropy = -(log_p_all.exp() * log_p_all).sum(dim=1).mean()
        if ppo.normalize_advantage and len(adv) > 1:
            adv = (adv - adv.mean()) / (adv.std() + 1e-8)
        ratio = torch.exp(log_p - old_log_p)
        clipped = ratio.clamp(1 - self._clip, 1 + self._clip)
        policy_loss = -torch.min(adv * ratio, adv * clipped).mean()
        value_loss = torch.nn.functional.mse_loss(values, ret)
        loss = policy_loss - ppo.ent_coef * entropy + ppo.vf_coef * value_loss
        opt = self.policy.optimizer
        opt.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(self.params, ppo.max_grad_norm, foreach=True)
        opt.step()


__all__ = ["PRECISIONS", "LeanPPO", "gae"]

"""Behaviour cloning from a scripted teacher: a warm start for PPO (``ocplus train --bc``).

PPO from scratch has to discover, by chance, a chain of a dozen right moves before the
first dish is paid; on the hard preset (dirty plates, layout switches, three-ingredient
orders) it never did in the budgets we tried. Imitation gives it that chain: a scripted
teacher (the greedy cook, ``make_controller("greedy", seed)``) plays kitchens, every
cook's observation is recorded with the teacher's action for that cook, and the shared
actor is fitted to those actions by cross-entropy (the critic to the discounted team
returns, so PPO's first advantages are not noise). overcooked_ai ships behaviour-cloned
agents the same way.

DAgger (Ross et al. 2011): after the first round, in which the teacher drives, later
rounds let the learner drive (with probability ``1 - 0.5**round`` per kitchen step) while
the teacher still labels every state, so the data covers the states the learner reaches
by its own mistakes. The data of all rounds is kept and the network refitted each round.
With ``focus`` above 1, a DAgger sample where the learner's own argmax differed from the
teacher's label weighs ``focus`` times as much in the cross-entropy: the states where the
learner goes wrong, which are the ones its dishes depend on, are a small part of the data.

The teacher is passed in as a factory ``seed -> Controller`` (the CLI resolves the name),
so this layer imports no controller. Everything a round does is reported (samples, dishes
per episode while collecting, fit accuracy) and written to ``OUT/train.json``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError
from ..sim.rules import Rules
from ..sim.state import new_state
from ..sim.step import transition
from .obs import make_encoder
from .policy import LoadedPolicy
from .shaping import RewardShaper, Shaping

#: a factory of teacher controllers (``seed -> Controller``; the controller API of agents/)
Teacher = Callable[[int], Any]


@dataclass(frozen=True)
class Imitation:
    """How much to imitate: ``steps`` kitchen steps of data per round, ``rounds`` rounds
    (round 0 driven by the teacher, later ones mostly by the learner), ``epochs`` passes
    over all data so far after each round."""

    steps: int
    rounds: int = 1
    epochs: int = 8
    batch_size: int = 1024
    learning_rate: float = 1e-3
    vf_coef: float = 0.5
    #: cross-entropy weight of a DAgger sample where the learner's argmax was not the label
    focus: float = 1.0

    def validate(self) -> None:
        for name in ("steps", "rounds", "epochs", "batch_size"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise ConfigError(f"bc {name} must be a positive integer, got {v!r}")
        if self.learning_rate <= 0:
            raise ConfigError(f"bc learning rate must be positive, got {self.learning_rate}")
        if not 1.0 <= self.focus <= 100.0:
            raise ConfigError(f"bc focus must be between 1 and 100, got {self.focus}")


@dataclass
class Dataset:
    """Recorded samples: one row per cook per kitchen step (observations kept as float16:
    a grid observation of the hard kitchen has 2,300 values; the fit converts batches)."""

    obs: list[np.ndarray]
    actions: list[np.ndarray]
    returns: list[np.ndarray]
    #: per sample: whether the learner's argmax differed from the label (False: no learner)
    missed: list[np.ndarray] = field(default_factory=list)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.concatenate(self.obs), np.concatenate(self.actions),
                np.concatenate(self.returns))

    def weights(self, focus: float) -> np.ndarray:
        """Per sample cross-entropy weight: ``focus`` where the learner missed, else 1."""
        missed = (np.concatenate(self.missed) if self.missed
                  else np.zeros(sum(len(a) for a in self.actions), bool))
        return np.where(missed, np.float32(focus), np.float32(1.0))


def discounted(rewards: np.ndarray, gamma: float) -> np.ndarray:
    """Discounted returns of one episode's ``(steps, agents)`` rewards (0 after its end,
    as the training env reports the horizon as a terminal step)."""
    out = np.zeros_like(rewards)
    acc = np.zeros(rewards.shape[1:], rewards.dtype)
    for t in range(len(rewards) - 1, -1, -1):
        acc = rewards[t] + gamma * acc
        out[t] = acc
    return out


def collect(rules: Rules | Sequence[Rules], obs_kind: str, obs_radius: int, teacher: Teacher, steps: int,
            seed: int, *, learner: LoadedPolicy | None = None, beta: float = 1.0,
            gamma: float = 0.99, reward_scale: float = 0.02,
            team_reward: bool = True, judge: bool = False) -> tuple[Dataset, list[int]]:
    """Play whole episodes until ``steps`` kitchen steps are recorded; each step the
    teacher labels every cook, and the teacher's (probability ``beta``) or the learner's
    sampled actions are played; with a list of rule sets (a kitchen distribution) each
    episode plays one drawn uniformly. Returns the data and the dishes of each episode. The
    reward behind the returns is the one PPO trains on once the shaping is 0 (true game
    reward, the team's sum when ``team_reward``, times ``reward_scale``). With ``judge`` (and a
    learner) each sample also records whether the learner's argmax missed the label."""
    pool = [rules] if isinstance(rules, Rules) else list(rules)
    encoders: dict[int, Any] = {}
    rng = np.random.default_rng([seed, 7])
    data = Dataset([], [], [], [])
    judge = judge and learner is not None
    dishes: list[int] = []
    shaper = RewardShaper(Shaping())
    done_steps, episode = 0, 0
    while done_steps < steps:
        kitchen = pool[int(rng.integers(len(pool)))] if len(pool) > 1 else pool[0]
        encoder = encoders.get(id(kitchen))
        if encoder is None:
            encoder = encoders[id(kitchen)] = make_encoder(obs_kind, kitchen, obs_radius)
        state = new_state(kitchen, seed * 1_000_003 + episode)
        ctrl = teacher(seed + episode)
        ctrl.reset(state)
        shaper.reset(state)
        ep_obs, ep_act, ep_rew, ep_miss = [], [], [], []
        while not state.done:
            obs = encoder.encode_all(state)
            label = ctrl.act(state)
            played = label
            if judge:
                ep_miss.append(learner.probs(obs).argmax(axis=1) != np.asarray(label))
            if learner is not None and rng.random() >= beta:
                played = learner.act(obs, rng)
            result = transition(state, played)
            ctrl.observe(state, result.events)
            true, _ = shaper.step(state, result.events, result.rewards)
            reward = [sum(true)] * len(true) if team_reward else list(true)
            ep_obs.append(obs)
            ep_act.append(label)
            ep_rew.append(reward)
        rewards = np.asarray(ep_rew, np.float32) * reward_scale
        data.obs.append(np.concatenate(ep_obs).astype(np.float16))
        data.actions.append(np.asarray(ep_act, np.int64).reshape(-1))
        data.returns.append(discounted(rewards, gamma).reshape(-1))
        data.missed.append(np.concatenate(ep_miss) if judge
                           else np.zeros(len(data.actions[-1]), bool))
        dishes.append(int(state.stats["dishes_served"]))
        done_steps += state.t
        episode += 1
    return data, dishes


def fit(policy: Any, data: Dataset, cfg: Imitation, seed: int) -> dict[str, float]:
    """Fit an SB3 ``ActorCriticPolicy``: cross-entropy on the teacher's actions plus
    ``vf_coef`` x the squared error of the value on the returns. Returns the last epoch's
    mean losses and the actor's accuracy on the data (argmax = teacher's action)."""
    import torch

    obs, actions, returns = (torch.as_tensor(a) for a in data.arrays())
    weights = torch.as_tensor(data.weights(cfg.focus))
    n = len(obs)
    opt = torch.optim.Adam(policy.parameters(), lr=cfg.learning_rate)
    gen = torch.Generator().manual_seed(seed)
    policy.set_training_mode(True)
    ce = vf = 0.0
    for _ in range(cfg.epochs):
        perm = torch.randperm(n, generator=gen)
        ce_sum = vf_sum = 0.0
        for lo in range(0, n, cfg.batch_size):
            idx = perm[lo:lo + cfg.batch_size]
            values, log_prob, _ = policy.evaluate_actions(obs[idx].float(), actions[idx])
            if cfg.focus == 1.0:
                loss_pi = -log_prob.mean()
            else:
                w = weights[idx]
                loss_pi = -(w * log_prob).sum() / w.sum()
            loss_vf = torch.nn.functional.mse_loss(values.flatten(), returns[idx])
            opt.zero_grad()
            (loss_pi + cfg.vf_coef * loss_vf).backward()
            torch.nn.utils.clip_grad_norm_(policy.parameters(), 0.5)
            opt.step()
            ce_sum += loss_pi.item() * len(idx)
            vf_sum += loss_vf.item() * len(idx)
        ce, vf = ce_sum / n, vf_sum / n
    policy.set_training_mode(False)
    with torch.no_grad():
        hits = 0
        for lo in range(0, n, 8192):
            dist = policy.get_distribution(obs[lo:lo + 8192].float())
            hits += int((dist.distribution.probs.argmax(1) == actions[lo:lo + 8192]).sum())
    return {"cross_entropy": round(ce, 4), "value_mse": round(vf, 5),
            "accuracy": round(hits / n, 4)}


def pretrain(model: Any, rules: Rules | Sequence[Rules], obs_kind: str, obs_radius: int, teacher: Teacher,
             cfg: Imitation, *, seed: int, gamma: float, reward_scale: float,
             team_reward: bool) -> list[dict[str, Any]]:
    """Behaviour-clone ``teacher`` into ``model.policy`` (an SB3 PPO model), DAgger rounds
    as described in the module doc; returns one report per round."""
    cfg.validate()
    data = Dataset([], [], [], [])
    learner = LoadedPolicy(Path("<training>"), {}, model)
    reports = []
    for rnd in range(cfg.rounds):
        beta = 0.5 ** rnd
        part, dishes = collect(
            rules, obs_kind, obs_radius, teacher, cfg.steps, seed + 7919 * rnd,
            learner=learner if rnd else None, beta=beta, gamma=gamma,
            reward_scale=reward_scale, team_reward=team_reward, judge=cfg.focus != 1.0,
        )
        missed = float(np.concatenate(part.missed).mean()) if rnd and cfg.focus != 1.0 else None
        for name in ("obs", "actions", "returns", "missed"):
            getattr(data, name).extend(getattr(part, name))
        stats = fit(model.policy, data, cfg, seed + rnd)
        reports.append({"round": rnd, "teacher_share": beta,
                        "samples": int(sum(len(a) for a in data.actions)),
                        "episodes": len(dishes),
                        "dishes_per_episode_collecting": round(float(np.mean(dishes)), 3),
                        **({} if missed is None else {"learner_missed": round(missed, 4)}),
                        **stats})
    return reports


__all__ = ["Dataset", "Imitation", "Teacher", "collect", "discounted", "fit", "pretrain"]

"""The advantages of the JAX trainer: GAE over the rules' reward plus the potential
shaping, the critic's targets its returns; ``PPOConfig.shaping_bonus`` adds that weight of
the shaping's own GAE with a value of 0, which a critic that has learned the potential
cannot cancel."""

from __future__ import annotations

import json

import numpy as np
import pytest

jax = pytest.importorskip("jax", reason="jax is not installed (the 'jax' extra)")
import jax.numpy as jnp  # noqa: E402

from ocplus_plan.rl.fast.jax_ppo import PPOConfig, _advantages  # noqa: E402

CONFIG = PPOConfig(gamma=0.9, gae_lambda=0.5, reward_scale=1.0, shaping_bonus=0.0)
# one kitchen, one cook, three steps, no episode end: values (steps, kitchens, cooks),
# rewards and ends (steps, kitchens)
VALUES = jnp.array([0.5, 1.0, 2.0]).reshape(3, 1, 1)
REWARD = jnp.array([[0.0], [0.0], [1.0]])
SHAPED = jnp.array([[0.3], [0.2], [-0.4]])
DONES = jnp.zeros((3, 1))
LAST = jnp.array([[0.25]])
ZEROS = jnp.zeros((3, 1, 1))


def _flat(a) -> np.ndarray:
    return np.asarray(a).reshape(-1)


def _by_hand(values, rewards, last, gamma=0.9, lam=0.5):
    """GAE written out: delta_t = r_t + gamma V_t+1 - V_t, A_t = delta_t + gamma lam A_t+1."""
    nxt = list(values[1:]) + [last]
    adv, out = 0.0, []
    for v, r, n in reversed(list(zip(values, rewards, nxt))):
        adv = r + gamma * n - v + gamma * lam * adv
        out.append(adv)
    return np.array(out[::-1])


def test_without_a_bonus_the_advantages_are_gae_over_the_reward_plus_the_shaping():
    adv, ret = _advantages(CONFIG, VALUES, REWARD, SHAPED, DONES, LAST)
    want = _by_hand([0.5, 1.0, 2.0], [0.3, 0.2, 0.6], 0.25)
    np.testing.assert_allclose(_flat(adv), want, rtol=1e-6)
    np.testing.assert_allclose(np.asarray(ret), np.asarray(adv) + np.asarray(VALUES))


def test_the_bonus_adds_the_shapings_own_gae_and_leaves_the_critics_targets():
    plain_adv, plain_ret = _advantages(CONFIG, VALUES, REWARD, SHAPED, DONES, LAST)
    adv, ret = _advantages(CONFIG._replace(shaping_bonus=0.5), VALUES, REWARD, SHAPED,
                           DONES, LAST)
    np.testing.assert_allclose(np.asarray(ret), np.asarray(plain_ret))
    bonus = _by_hand([0.0, 0.0, 0.0], [0.3, 0.2, -0.4], 0.0)  # the shaping, no baseline
    np.testing.assert_allclose(_flat(adv), _flat(plain_adv) + 0.5 * bonus, rtol=1e-6)


def test_a_critic_that_has_learned_the_potential_does_not_cancel_the_bonus():
    # phi rises 0 -> 1 -> 2 -> 3 along the rollout (gamma 1, so F = phi' - phi = 1 a
    # step); the rules pay nothing. A critic of the shaped returns has learned V = -phi
    # (plus a constant): the plain advantages are then 0 at every step.
    config = CONFIG._replace(gamma=1.0, gae_lambda=1.0)
    phi = jnp.array([0.0, 1.0, 2.0]).reshape(3, 1, 1)
    shaped, reward = jnp.ones((3, 1)), jnp.zeros((3, 1))
    adv, _ = _advantages(config, -phi, reward, shaped, DONES, jnp.array([[-3.0]]))
    np.testing.assert_allclose(np.asarray(adv), 0.0, atol=1e-6)
    adv, _ = _advantages(config._replace(shaping_bonus=1.0), -phi, reward, shaped, DONES,
                         jnp.array([[-3.0]]))
    np.testing.assert_allclose(_flat(adv), [3.0, 2.0, 1.0])  # the rise ahead


def test_an_episode_end_stops_the_bonus():
    config = CONFIG._replace(gamma=1.0, gae_lambda=1.0, shaping_bonus=1.0)
    dones = jnp.array([[0.0], [1.0], [0.0]])
    args = (ZEROS, jnp.zeros((3, 1)), jnp.ones((3, 1)), dones, jnp.array([[0.0]]))
    plain, _ = _advantages(config._replace(shaping_bonus=0.0), *args)
    adv, _ = _advantages(config, *args)
    np.testing.assert_allclose(_flat(adv) - _flat(plain), [2.0, 1.0, 1.0])


def test_ocplus_train_passes_the_bonus_to_the_jax_trainer_only(tmp_path, capsys):
    from ocplus_plan.cli import main

    base = ["train", "--preset", "easy", "--timesteps", "32", "--n-kitchens", "2",
            "--n-steps", "4", "--n-epochs", "1", "--hidden", "8,8", "--obs-radius", "1",
            "--quiet"]
    assert main(base + ["--engine", "jax", "--shaping-bonus", "0.25",
                        "--out", str(tmp_path / "a")]) == 0
    summary = json.loads((tmp_path / "a" / "train.json").read_text())
    assert summary["config"]["shaping_bonus"] == 0.25
    assert main(base + ["--engine", "loop", "--shaping-bonus", "0.25",
                        "--out", str(tmp_path / "b")]) == 2
    assert "--shaping-bonus is an option of --engine jax" in capsys.readouterr().err
    assert not (tmp_path / "b").exists()
    assert main(base + ["--engine", "jax", "--shaping-bonus", "-1",
                        "--out", str(tmp_path / "c")]) == 2
    assert "--shaping-bonus" in capsys.readouterr().err

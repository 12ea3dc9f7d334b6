"""The batched engine's features and shaping are the loop engine's, bit for bit: a
differential property test steps a :class:`BatchSim` with :class:`BatchFeatures` beside one
reference state per kitchen (``transition``, :class:`FeatureEncoder`, :class:`RewardShaper`)
with the same seeds and actions and compares every agent's features and training reward at
every step (every preset, generated kitchens with drawn process records and menus, resets,
layout switches, one to three cooks), compiled and in plain Python, through the shared
harness ``eval.mirrors.check_mirror``; and the trainer's vec env gives the same observations,
rewards and episode ends on both engines."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ocplus_plan.eval.mirrors import check_mirror
from ocplus_plan.rl.fast import features_kernels as fk
from ocplus_plan.rl.features import FeatureEncoder
from ocplus_plan.rl.fast.features_batch import BatchFeatures
from ocplus_plan.rl.shaping import Shaping
from ocplus_plan.sim import make_rules
from ocplus_plan.sim.fast.batch import BatchSim, numba_available
from tests.sim.fast.test_batch import QUICK, kitchens

needs_numba = pytest.mark.skipif(not numba_available(),
                                 reason="numba is not installed (the 'fast' extra)")
TERMS = ("subtask_scale", "stage", "useful_plate", "carry_fresh", "carry_ready", "carry_dish")


@st.composite
def shaped_kitchens(draw):
    rules, _radius, seed = draw(kitchens())
    if rules.preset == "hard" and draw(st.booleans()):
        rules = make_rules("hard", n_agents=3, **QUICK, horizon=rules.horizon)
    weights = draw(st.sampled_from([{}, {"stage": 0.3, "carry_dish": 2.5, "carry_ready": 0.7},
                                    {"subtask_scale": 0.1, "useful_plate": 0.0}]))
    return rules, seed, Shaping(**weights), draw(st.booleans())


@needs_numba
@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shaped_kitchens())
def test_compiled_features_and_shaping_are_the_loop_engines(kitchen):
    rules, seed, shaping, team = kitchen
    check_mirror("features", [rules], steps=45, seed=seed, n_envs=3, shaping=shaping, team=team)


@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shaped_kitchens())
def test_plain_python_features_and_shaping_are_the_loop_engines(kitchen):
    rules, seed, shaping, team = kitchen
    check_mirror("features-kernels", [rules], steps=30, seed=seed, n_envs=2, shaping=shaping,
                 team=team)


@pytest.mark.parametrize("term", TERMS)
def test_the_differential_run_pays_every_shaping_term(term: str):
    """Not vacuous: with only ``term`` weighted, the cooks earn some of it."""
    rules = make_rules("hard", **dict(QUICK, horizon=100))
    only = Shaping(**{t: (1.0 if t == term else 0.0) for t in TERMS})
    mirror = "features" if numba_available() else "features-kernels"
    assert check_mirror(mirror, [rules], steps=100, seed=1, n_envs=3, shaping=only,
                        noise=0.1)["shaped"] > 0


def test_kernel_feature_offsets_follow_the_feature_names():
    names = FeatureEncoder(make_rules("hard")).feature_names()
    assert len(names) == fk.N_FEATURES == BatchFeatures.size
    expected = {fk.F_HAND: "hand:empty", fk.F_HAND_PLATE: "hand_plate:has_tomato",
                fk.F_NEAR_PLATE: "near_plate:has_tomato", fk.F_ORDERS: "order0:tomato",
                fk.F_DEMAND: "demand:tomato", fk.F_ADJ: "adj_right:walkable",
                fk.F_OTHERS: "other0:drow", fk.F_CLOCK: "time",
                6 * fk.T_WANTED_READY: "wanted_ready:go_right"}
    assert {i: names[i] for i in expected} == expected


def _same_steps(loop, batch, steps: int, rng: np.random.Generator, t0: int = 0) -> None:
    """Step both vec envs with the same actions; assert the same bits out."""
    for t in range(t0, t0 + steps):
        loop.shaping_coef = batch.shaping_coef = 1.0 - t / 100
        actions = rng.integers(0, 5, size=loop.num_envs)
        for env in (loop, batch):
            env.step_async(actions)
        (o1, r1, d1, i1), (o2, r2, d2, i2) = loop.step_wait(), batch.step_wait()
        assert (o1.tobytes(), r1.tobytes(), d1.tolist()) == (o2.tobytes(), r2.tobytes(),
                                                             d2.tolist())
        for a, b in zip(i1, i2):
            if "terminal_observation" in a:
                assert a["terminal_observation"].tobytes() == b["terminal_observation"].tobytes()
    keys = ("kitchen", "rules", "seed", "steps", "dishes", "train_return")
    assert [[f[k] for k in keys] for f in loop.finished] == \
        [[f[k] for k in keys] for f in batch.finished]


@pytest.mark.parametrize("obs", ["features", "grid"])
def test_trainer_vec_env_is_the_same_on_both_engines(obs: str):
    from ocplus_plan.rl.vec_env import KitchenVecEnv

    rules = make_rules("hard", n_agents=2, reward_mode="individual", **dict(QUICK, horizon=25))
    loop, batch = (KitchenVecEnv(rules, n_kitchens=3, seed=5, obs=obs, engine=engine)
                   for engine in ("loop", "batch"))
    assert loop.reset().tobytes() == batch.reset().tobytes()
    _same_steps(loop, batch, 55, np.random.default_rng(0))  # two resets
    assert len(batch.finished) == 6


def test_a_curriculum_is_the_same_on_both_engines():
    """Several rule sets (kitchen j plays rules[j % 2]), then a switch to one of them that
    kitchens pick up at their next reset, as the trainer's curriculum does."""
    from ocplus_plan.rl.vec_env import KitchenVecEnv

    quick = dict(QUICK, horizon=12, reward_mode="individual", n_agents=2)
    stages = [make_rules("medium", **quick), make_rules("hard", **quick)]
    loop, batch = (KitchenVecEnv(stages, n_kitchens=3, seed=2, engine=engine)
                   for engine in ("loop", "batch"))
    assert loop.reset().tobytes() == batch.reset().tobytes()
    rng = np.random.default_rng(1)
    _same_steps(loop, batch, 18, rng)
    for env in (loop, batch):
        env.set_rules(stages[1])
    _same_steps(loop, batch, 30, rng, t0=18)
    assert {f["preset"] for f in batch.finished[-3:]} == {"hard"}


def test_trainer_picks_the_batch_engine_when_it_can():
    from ocplus_plan.rl.train import TrainConfig

    fast = "batch" if numba_available() else "loop"
    assert TrainConfig().engine == TrainConfig(curriculum=("easy",)).engine == fast
    assert TrainConfig(engine="loop").engine == "loop"


def test_a_trainer_kitchen_holds_a_few_kib_with_its_observations():
    rules = make_rules("hard", n_agents=2)
    sim = BatchSim(rules, 8, compiled=False, observe=False)
    feats = BatchFeatures(sim)
    held = sim.memory_per_kitchen() + feats.memory_per_kitchen()
    assert feats.obs.nbytes // 8 == 2 * fk.N_FEATURES * 4 < held < 4096

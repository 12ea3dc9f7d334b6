"""Learner interface: Gymnasium envs (registered here) and a PettingZoo ParallelEnv.

``import ocplus_plan.env`` registers ``OvercookedPlus-v0``, ``Overcooked-Plus`` (the
paper's name) and ``OvercookedPlusSingle-v0`` with Gymnasium (string entry points, so
nothing heavy is imported until ``gymnasium.make``)::

    import gymnasium as gym
    import ocplus_plan.env  # noqa: F401  (registers the ids)
    env = gym.make("OvercookedPlus-v0", preset="hard", n_agent=2, obs_radius=2)
    obs, info = env.reset(seed=0)
    kitchens = gym.make_vec("OvercookedPlus-v0", num_envs=1024,
                            vectorization_mode="vector_entry_point", preset="hard")

``parallel_env(...)`` returns the PettingZoo view (needs pettingzoo). This package
never imports unified_planning, pygame, torch or matplotlib.
"""

from __future__ import annotations

from typing import Any

import gymnasium

from .core import MODES, EnvConfig, parse_env_kwargs

#: id -> (entry point, default kwargs): the registered configurations
REGISTRY: dict[str, tuple[str, dict[str, Any]]] = {
    "OvercookedPlus-v0": ("ocplus_plan.env.gym_env:OvercookedPlusEnv", {"preset": "hard"}),
    # the paper's id: its constructor's defaults and map-driven preset (env/paper.py)
    "Overcooked-Plus": ("ocplus_plan.env.gym_env:make_paper_env", {}),
    "OvercookedPlusSingle-v0": (
        "ocplus_plan.env.gym_env:OvercookedPlusSingleEnv", {"preset": "hard"},
    ),
}


#: ids whose ``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`` steps all
#: kitchens in the batched engine (:mod:`ocplus_plan.env.vector_env`)
VECTOR_ENTRY_POINT = "ocplus_plan.env.vector_env:OvercookedPlusVectorEnv"
VECTOR_IDS = ("OvercookedPlus-v0", "Overcooked-Plus")


def register_envs() -> None:
    """Register every id of :data:`REGISTRY` with Gymnasium (idempotent)."""
    for env_id, (entry_point, kwargs) in REGISTRY.items():
        if env_id not in gymnasium.registry:
            vector = VECTOR_ENTRY_POINT if env_id in VECTOR_IDS else None
            gymnasium.register(env_id, entry_point=entry_point, kwargs=dict(kwargs),
                               vector_entry_point=vector,
                               # per-cook rewards are not the scalar the passive checker wants
                               disable_env_checker=env_id == "Overcooked-Plus")


def parallel_env(preset: str = "hard", **kwargs: Any) -> Any:
    """The PettingZoo ``ParallelEnv`` (same keywords as the Gymnasium env)."""
    from .parallel import OvercookedPlusParallelEnv  # pettingzoo is optional

    return OvercookedPlusParallelEnv(preset, **kwargs)


def make_jax_env(preset: str = "hard", *, reward_scope: str = "team", checked: bool = False,
                 sparse_reward: bool = False, **kwargs: Any) -> Any:
    """The kitchen in JAX behind JaxMARL's ``MultiAgentEnv`` interface (the ``jax`` extra),
    from the Gymnasium env's keywords (:class:`ocplus_plan.sim.fast.jax_env.JaxKitchenEnv`).
    ``checked=True`` checks every action on the host before the jitted step (a debugging
    mode: an integer outside 0..4 is then refused instead of acting as stay);
    ``sparse_reward=True`` leaves the subtask part, ``infos["shaped_reward"]``, out of the
    rewards."""
    from ..sim.fast.jax_env import JaxKitchenEnv  # needs jax: DependencyNotInstalled names the extra

    rules, config = parse_env_kwargs(preset, **kwargs)
    return JaxKitchenEnv.from_options(
        rules, mode=config.mode, obs_radius=config.obs_radius, comm=config.comm,
        render_mode=config.render_mode, reward_scope=reward_scope, checked=checked,
        sparse_reward=sparse_reward)


def __getattr__(name: str) -> Any:
    # lazy access to the env classes without importing them at package import
    if name in ("OvercookedPlusEnv", "OvercookedPlusSingleEnv", "StateSpace"):
        from . import gym_env

        return getattr(gym_env, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


register_envs()

__all__ = [
    "MODES",
    "REGISTRY",
    "EnvConfig",
    "OvercookedPlusEnv",
    "OvercookedPlusSingleEnv",
    "make_jax_env",
    "parallel_env",
    "parse_env_kwargs",
    "register_envs",
]

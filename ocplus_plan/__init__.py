"""ocplus-plan: a symbolic-planning benchmark on an Overcooked-style cooking simulator.

Importing the package registers the Gymnasium ids (``OvercookedPlus-v0``,
``Overcooked-Plus``, ``OvercookedPlusSingle-v0``), as Minigrid or ALE do, so both of these
work::

    import gymnasium, ocplus_plan
    env = gymnasium.make("OvercookedPlus-v0", preset="hard")
    env = gymnasium.make("ocplus_plan:OvercookedPlus-v0")   # in a fresh interpreter

``create_env`` is the paper's constructor (:mod:`ocplus_plan.env.paper`).
"""

from __future__ import annotations

__version__ = "0.1.0"

from .env import register_envs
from .env.paper import create_env

register_envs()


def make_jax_env(preset: str = "hard", *, reward_scope: str = "team", **kwargs: object) -> object:
    """The kitchen in JAX behind JaxMARL's ``MultiAgentEnv`` interface (the ``jax`` extra),
    from the Gymnasium env's keywords (:class:`ocplus_plan.sim.fast.jax_env.JaxKitchenEnv`)."""
    from .sim.fast.jax_env import JaxKitchenEnv  # needs jax: DependencyNotInstalled names the extra
    from .env.core import parse_env_kwargs

    rules, config = parse_env_kwargs(preset, **kwargs)
    return JaxKitchenEnv.from_options(
        rules, mode=config.mode, obs_radius=config.obs_radius, comm=config.comm,
        render_mode=config.render_mode, reward_scope=reward_scope)


__all__ = ["__version__", "create_env", "make_jax_env", "register_envs"]

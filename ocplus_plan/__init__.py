"""ocplus-plan: a symbolic-planning benchmark on an Overcooked-style cooking simulator.

Importing the package registers the Gymnasium ids (``OvercookedPlus-v0``,
``Overcooked-Plus``, ``OvercookedPlusSingle-v0``), as Minigrid or ALE do, so both of these
work::

    import gymnasium, ocplus_plan
    env = gymnasium.make("OvercookedPlus-v0", preset="hard")
    env = gymnasium.make("ocplus_plan:OvercookedPlus-v0")   # in a fresh interpreter

``create_env`` is the paper's constructor (:mod:`ocplus_plan.env.paper`); ``make_jax_env`` the
kitchen in JAX (the ``jax`` extra, imported when called).
"""

from __future__ import annotations

__version__ = "0.1.0"

from .env import make_jax_env, register_envs
from .env.paper import create_env

register_envs()


__all__ = ["__version__", "create_env", "make_jax_env", "register_envs"]

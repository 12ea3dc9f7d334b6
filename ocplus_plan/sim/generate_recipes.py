"""Drawn recipes: a seeded menu of dishes for a kitchen, so task difficulty is set by
recipe length and station count as well as by the layout.

:func:`draw_recipes` draws ``count`` distinct recipes of the given lengths from those a
layout can make (its spawn tiles and process stations, as
:func:`.rules.recipe_pool` decides) with a generator seeded by ``seed``: the same kitchen,
seed and lengths give the same menu. Pass the menu to :func:`.rules.make_rules` as
``recipes`` (SPEC section 4: an order's recipe is drawn from it)::

    layout = load_kitchen("gen:open:train:0:medium")
    rules = make_rules("medium", map=layout, recipes=draw_recipes(layout, 7, (3,), 2))

:func:`draw_dishes` draws the same menu as dish records (:mod:`.dishes`), which a kitchen
file declares under ``recipes:`` (``ocplus generate --recipes LENGTHS --menu N`` writes them
into each generated kitchen, so the file carries its menu).
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from .dishes import Dish, dish_of
from .maps import Layout
from .processes import PROCESSES
from .rules import parse_recipe, recipe_name, recipe_pool

#: the longest recipe a menu may ask for (a plate holds at most this many ingredients in
#: the planning model's contents)
MAX_LENGTH = 6


def draw_recipes(layout: Layout, seed: int, lengths: tuple[int, ...] = (1, 2, 3),
                 count: int = 3, steak: str = "allowed") -> list[str]:
    """``count`` distinct recipe names (``"steak+tomato"``) of the given ``lengths`` that
    ``layout`` can make, drawn with ``numpy.random.default_rng(seed)``; fewer when the
    kitchen can make fewer. ``steak``: ``never``, ``required`` (exactly one) or
    ``allowed``."""
    if not lengths or any(isinstance(n, bool) or not isinstance(n, int)
                          or not 1 <= n <= MAX_LENGTH for n in lengths):
        raise ConfigError(f"recipe lengths must be integers from 1 to {MAX_LENGTH}, "
                          f"got {lengths!r}")
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ConfigError(f"count must be a positive integer, got {count!r}")
    if steak not in ("never", "required", "allowed"):
        raise ConfigError(f"steak must be never, required or allowed, got {steak!r}")
    pool = recipe_pool(layout, tuple(sorted(set(lengths))), steak)
    if not pool:
        raise ConfigError(f"kitchen {layout.name!r} can make no recipe of length "
                          f"{sorted(set(lengths))}; draw shorter recipes or use a kitchen "
                          "with more spawn tiles and stations")
    rng = np.random.default_rng(seed)
    picks = rng.choice(len(pool), size=min(count, len(pool)), replace=False)
    return [recipe_name(pool[int(i)]) for i in sorted(picks)]


def draw_dishes(layout: Layout, seed: int, lengths: tuple[int, ...] = (1, 2, 3),
                count: int = 3, steak: str = "allowed",
                reward: float | None = None) -> tuple[Dish, ...]:
    """The menu of :func:`draw_recipes` as dish records, each ingredient in the state the
    kitchen's process records make, each earning ``reward`` (None: ``correct_delivery``)."""
    procs = layout.processes or PROCESSES
    return tuple(dish_of(parse_recipe(name), procs, reward)
                 for name in draw_recipes(layout, seed, lengths, count, steak))


__all__ = ["MAX_LENGTH", "draw_dishes", "draw_recipes"]

"""One record per recipe (a dish): its ingredients with their required states, its plate and
its reward, and a kitchen file's ``recipes:`` read into them (SPEC section 4).

A :class:`Dish` is what an order asks for. Its ingredients are item kinds, each in the state
the kitchen's process records make (a plate takes an ingredient only in that state:
``chopped`` tomato, ``cooked`` steak); its plate is the item kind it is served on; its
reward is what serving it earns (None: the rule set's ``correct_delivery``). The presets'
recipe pools are dishes of the default reward (:meth:`.rules.Rules.dishes`), so a kitchen
file spells the same records: :func:`dish_to_dict` writes one as an entry that
:func:`parse_recipes` reads back into the same record.

An order's identity stays its :data:`Recipe` (the sorted ingredient kinds): the engines
match a served plate against it and read the dish's reward from a table by recipe index.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..errors import MapFormatError
from .codes import ITEM_NAMES, Cell, Item, ItemState
from .process_yaml import check_entry
from .processes import Process, ready_state

Recipe = tuple[Item, ...]  # sorted multiset of ingredient kinds, each to be processed

#: at most this many dishes in a kitchen file
MAX_RECIPES = 32
#: at most this many ingredients on one plate (the planning model's plate contents)
MAX_INGREDIENTS = 6
#: the largest reward a dish may give, either sign
MAX_REWARD = 1e6
KEYS = ("ingredients", "plate", "reward")
#: the item kinds a dish may be served on
PLATES = {"plate": Item.PLATE}
_STATES = {**{s.name.lower(): s for s in ItemState}, "raw": ItemState.RAW}


@dataclass(frozen=True)
class Dish:
    """The record of one recipe."""

    #: (item kind, required state) per ingredient, sorted by kind (a multiset)
    ingredients: tuple[tuple[Item, ItemState], ...]
    plate: Item = Item.PLATE
    #: what serving it earns; None: the rule set's ``correct_delivery``
    reward: float | None = None

    @property
    def recipe(self) -> Recipe:
        """The order's identity: the sorted ingredient kinds."""
        return tuple(k for k, _ in self.ingredients)


def dish_of(recipe: Recipe, processes: tuple[Process, ...], reward: float | None = None) -> Dish:
    """The record of ``recipe`` under ``processes``: each ingredient in the state its process
    makes (a kind no process takes keeps ``fresh``)."""
    ready = ready_state(processes)
    return Dish(tuple((k, ready.get(k, ItemState.FRESH)) for k in sorted(recipe)),
                Item.PLATE, reward)


def dish_to_dict(d: Dish) -> dict[str, Any]:
    """A record as a kitchen file's ``recipes`` entry."""
    out: dict[str, Any] = {
        "ingredients": [{k.name.lower(): s.name.lower()} for k, s in d.ingredients],
        "plate": d.plate.name.lower()}
    if d.reward is not None:
        out["reward"] = d.reward
    return out


def parse_recipes(value: Any, src: str, processes: tuple[Process, ...],
                  stations: dict[int, Any]) -> tuple[Dish, ...]:
    """A kitchen file's ``recipes``: bounded, known keys, each ingredient a kind in the state
    the kitchen's ``processes`` make, made by a station on the map from its spawn tiles (as
    many as the dish needs), no two dishes alike. Errors name the file, the entry and the
    fix."""
    if not isinstance(value, list) or not value or len(value) > MAX_RECIPES:
        raise MapFormatError(f"{src}: 'recipes' must be a list of 1 to {MAX_RECIPES} dishes "
                             "(mappings such as {ingredients: [{steak: cooked}, "
                             "{tomato: chopped}], reward: 250})")
    ready = ready_state(processes)
    makers = {k: p.station for p in processes for k in p.takes}
    out: list[Dish] = []
    for n, entry in enumerate(value):
        where = f"{src}: recipes[{n}]"
        dish = _dish(entry, where, ready)
        for kind in sorted(set(dish.recipe)):
            _check_makeable(kind, dish.recipe.count(kind), makers, stations, where)
        if any(d.recipe == dish.recipe for d in out):
            raise MapFormatError(f"{where} has the same ingredients as an earlier dish; "
                                 "give each dish other ingredients, or keep one")
        out.append(dish)
    return tuple(out)


def _dish(entry: Any, where: str, ready: dict[Item, ItemState]) -> Dish:
    check_entry(entry, where, "{ingredients: [{steak: cooked}, {tomato: chopped}], plate: "
                "plate, reward: 250}", KEYS)
    parts = entry.get("ingredients")
    if not isinstance(parts, list) or not 1 <= len(parts) <= MAX_INGREDIENTS:
        raise MapFormatError(f"{where}: 'ingredients' must be a list of 1 to {MAX_INGREDIENTS} "
                             "one-key mappings kind: state, such as [{steak: cooked}]")
    pairs = sorted(_ingredient(x, where, ready) for x in parts)
    plate = entry.get("plate", "plate")
    if not isinstance(plate, str) or plate.strip().lower() not in PLATES:
        raise MapFormatError(f"{where}: plate {str(plate)[:40]!r} is not one of "
                             f"{', '.join(PLATES)}")
    reward = entry.get("reward")
    if reward is not None and (isinstance(reward, bool) or not isinstance(reward, (int, float))
                               or abs(reward) > MAX_REWARD or not math.isfinite(reward)):
        raise MapFormatError(f"{where}: 'reward' must be a number from {-MAX_REWARD:g} to "
                             f"{MAX_REWARD:g}, got {str(reward)[:40]!r}")
    return Dish(tuple(pairs), PLATES[plate.strip().lower()],
                None if reward is None else float(reward))


def _ingredient(x: Any, where: str, ready: dict[Item, ItemState]) -> tuple[Item, ItemState]:
    if not isinstance(x, dict) or len(x) != 1:
        raise MapFormatError(f"{where}: each ingredient is a one-key mapping kind: state, "
                             f"such as {{tomato: chopped}}, got {str(x)[:40]!r}")
    (name, state), = x.items()
    key = name.strip().lower() if isinstance(name, str) else ""
    if key not in ITEM_NAMES or ITEM_NAMES[key] == Item.PLATE:
        raise MapFormatError(f"{where}: ingredient {str(name)[:40]!r} is not one of "
                             f"{', '.join(k for k in ITEM_NAMES if k != 'plate')}")
    kind = ITEM_NAMES[key]
    if not isinstance(state, str) or state.strip().lower() not in _STATES:
        raise MapFormatError(f"{where}: {key}'s state {str(state)[:40]!r} is not one of "
                             f"{', '.join(_STATES)}")
    need = ready.get(kind)
    if need is None:
        raise MapFormatError(f"{where}: no process station of this kitchen takes {key}; "
                             "add one under 'processes' or drop the ingredient")
    if _STATES[state.strip().lower()] != need:
        raise MapFormatError(f"{where}: {key} must be {need.name.lower()} here (the state its "
                             f"process makes, the only one a plate takes), not "
                             f"{state.strip().lower()}")
    return kind, need


def _check_makeable(kind: Item, count: int, makers: dict[Item, Cell],
                    stations: dict[int, Any], where: str) -> None:
    name, station = kind.name.lower(), makers[kind]
    if not stations.get(int(station)):
        raise MapFormatError(f"{where}: {name} needs a {station.name.lower()} (code "
                             f"{int(station)}) and the map has none; add one or drop {name}")
    spawns = len(stations.get(int(kind), ()))
    if count > spawns:
        raise MapFormatError(f"{where} needs {count} {name} but the map has {spawns} spawn "
                             f"tile(s) for it (code {int(kind)}); add tiles or use fewer")


__all__ = ["Dish", "KEYS", "MAX_INGREDIENTS", "MAX_RECIPES", "MAX_REWARD", "PLATES", "Recipe",
           "dish_of", "dish_to_dict", "parse_recipes"]

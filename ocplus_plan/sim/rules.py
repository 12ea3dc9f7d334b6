"""Rule parameters, rewards, presets and recipe pools (SPEC sections 3, 4, 6, 7).

Everything the transition, the planning compiler and the executive need to know
about the rules of one episode lives in one frozen :class:`Rules` object made by
:func:`make_rules`. Every default is overridable by keyword.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from ..errors import ConfigError, MapFormatError
from .codes import ITEM_NAMES, VEGETABLES, Cell, Item
from .dishes import Dish, Recipe, dish_of
from .kitchens import load_kitchen
from .maps import Layout
from .presets import PRESETS, Preset
from .processes import (
    PROCESSES,
    Process,
    ProcessTables,
    check_processes,
    ingredient_process,
    process_tables,
)


@dataclass(frozen=True)
class Rewards:
    """Reward values, keyed as in the paper's ``rewardList``."""

    subtask_finished: float = 10.0
    correct_delivery: float = 200.0
    wrong_delivery: float = -5.0
    step_penalty: float = -0.1
    burned_penalty: float = -2.0
    order_expired: float = -20.0

    @classmethod
    def from_mapping(cls, values: Mapping[str, float] | Rewards | None) -> Rewards:
        """Rewards from a mapping keyed as here (``correct_delivery``) or as the paper's
        ``rewardList`` (``"correct delivery"``); unlisted keys keep their defaults."""
        if values is None:
            return cls()
        if isinstance(values, Rewards):
            return values
        if not isinstance(values, Mapping):
            raise ConfigError(
                "rewards / rewardList must be a mapping such as {'correct_delivery': 200} or "
                f"{{'correct delivery': 200}}, got {type(values).__name__}"
            )
        given = {reward_key(k): v for k, v in values.items()}
        known = {f.name for f in fields(cls)}
        bad = sorted(set(given) - known)
        if bad:
            raise ConfigError(f"unknown reward key(s) {bad}; known keys: {sorted(known)} "
                              "(the paper's spellings with spaces work too)")
        return cls(**{k: float(v) for k, v in given.items()})


def reward_key(key: object) -> str:
    """``"Correct delivery"`` / ``"correct-delivery"`` -> ``"correct_delivery"``."""
    return str(key).strip().lower().replace(" ", "_").replace("-", "_")


@dataclass(frozen=True)
class Rules:
    """The complete rule set of an episode. Build it with :func:`make_rules`."""

    preset: str
    layout: Layout
    n_agents: int
    recipes: tuple[Recipe, ...]
    chop_steps: int = 3
    cook_time: int = 10
    burn_time: int = 20
    wash_steps: int = 3
    n_orders: int = 2
    horizon: int = 200
    order_time_limit: int | None = None
    stop_after_orders: int | None = None
    dirty_plates: bool = False
    dynamic: bool = False
    map_switch_step: int = 15
    reward_mode: str = "individual"
    rewards: Rewards = field(default_factory=Rewards)
    #: fixed orders (the paper's ``fixed_task``): exactly these are open in every episode,
    #: and a served or expired order is replaced by one with the same recipe
    fixed_orders: tuple[Recipe, ...] | None = None
    #: the process stations' rules (:mod:`.processes`); durations named by a record's
    #: ``duration_param`` / ``overrun_param`` are read from the fields above
    processes: tuple[Process, ...] = PROCESSES

    def __post_init__(self) -> None:
        # the compiled process tables (durations from the fields above): a plain attribute,
        # not a field, so every engine reads them at the cost of an attribute; a rule set
        # whose numbers are not integers gets None here and a ConfigError from the check
        try:
            tables: ProcessTables | None = process_tables(self)
        except (TypeError, ValueError):
            tables = None
        object.__setattr__(self, "tables", tables)
        # the dish record of each recipe (the kitchen file's, else one of the default
        # reward) and what serving it earns, by recipe index: the engines' reward table
        declared = {d.recipe: d for d in self.layout.recipes or ()}
        dishes = tuple(declared.get(r) or dish_of(r, self.processes) for r in self.recipes)
        default = self.rewards.correct_delivery
        object.__setattr__(self, "dishes", dishes)
        object.__setattr__(self, "recipe_rewards", tuple(
            default if d.reward is None else d.reward for d in dishes))
        object.__setattr__(self, "reward_of", dict(zip(self.recipes, self.recipe_rewards)))

    def recipe_name(self, recipe: Recipe) -> str:
        return recipe_name(recipe)


def recipe_name(recipe: Recipe) -> str:
    return "+".join(i.name.lower() for i in recipe)


_RULE_FIELDS = {
    f.name for f in fields(Rules)
    if f.name not in ("preset", "layout", "recipes", "rewards", "fixed_orders", "processes")
}
_OVERRIDES = _RULE_FIELDS | {"map", "rewards", "recipes", "recipe_sizes", "fixed_orders"}
#: the generator seed of ``fixed_orders=True`` (a constant: the same orders in every episode)
FIXED_ORDERS_SEED = 42


def recipe_pool(
    layout: Layout, sizes: tuple[int, ...], steak: str = "allowed"
) -> tuple[Recipe, ...]:
    """All recipes of the given sizes that ``layout`` can make.

    An ingredient appears at most as often as the map has spawn tiles for it, and
    only if the station that processes it is on the map. ``steak`` is ``never``,
    ``required`` (exactly one steak) or ``allowed``.
    """
    supply = {}
    for item, process in sorted(ingredient_process(layout.processes or PROCESSES).items()):
        if layout.cells_of(process.station):
            supply[item] = len(layout.cells_of(Cell(int(item))))
    kinds = sorted(k for k, n in supply.items() if n > 0)
    pool: list[Recipe] = []
    for size in sizes:
        for combo in itertools.combinations_with_replacement(kinds, size):
            if any(combo.count(k) > supply[k] for k in set(combo)):
                continue
            n_steak = combo.count(Item.STEAK)
            if steak == "never" and n_steak:
                continue
            if steak == "required" and n_steak != 1:
                continue
            pool.append(tuple(combo))
    return tuple(pool)


def parse_recipe(spec: Any) -> Recipe:
    """``"tomato+lettuce"`` or ``["tomato", "lettuce"]`` -> a sorted recipe."""
    names = spec.split("+") if isinstance(spec, str) else list(spec)
    items = []
    for n in names:
        key = str(n).strip().lower()
        if key not in ITEM_NAMES or ITEM_NAMES[key] == Item.PLATE:
            raise ConfigError(
                f"recipe {spec!r}: unknown ingredient {n!r}; use tomato, lettuce, onion, steak"
            )
        items.append(ITEM_NAMES[key])
    if not items:
        raise ConfigError(f"recipe {spec!r} is empty")
    return tuple(sorted(items))


def _needed_stations(p: Preset, layout: Layout) -> tuple[Cell, ...]:
    """The stations preset ``p`` needs on ``layout``: a shipped process station whose item
    kinds the kitchen's records give to another station (the pan's steak to an oven) is
    needed as that one."""
    own = layout.processes or PROCESSES
    out: list[Cell] = []
    for c in p.stations:
        kinds = {k for q in PROCESSES if q.station == c for k in q.takes}
        now = [q.station for q in own if kinds & set(q.takes)] if kinds else [c]
        out += [s for s in now if s not in out]
    return tuple(out)


def make_rules(preset: str = "easy", *, map: str | dict | Layout | None = None, **overrides: Any) -> Rules:
    """Rules for a preset, with any parameter overridden by keyword.

    Raises :class:`ConfigError` for an unknown preset or parameter, and for an
    impossible combination (a map without the stations the preset needs, more
    agents than spawn points, an empty recipe pool, ...).
    """
    if preset not in PRESETS:
        raise ConfigError(f"unknown preset {preset!r}; choose one of {', '.join(PRESETS)}")
    p = PRESETS[preset]
    bad = sorted(set(overrides) - _OVERRIDES)
    if bad:
        raise ConfigError(f"unknown rule parameter(s) {bad}; known: {sorted(_OVERRIDES)}")

    try:
        layout = load_kitchen(map if map is not None else p.map)
    except MapFormatError:
        raise
    n_agents = overrides.pop("n_agents", p.n_agents)
    if not isinstance(n_agents, int) or n_agents < 1:
        raise ConfigError(f"n_agents must be a positive integer, got {n_agents!r}")
    if n_agents > layout.max_agents:
        raise ConfigError(_too_many_agents(n_agents, layout))
    dynamic = overrides.pop("dynamic", p.dynamic)
    if dynamic and not layout.is_dynamic:
        why = ("has no switch_map" if layout.switch_grid is None
               else "is marked static (is_dynamic_map / dynamic_map: false)")
        raise ConfigError(
            f"preset {preset!r} wants a dynamic layout but map {layout.name!r} {why}; "
            "use a dynamic map (e.g. mapC) or pass dynamic=False"
        )
    missing = [c.name.lower() for c in _needed_stations(p, layout) if not layout.cells_of(c)]
    dirty = overrides.pop("dirty_plates", p.dirty_plates)
    if dirty and not layout.cells_of(Cell.SINK) and "sink" not in missing:
        missing.append("sink")
    if missing:
        raise ConfigError(
            f"preset {preset!r} needs {', '.join(missing)} but map {layout.name!r} has none; "
            "choose a map that has them"
        )

    overrides_given = set(overrides)
    recipe_sizes = tuple(overrides.pop("recipe_sizes", p.recipe_sizes))
    if "recipes" not in overrides and layout.recipes:  # the kitchen file's own menu
        recipes = tuple(d.recipe for d in layout.recipes)
    elif "recipes" in overrides:
        recipes = tuple(parse_recipe(r) for r in overrides.pop("recipes"))
        can = set(recipe_pool(layout, tuple(sorted({len(r) for r in recipes})), "allowed"))
        for r in recipes:
            if r not in can:
                raise ConfigError(
                    f"recipe {recipe_name(r)!r} cannot be made on map {layout.name!r} "
                    "(missing spawn tiles or stations)"
                )
    else:
        recipes = recipe_pool(layout, recipe_sizes, p.steak)
    if not recipes:
        raise ConfigError(
            f"no recipe of preset {preset!r} can be made on map {layout.name!r}; "
            "it lacks the ingredients or stations the preset's recipes need"
        )

    fixed = overrides.pop("fixed_orders", None)
    if fixed is not None and fixed is not False:
        recipes, fixed = _fixed_orders(fixed, recipes, layout, "recipes" in overrides_given,
                                       overrides)
    else:
        fixed = None
    rewards = Rewards.from_mapping(overrides.pop("rewards", None))
    # a static map may say 0 (the paper's do): then the Rules default stands, unused
    params: dict[str, Any] = (
        {"map_switch_step": layout.map_switch_step} if layout.map_switch_step > 0 else {})
    params.update(overrides)
    if layout.processes is not None:  # the kitchen file's own process records
        params["processes"] = layout.processes
    rules = Rules(
        preset=preset,
        layout=layout,
        n_agents=n_agents,
        recipes=recipes,
        dirty_plates=bool(dirty),
        dynamic=bool(dynamic),
        rewards=rewards,
        fixed_orders=fixed,
        **params,
    )
    _check(rules)
    return rules


def _fixed_orders(
    spec: Any, recipes: tuple[Recipe, ...], layout: Layout, recipes_given: bool,
    overrides: dict[str, Any],
) -> tuple[tuple[Recipe, ...], tuple[Recipe, ...]]:
    """(recipe pool, fixed orders) for ``fixed_orders``: ``True`` draws ``n_orders`` recipes
    once from the pool with a constant seed; a list of recipes names them (and sets
    ``n_orders`` to their number; the pool becomes them unless ``recipes`` is given)."""
    if spec is True:
        n = overrides.get("n_orders", Rules.n_orders)
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ConfigError(f"n_orders must be a positive integer, got {n!r}")
        rng = np.random.default_rng(FIXED_ORDERS_SEED)
        return recipes, tuple(recipes[int(rng.integers(len(recipes)))] for _ in range(n))
    if isinstance(spec, str) or not isinstance(spec, (list, tuple)):
        raise ConfigError(f"fixed_orders must be True or a list of recipes such as "
                          f"['tomato', 'steak+lettuce'], got {spec!r}")
    if not spec:
        raise ConfigError("fixed_orders needs at least one recipe")
    fixed = tuple(parse_recipe(r) for r in spec)
    can = set(recipe_pool(layout, tuple(sorted({len(r) for r in fixed})), "allowed"))
    for r in fixed:
        if r not in can:
            raise ConfigError(f"fixed order {recipe_name(r)!r} cannot be made on map "
                              f"{layout.name!r} (missing spawn tiles or stations)")
        if recipes_given and r not in recipes:
            raise ConfigError(f"fixed order {recipe_name(r)!r} is not among the recipes "
                              f"{[recipe_name(x) for x in recipes]}; add it or drop 'recipes'")
    n = overrides.setdefault("n_orders", len(fixed))
    if n != len(fixed):
        raise ConfigError(f"fixed_orders lists {len(fixed)} orders but n_orders={n!r}; "
                          "give one of them, or make them agree")
    return (recipes if recipes_given else tuple(dict.fromkeys(fixed))), fixed


def _too_many_agents(n_agents: int, layout: Layout) -> str:
    spawns = len(layout.spawn_points)
    why = f"max_n_agent {layout.max_agents}"
    if layout.declared_max_agents > spawns:
        why = f"it has only {spawns} spawn points; max_n_agent {layout.declared_max_agents}"
    return (f"n_agents={n_agents} but map {layout.name!r} allows at most {layout.max_agents} "
            f"cooks ({why}); pick another map or fewer agents")


#: the largest count or time a rule may hold (recordings store them as 32-bit integers)
MAX_RULE_INT = 2**31 - 1
#: open orders at once: the first state draws them all, so a huge count would stall it
MAX_ORDERS = 1000
#: the one table of integer rule limits, (low, high) inclusive: :func:`make_rules`,
#: ``--rules`` and the recordings' reader (``render/replay.py``) all check these
RULE_LIMITS: dict[str, tuple[int, int]] = {
    **{name: (1, MAX_RULE_INT) for name in (
        "chop_steps", "cook_time", "burn_time", "wash_steps", "horizon", "map_switch_step")},
    "n_orders": (1, MAX_ORDERS),
}
#: the same for the rules that may also be None (no limit)
OPTIONAL_RULE_LIMITS: dict[str, tuple[int, int]] = {
    "order_time_limit": (1, MAX_RULE_INT), "stop_after_orders": (1, MAX_RULE_INT)}


def rule_limit_problem(name: str, value: Any) -> str | None:
    """Why ``value`` is not allowed for the integer rule ``name`` (None when it is)."""
    if name in OPTIONAL_RULE_LIMITS:
        if value is None:
            return None
        lo, hi = OPTIONAL_RULE_LIMITS[name]
        kind = "an integer or None"
    else:
        lo, hi = RULE_LIMITS[name]
        kind = "an integer"
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        return f"{name} must be {kind} from {lo} to {hi}, got {value!r}"
    return None


def _check(rules: Rules) -> None:
    for name in (*RULE_LIMITS, *OPTIONAL_RULE_LIMITS):
        problem = rule_limit_problem(name, getattr(rules, name))
        if problem:
            raise ConfigError(problem)
    if rules.burn_time < rules.cook_time:
        raise ConfigError(
            f"burn_time ({rules.burn_time}) must be >= cook_time ({rules.cook_time}), "
            "or a steak would burn before it is cooked"
        )
    if rules.processes is not PROCESSES:
        check_processes(rules.processes, {f.name: getattr(rules, f.name) for f in fields(rules)})
    if rules.reward_mode not in ("individual", "shared"):
        raise ConfigError(f"reward_mode must be 'individual' or 'shared', got {rules.reward_mode!r}")


def with_overrides(rules: Rules, **changes: Any) -> Rules:
    """A copy of ``rules`` with some fields changed (checked again)."""
    new = replace(rules, **changes)
    _check(new)
    return new


__all__ = [
    "MAX_ORDERS",
    "MAX_RULE_INT",
    "OPTIONAL_RULE_LIMITS",
    "PRESETS",
    "Dish",
    "Preset",
    "Recipe",
    "Rewards",
    "RULE_LIMITS",
    "Rules",
    "VEGETABLES",
    "make_rules",
    "parse_recipe",
    "recipe_name",
    "recipe_pool",
    "rule_limit_problem",
    "with_overrides",
]

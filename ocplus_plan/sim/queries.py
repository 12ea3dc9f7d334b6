"""The kitchen's questions, answered once: every layer asks these instead of re-deriving them.

- walking: :func:`walks` / :func:`distances` / :func:`walk_actions` (shortest walks),
  :func:`interaction_spots` (all from :mod:`.grid`, the floor below), :func:`walkable_in_any_layout`,
  :func:`direction`;
- bumps: :func:`bump_effect` (what bumping a cell does) and :func:`bumps_needed` (how many
  chops or washes finish one); the transition dispatches on them, so they are the rule;
- the pan: :func:`ticks_until_cooked`, :func:`ticks_until_burnt` (the transition uses them);
- plates: :func:`is_plateable`, :func:`plate_fits` (can a plate still become a recipe).

Cells are flat indices; ``neighbors[c]`` lists the cells in the directions RIGHT, DOWN,
LEFT, UP (-1 off the grid), so a neighbour's position there is the action that enters it.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass
from enum import IntEnum
from functools import lru_cache
from typing import TYPE_CHECKING

from ..errors import ConfigError
from .codes import COUNTERS, STATIONS, Action, Cell, Item, ItemState, Where
from .grid import (Neighbors, Walks, distances, grid_neighbors, interaction_spots, walk_actions,
                   walk_to, walks)

if TYPE_CHECKING:
    from .rules import Rules
    from .state import Geometry, State

_STAY = int(Action.STAY)
_COUNTERS = frozenset(int(c) for c in COUNTERS)
_STEAK = int(Item.STEAK)
_DELIVERY, _TRASH = int(Cell.DELIVERY), int(Cell.TRASH)
_PLATE = int(Item.PLATE)
_CLEAN = int(ItemState.CLEAN)


# ---------------------------------------------------------------- walking (.grid)
def stations_cut_off(geo: Geometry, layout: int, blocker: int,
                     sources: Iterable[int]) -> list[int]:
    """The station cells (:data:`~.codes.STATIONS`) that a cook standing still on ``blocker``
    cuts off from ``sources`` in ``layout``: each can be bumped from a cell that a walk from
    ``sources`` reaches without the blocker, and from none with it (a one-lane way, or the
    only cell in front of the station)."""
    walkable = geo.walkables[layout]
    sources = [s for s in sources if s != blocker]
    free = walks(geo.neighbors, walkable, sources).dist
    held = walks(geo.neighbors, walkable, sources, {blocker}).dist
    out = []
    for cell, code in enumerate(geo.terrains[layout]):
        if code not in STATIONS:
            continue
        spots = interaction_spots(geo.neighbors, walkable, cell)
        if any(free[c] >= 0 for c in spots) and not any(held[c] >= 0 for c in spots
                                                         if c != blocker):
            out.append(cell)
    return out


@lru_cache(maxsize=64)
def walkable_in_any_layout(geo: Geometry) -> tuple[bool, ...]:
    """Per cell: walkable in at least one of the map's layouts (the floor a walk across
    layout switches may use, waiting for each switch)."""
    return tuple(any(flags) for flags in zip(*geo.walkables))


def layout_at(layout: int, due: int, period: int, t: int) -> int:
    """The layout in force ``t`` steps from now on a two-layout map whose next switch is due
    in ``due`` steps and then every ``period`` steps (switches on time)."""
    if t < due:
        return layout
    return layout if (1 + (t - due) // period) % 2 == 0 else 1 - layout


class SwitchingWalks:
    """Earliest arrivals on a map whose two layouts alternate on a known schedule: a walk may
    wait for a switch to open its way. One reachability front per (start cell, layout,
    steps to the next switch), as bit masks over the grid, kept for the geometry's life;
    other cooks are ignored (as in every walking estimate of the schedule)."""

    def __init__(self, geo: Geometry, period: int) -> None:
        self.geo, self.period = geo, max(1, period)
        cols, n = geo.cols, geo.rows * geo.cols
        self.full = (1 << n) - 1
        self.not_first = sum(1 << c for c in range(n) if c % cols != 0)
        self.not_last = sum(1 << c for c in range(n) if c % cols != cols - 1)
        self.walk = [sum(1 << c for c in range(n) if w[c]) for w in geo.walkables]
        self._spots: dict[tuple[int, int], int] = {}
        self._fronts: dict[tuple[int, int, int], list[int]] = {}
        self._arrivals: dict[tuple[int, int, int, int], tuple[int, int] | None] = {}

    def _grow(self, front: int) -> int:
        cols = self.geo.cols
        return (front | ((front & self.not_last) << 1) | ((front & self.not_first) >> 1)
                | (front << cols) | (front >> cols)) & self.full

    def fronts(self, pos: int, layout: int, due: int) -> list[int]:
        """Cells reachable from ``pos`` within 0, 1, 2, ... steps (until nothing changes for
        two whole periods, after which nothing will)."""
        key = (pos, layout, due)
        out = self._fronts.get(key)
        if out is None:
            front, out, still = 1 << pos, [1 << pos], 0
            limit = due + 2 * self.period + 4 * (self.geo.rows + self.geo.cols)
            for t in range(limit):
                grown = (self._grow(front) & self.walk[layout_at(layout, due, self.period, t)]) | front
                still = still + 1 if grown == front else 0
                front = grown
                out.append(front)
                if still >= 2 * self.period:
                    break
            self._fronts[key] = out
        return out

    def spot_mask(self, target: int, layout: int) -> int:
        key = (target, layout)
        if key not in self._spots:
            self._spots[key] = sum(1 << c for c in interaction_spots(
                self.geo.neighbors, self.geo.walkables[layout], target))
        return self._spots[key]

    def phase(self, layout: int, due: int, at: int) -> tuple[int, int]:
        """(layout, steps to its next switch) ``at`` steps after a moment when ``layout``
        was in force with its next switch ``due`` steps away."""
        if at < due:
            return layout, due - at
        return layout_at(layout, due, self.period, at), self.period - (at - due) % self.period

    def arrival(self, pos: int, target: int, layout: int, due: int) -> tuple[int, int] | None:
        """(steps, spot) of the earliest arrival next to ``target`` from ``pos`` when the
        current layout is ``layout`` and the next switch is ``due`` steps away; None if no
        walk over the switches reaches it (answers are kept: the executive asks the same
        ones at every step while a steak cooks)."""
        key = (pos, target, layout, due)
        if key not in self._arrivals:
            self._arrivals[key] = None
            for t, front in enumerate(self.fronts(pos, layout, due)):
                hit = front & self.spot_mask(target, layout_at(layout, due, self.period, t))
                if hit:
                    self._arrivals[key] = (t, (hit & -hit).bit_length() - 1)
                    break
        return self._arrivals[key]


_SWITCHING: dict[int, SwitchingWalks] = {}


def switching_walks(geo: Geometry, period: int) -> SwitchingWalks:
    """The :class:`SwitchingWalks` of a geometry (one per geometry and period)."""
    key = id(geo)
    walks = _SWITCHING.get(key)
    if walks is None or walks.geo is not geo or walks.period != max(1, period):
        walks = _SWITCHING[key] = SwitchingWalks(geo, period)
    return walks


def direction(geo: Geometry, src: int, dst: int) -> int:
    """The action that moves from ``src`` into the neighbouring ``dst`` (or bumps it);
    STAY when they are the same cell. Cells that are not neighbours are a ConfigError."""
    if src == dst:
        return _STAY
    for action, nb in enumerate(geo.neighbors[src]):
        if nb == dst:
            return action
    raise ConfigError(f"cells {geo.rc(src)} and {geo.rc(dst)} are not adjacent")


# ---------------------------------------------------------------- bumps
class Bump(IntEnum):
    """What bumping a non-walkable cell does (SPEC section 3)."""

    NOTHING = 0
    PICK_UP = 1  # the item lying there goes into the empty hand
    PUT_DOWN = 2  # the held item goes onto the empty cell
    ONTO_PLATE = 3  # the held ingredient goes onto the clean plate lying there
    TAKE_ONTO_PLATE = 4  # the ingredient lying there goes onto the held clean plate
    CHOP = 5  # one chop of the fresh vegetable on the board
    WASH = 6  # one wash of the dirty plate in the sink
    DELIVER = 7  # the held thing is served (or refused: see sim.orders.matching_order)
    TRASH = 8  # the held ingredient, or the held plate's contents, go back to their spawn
    WORK = 9  # one unit of work of another bump-driven process (its record says which)


_NOTHING, _PICK_UP, _PUT_DOWN = Bump.NOTHING, Bump.PICK_UP, Bump.PUT_DOWN


def is_plateable(state: State, item: int) -> bool:
    """An ingredient in the state its process makes (a chopped vegetable, a cooked steak):
    the only things a plate takes."""
    return state.rules.tables.plateable_list[state.geo.item_kind[item]][state.item_state[item]]


#: the bump of each shipped bump-driven process; any other one is :attr:`Bump.WORK`
_WORK_BUMP = {"chop": Bump.CHOP, "wash": Bump.WASH}


def bump_effect(state: State, held: int, cell: int) -> Bump:
    """What an agent holding ``held`` (an item id, -1 for empty hands) does by bumping
    ``cell`` in the current layout. It does not depend on where the agent stands."""
    code = state.geo.terrains[state.layout_index][cell]
    here = state.cell_item[cell]
    if code in _COUNTERS:
        if held < 0:
            return _PICK_UP if here >= 0 else _NOTHING
        return _PUT_DOWN if here < 0 else _plate_exchange(state, held, here)
    tables = state.rules.tables
    p = tables.by_code.get(code, -1)
    if p >= 0:  # a process station: its record's tables say
        kinds = state.geo.item_kind
        if held < 0:  # a bump-driven item is worked where it lies, never picked up half-done
            if here < 0:
                return _NOTHING
            if tables.works_list[p][kinds[here]][state.item_state[here]]:
                return _WORK_BUMP.get(tables.processes[p].verb, Bump.WORK)
            return _PICK_UP
        if here < 0:
            return (_PUT_DOWN if tables.accepts_list[p][kinds[held]][state.item_state[held]]
                    else _NOTHING)
        return _plate_exchange(state, held, here) if tables.plates[p] else _NOTHING
    if code == _DELIVERY:
        return Bump.DELIVER if held >= 0 else _NOTHING
    if code == _TRASH and held >= 0:  # an empty plate: nothing to throw away
        empty_plate = state.geo.item_kind[held] == _PLATE and not state.plate_contents(held)
        return _NOTHING if empty_plate else Bump.TRASH
    return _NOTHING


def _plate_exchange(state: State, held: int, here: int) -> Bump:
    """Held ingredient onto a clean plate lying here, or the ingredient lying here onto the
    held clean plate; anything else does nothing."""
    kinds, states = state.geo.item_kind, state.item_state
    if kinds[here] == _PLATE and states[here] == _CLEAN and is_plateable(state, held):
        return Bump.ONTO_PLATE
    if kinds[held] == _PLATE and states[held] == _CLEAN and is_plateable(state, here):
        return Bump.TAKE_ONTO_PLATE
    return _NOTHING


def bumps_needed(rules: Rules, effect: Bump, verb: str = "") -> int:
    """How many bumps of this kind finish the job: the duration of the bump-driven process
    (``chop_steps`` chops, ``wash_steps`` washes; for :attr:`Bump.WORK`, the process named
    by ``verb``), one of anything else."""
    name = {Bump.CHOP: "chop", Bump.WASH: "wash"}.get(effect, verb if effect == Bump.WORK else "")
    if not name:
        return 1
    tables = rules.tables
    return next(tables.duration[i] for i, p in enumerate(tables.processes) if p.verb == name)


# ---------------------------------------------------------------- time-driven stations
def ticks_until_done(rules: Rules, code: int, ticks: int) -> int:
    """Ticks still needed, after ``ticks`` on the time-driven station ``code``, before the
    item it takes is done (0: it is)."""
    tables = rules.tables
    return max(0, tables.duration[tables.by_code[code]] - ticks)


def ticks_until_overrun(rules: Rules, code: int, ticks: int) -> int:
    """Ticks, after ``ticks`` on the time-driven station ``code``, until the item overruns
    (0: it has): on the tick that takes it past the overrun time."""
    tables = rules.tables
    return max(0, tables.overrun[tables.by_code[code]] + 1 - ticks)


def ticks_until_cooked(rules: Rules, ticks: int) -> int:
    """Pan ticks still needed, after ``ticks`` on the pan, before a raw steak is cooked
    (0: it is); the pan is the station that heats steak (an oven in a kitchen with one)."""
    return ticks_until_done(rules, rules.tables.station_of(_STEAK), ticks)


def ticks_until_burnt(rules: Rules, ticks: int) -> int:
    """Pan ticks, after ``ticks`` on the pan, until the steak burns (0: it has): it burns
    on the tick that takes it past ``burn_time``."""
    return ticks_until_overrun(rules, rules.tables.station_of(_STEAK), ticks)


# ---------------------------------------------------------------- plates
def plate_fits(contents: Counter[int], recipe: Counter[int]) -> bool:
    """Can a plate holding ``contents`` still become ``recipe`` by adding ingredients?
    (Multiset inclusion; both count ingredient kinds.)"""
    return not (contents - recipe)


@dataclass(frozen=True)
class OrderNeeds:
    """What the open orders still need (:func:`order_needs`); kinds count ingredient kinds."""

    recipes: list[Counter]  #: per open order (oldest first), kind -> count
    plate_contents: dict[int, Counter]  #: clean plate (on a cell or in a hand) -> what it holds
    plate_order: dict[int, int]  #: clean plate -> index of the order it is matched to
    plate_missing: dict[int, Counter]  #: matched plate -> what its order still misses
    need: Counter  #: kind -> count the orders need (a matched order: what its plate misses)
    supply: Counter  #: kind -> count on its way (ready, or fresh in a hand or on its station)


def order_needs(state: State) -> OrderNeeds:
    """Match clean plates to the open orders (oldest order first, each to the fitting plate
    with the most on it) and count what the orders still need and what is on its way; the
    greedy cook allocates work by these, and a learner's features read them."""
    kind = state.geo.item_kind
    terrain = state.geo.terrains[state.layout_index]
    heat = state.rules.tables.station_of(_STEAK)
    recipes = [Counter(int(k) for k in o.recipe) for o in state.orders]
    clean = [i for i in range(state.n_items) if kind[i] == _PLATE and state.item_state[i] == _CLEAN
             and state.item_where[i] in (Where.CELL, Where.HAND)]
    contents = {p: Counter(kind[i] for i in state.plate_contents(p)) for p in clean}
    plate_order: dict[int, int] = {}
    for oi, rec in enumerate(recipes):
        fitting = [p for p in clean if p not in plate_order and plate_fits(contents[p], rec)]
        if fitting:
            plate_order[max(fitting, key=lambda p: sum(contents[p].values()))] = oi  # (the first)
    missing = {p: recipes[oi] - contents[p] for p, oi in plate_order.items()}
    need: Counter = Counter()
    for m in missing.values():
        need.update(m)
    for oi, rec in enumerate(recipes):
        if oi not in plate_order.values():
            need.update(rec)
    supply: Counter = Counter()
    for i in range(state.n_items):
        k, st, w = kind[i], state.item_state[i], state.item_where[i]
        if k == _PLATE or w in (Where.PLATE, Where.WAITING):
            continue
        if st == state.rules.tables.ready_of(k) or (st == int(ItemState.FRESH) and (
                w == Where.HAND or terrain[state.item_loc[i]] in (Cell.BOARD, heat))):
            supply[k] += 1
    return OrderNeeds(recipes, contents, plate_order, missing, need, supply)


__all__ = ["Bump", "OrderNeeds", "SwitchingWalks", "Walks", "bump_effect", "bumps_needed", "direction",
           "distances", "grid_neighbors", "interaction_spots", "is_plateable", "layout_at",
           "order_needs", "plate_fits",
           "stations_cut_off", "switching_walks", "ticks_until_burnt", "ticks_until_cooked",
           "ticks_until_done", "ticks_until_overrun", "walk_actions",
           "walk_to", "walkable_in_any_layout", "walks"]

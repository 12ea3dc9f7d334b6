"""``compile(state, ...)``: any simulator state and its open orders as a UP problem.

The problem's domain comes from :mod:`.model`; this module adds the objects of one
state (agents, spots, places, items, kinds, contents, orders), its initial facts,
the rule numbers (read from ``state.rules``), the goal (serve every selected
order) and, for the temporal encoding, the timed initial literals of a steak that
is already on a pan. :class:`Compiled` also maps every plan action back to a
:class:`~.names.MappedAction`.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..errors import CompileError
from ..sim.codes import COUNTERS, Cell, Item, ItemState, Where
from ..sim.state import Order, State
from ..sim.processes import PROCESSES
from ..sim.stations import CELL_KINDS, PLACE_FLAGS
from ._build import Builder as _Builder
from ._build import new_problem as _new_problem
from .model import BUMP_DONE_KINDS, build_domain, hand_change
from .names import MappedAction, Names
from .spots import SpotGraph, build_spots, walk_distance

_HOLDERS = frozenset(int(c) for c in COUNTERS)
#: an empty hand picks up anything here (a board chops a fresh vegetable instead, a
#: sink washes a dirty plate: those have their own pick actions)
#: the kinds the model's cooking covers: those whose place flag is the pan's (an oven)
_HEATS = frozenset(int(k.code) for k in CELL_KINDS if k.pddl == PLACE_FLAGS[int(Cell.PAN)])
_GRABBABLE = _HOLDERS | _HEATS
#: a held clean plate takes a ready ingredient from here
_TAKES_FROM = _HOLDERS | {int(Cell.BOARD)} | _HEATS
_PLACE_FLAGS = PLACE_FLAGS  # the place flag of each station kind (sim/stations.py)
_STATE_FLAG = {ItemState.FRESH: "fresh", ItemState.CHOPPED: "ready",
               ItemState.COOKED: "ready", ItemState.BURNT: "burnt", ItemState.CLEAN: "clean",
               ItemState.DIRTY: "dirty"}
_KIND_NAMES = {Item.TOMATO: "tomato", Item.LETTUCE: "lettuce", Item.ONION: "onion",
               Item.STEAK: "steak"}


@dataclass
class Compiled:
    """A compiled state: the UP problem, the name map and what the plan steps mean."""

    problem: Any
    names: Names
    encoding: str
    granularity: str
    spots: SpotGraph
    #: goal orders (oldest first)
    goal_orders: tuple[int, ...]
    #: steaks on a pan that the model calls burnt although the simulator may not have
    #: burnt them yet (classical: nobody can rescue them in time)
    doomed: frozenset[int] = frozenset()
    #: static numbers behind the costs: name -> value (per object tuple)
    numbers: dict[tuple[str, tuple[str, ...]], int] = field(default_factory=dict)
    geometry: Any = None
    #: stations moves per layout, switches as timed literals (``anticipate_switches``)
    switches: bool = False

    def map_back(self, action_instance: Any, start: float | None = None,
                 duration: float | None = None) -> MappedAction:
        """The :class:`MappedAction` of one plan action (a UP ``ActionInstance``)."""
        action = action_instance.action
        values = [str(p.object()) if p.is_object_exp() else str(p)
                  for p in action_instance.actual_parameters]
        args = dict(zip((p.name for p in action.parameters), values))
        sch = build_domain(self.encoding, self.granularity, _k_of(self.problem),
                           self.switches).schemas.get(action.name)
        kind = sch.kind if sch is not None else BUMP_DONE_KINDS.get(
            action.name, action.name.split("_rest")[0])
        n = self.names

        def cell(key: str) -> tuple[int, int] | None:
            return n.cells[args[key]] if key in args else None

        items = tuple(n.items[args[k]] for k in ("i", "q", "w", "i1", "i2", "i3", "i4", "i5",
                                                    "i6", "i7", "i8", "i9") if k in args)
        agent_key = "a" if "a" in args else ("a1" if "a1" in args else None)
        if action.name in ("cook", "cook_rest") and "a1" in args:
            dur = round(float(duration)) if duration is not None else self._number(
                "cook_lo_full" if action.name == "cook" else "cook_lo",
                () if action.name == "cook" else (args["i"],))
            return MappedAction(action.name, "cook", n.agents[args["a1"]], items, cell("p"),
                                cell("s1"), None, dur, None, start, n.agents[args["a2"]],
                                cell("s2"))
        if sch is None or isinstance(sch.cost, int):
            dur = sch.cost if sch is not None else 1
        else:
            dur = self._number(sch.cost[0], tuple(args[x] for x in sch.cost[1:]))
        spot_key = "s2" if action.name == "move" else "s"
        from_key = "s1" if action.name in ("move", "rescue") else None
        return MappedAction(
            action.name, kind, n.agents[args[agent_key]] if agent_key else None, items,
            cell("p"), cell(spot_key), cell(from_key) if from_key else None, int(dur),
            n.orders[args["o"]] if "o" in args else None, start,
            hand=hand_change(sch) if sch is not None else "keep",
        )

    def _number(self, name: str, args: tuple[str, ...]) -> int:
        return self.numbers.get((name, args), 1 if name == "move" else 0)


def _k_of(problem: Any) -> int:
    return max(int(a.name[len("deliver"):].split("_")[0]) for a in problem.actions
               if a.name.startswith("deliver"))


@dataclass
class _Objects:
    """The problem's object names, keyed by the simulator thing each stands for."""

    agents: dict[int, str]
    spots: dict[int, str]
    places: dict[int, str]
    items: list[str]
    kinds: dict[Item, str]
    contents: dict[tuple[Item, ...], str] = field(default_factory=dict)
    orders: dict[int, str] = field(default_factory=dict)


def compile(state: State, orders: Sequence[Order] | None = None, encoding: str = "classical",
            granularity: str = "stations", max_orders: int | None = None,
            anticipate_switches: bool = False, extra_counters: int = 2,
            _fast: bool = True, agents: Sequence[int] | None = None) -> Compiled:
    """Compile ``state`` and its open orders into a unified-planning problem.

    ``orders`` defaults to ``state.orders`` (oldest first); ``max_orders`` keeps the
    first k of them as the goal. ``anticipate_switches`` (temporal only) encodes the
    coming layout switches as timed initial literals: cells open and close (cells),
    or the layout whose moves are allowed changes (stations; see ``planning.model``).
    ``agents`` (default: every cook) are the cooks the problem models; the others are
    left out (they must hold nothing), e.g. to plan the work for one cook and schedule
    it over all of them afterwards (``execution.schedule``).
    """
    from unified_planning.model.metrics import MinimizeMakespan

    if anticipate_switches and encoding != "temporal":
        raise CompileError(
            "anticipate_switches needs encoding='temporal': the coming layout switches are "
            "timed initial literals, which classical PDDL cannot express"
        )
    _check_processes(state)
    cooks = _cooks(state, agents)
    goal, model_orders = _goal_orders(state, orders, max_orders)
    geo = state.geo
    plates = [i for i, k in enumerate(geo.item_kind) if k == Item.PLATE]
    initial_contents = {q: tuple(sorted(Item(geo.item_kind[i]) for i in state.plate_contents(q)))
                        for q in plates}
    k_max = max([3] + [len(r) for r in state.rules.recipes]
                + [len(c) for c in initial_contents.values()])
    switches = anticipate_switches and granularity == "stations"
    domain = build_domain(encoding, granularity, k_max, switches)
    spots = build_spots(state, granularity, extra_counters, every_layout=anticipate_switches)
    problem = _new_problem(f"ocplus_{encoding}_{granularity}", domain, _fast)
    comp = Compiled(problem, Names(), encoding, granularity, spots,
                    tuple(o.order_id for o in goal), geometry=geo, switches=switches)
    builder = _Builder(problem, domain, comp, _fast)

    objects = _declare_objects(builder, state, spots, cooks)
    _declare_contents(builder, objects, goal, initial_contents)
    _declare_orders(builder, objects, goal, model_orders)
    _place_facts(builder, state, spots, objects, granularity, switches)
    _agent_facts(builder, state, spots, objects, encoding)
    _rule_numbers(builder, state)
    cooking = _item_facts(builder, state, objects, initial_contents)
    _pans(builder, state, comp, cooking, objects)
    problem.add_quality_metric(domain.metric if encoding == "classical" else MinimizeMakespan())
    if anticipate_switches:
        _switch_literals(builder, state, objects.spots)
    builder.flush()
    return comp


def _check_processes(state: State) -> None:
    """The model's schemas are written for the shipped process records (any durations; a
    time-driven station may have another verb): refuse records of another shape rather
    than plan with wrong rules."""
    def shape(p: Any) -> tuple:  # a station with a shipped one's place flag plans as it
        return (PLACE_FLAGS.get(int(p.station), p.station), p.drive, p.takes, p.takes_state, p.makes_state, p.overrun_state,
                p.plates, "" if p.timed else p.verb)

    shipped = {shape(p)[0]: p for p in PROCESSES}
    for p in state.rules.processes:
        flag = shape(p)[0]
        if flag not in shipped or shape(p) != shape(shipped[flag]):
            covered = ", ".join(f"{q.verb} on the {q.station.name.lower()}" for q in PROCESSES)
            raise CompileError(
                f"the planning model covers the shipped process stations ({covered}, any "
                f"durations); {p.verb!r} on the {p.station.name.lower()} of map "
                f"{state.rules.layout.name!r} differs: plan with the shipped records")


def _cooks(state: State, agents: Sequence[int] | None) -> tuple[int, ...]:
    """The modelled cooks; a cook left out must hold nothing."""
    cooks = tuple(range(state.n_agents)) if agents is None else tuple(sorted(set(agents)))
    if not cooks or any(not 0 <= a < state.n_agents for a in cooks):
        raise CompileError(f"agents={agents!r}: the kitchen has cooks 0..{state.n_agents - 1}")
    left_out = [a for a in range(state.n_agents) if a not in cooks and state.agent_hand[a] >= 0]
    if left_out:
        raise CompileError(f"cooks {left_out} hold an item: they must be among agents={cooks}")
    return cooks


def _goal_orders(state: State, orders: Sequence[Order] | None,
                 max_orders: int | None) -> tuple[list[Order], list[Order]]:
    """(the goal orders, the open orders up to the last goal one: the serving chain)."""
    if max_orders is not None and max_orders < 0:
        raise CompileError(f"max_orders must be >= 0, got {max_orders}")
    goal = list(state.orders if orders is None else orders)
    if max_orders is not None:
        goal = goal[:max_orders]
    order_ids = [o.order_id for o in state.orders]
    for o in goal:
        if o.order_id not in order_ids:
            raise CompileError(f"order {o.order_id} is not open in this state")
    last = max((order_ids.index(o.order_id) for o in goal), default=-1)
    return goal, state.orders[: last + 1]


def _declare_objects(builder: _Builder, state: State, spots: SpotGraph,
                     cooks: tuple[int, ...]) -> _Objects:
    """Agents, spots, places, items and ingredient kinds."""
    geo, types = state.geo, builder.dom.types
    terrain = geo.terrains[state.layout_index]
    places = {}
    for p in spots.places:
        label = Cell(terrain[p]).name.lower()
        places[p] = builder.obj("cells", "{}_{}_{}".format(label, *geo.rc(p)), geo.rc(p),
                                types["place"])
    return _Objects(
        agents={a: builder.obj("agents", f"a{a}", a, types["agent"]) for a in cooks},
        spots={s: builder.obj("cells", "s_{}_{}".format(*geo.rc(s)), geo.rc(s), types["spot"])
               for s in spots.spots},
        places=places,
        items=[builder.obj("items", geo.item_names[i], i, types["item"])
               for i in range(state.n_items)],
        kinds={k: builder.obj("kinds", f"k_{v}", v, types["kind"]) for k, v in _KIND_NAMES.items()},
    )


def _declare_contents(builder: _Builder, objects: _Objects, goal: list[Order],
                      initial_contents: dict[int, tuple[Item, ...]]) -> None:
    """Every sub-multiset of a goal recipe, plus what plates hold now, and how one grows
    into another (``next_content`` only toward a goal recipe)."""
    useful: set[tuple[Item, ...]] = {()}
    for o in goal:
        for size in range(len(o.recipe) + 1):
            useful.update(tuple(sorted(c)) for c in itertools.combinations(o.recipe, size))
    for contents in sorted(useful | set(initial_contents.values()), key=lambda c: (len(c), c)):
        label = "_".join(_KIND_NAMES[k] for k in contents) or "empty"
        objects.contents[contents] = builder.obj(
            "contents", f"c_{label}", tuple(_KIND_NAMES[k] for k in contents),
            builder.dom.types["content"])
    for contents, name in objects.contents.items():
        builder.true(f"size{len(contents)}" if contents else "empty", name)
        if contents in useful:
            for kind in _KIND_NAMES:
                grown = tuple(sorted(contents + (kind,)))
                if grown in useful:
                    builder.true("next_content", name, objects.kinds[kind],
                                 objects.contents[grown])


def _declare_orders(builder: _Builder, objects: _Objects, goal: list[Order],
                    model_orders: list[Order]) -> None:
    """Orders are served oldest first among equal recipes; each chain ends in ``o_none``."""
    for o in model_orders:
        objects.orders[o.order_id] = builder.obj("orders", f"o{o.order_id}", o.order_id,
                                                 builder.dom.types["order"])
    sentinel = builder.obj("orders", "o_none", -1, builder.dom.types["order"])
    by_recipe: dict[tuple[Item, ...], list[Order]] = {}
    for o in model_orders:
        by_recipe.setdefault(tuple(o.recipe), []).append(o)
        recipe = tuple(sorted(o.recipe))
        if recipe in objects.contents:
            builder.true("serves", objects.contents[recipe], objects.orders[o.order_id])
    for chain in by_recipe.values():
        builder.true("up_next", objects.orders[chain[0].order_id])
        for older, newer in zip(chain, chain[1:] + [None]):
            builder.true("next_order", objects.orders[older.order_id],
                         objects.orders[newer.order_id] if newer else sentinel)
    for o in goal:
        builder.problem.add_goal(
            builder.dom.fluents["served"](builder.objects[objects.orders[o.order_id]]))


def _place_facts(builder: _Builder, state: State, spots: SpotGraph, objects: _Objects,
                 granularity: str, switches: bool) -> None:
    """What each place is and holds, where items may go, and how agents move between spots."""
    geo = state.geo
    terrain = geo.terrains[state.layout_index]
    waiting_homes = {geo.item_home[i] for i in range(state.n_items)
                     if state.item_where[i] == Where.WAITING}
    for p, name in objects.places.items():
        code = terrain[p]
        for flag, codes in (("holder", _HOLDERS), ("grabbable", _GRABBABLE),
                            ("takes_from", _TAKES_FROM)):
            if code in codes:
                builder.true(flag, name)
        if code in _PLACE_FLAGS:
            builder.true(_PLACE_FLAGS[code], name)
        if state.cell_item[p] < 0:
            builder.true("free", name)
        if p not in waiting_homes:
            builder.true("nowait", name)
    plain_counters = [p for p in spots.places if terrain[p] == Cell.COUNTER]
    for i in range(state.n_items):
        home = objects.places.get(geo.item_home[i])
        if home is not None:  # (a crate nobody reaches, a partner in its only way in: none)
            builder.true("home", objects.items[i], home)
            builder.true("drop_ok", objects.items[i], home)
        for p in plain_counters:
            builder.true("drop_ok", objects.items[i], objects.places[p])
    for s, p in spots.adjacent:
        builder.true("adj", objects.spots[s], objects.places[p])
    if granularity == "cells":
        walk_now = geo.walkables[state.layout_index]
        for s in spots.spots:
            if walk_now[s]:
                builder.true("open", objects.spots[s])
    for s1, s2, d in ([] if switches else spots.links):
        builder.true("link", objects.spots[s1], objects.spots[s2])
        if granularity == "stations":
            builder.num("dist", d, objects.spots[s1], objects.spots[s2])
    if switches:
        layouts = [builder.obj("layouts", f"layout{k}", k, builder.dom.types["layout"])
                   for k in range(len(geo.walkables))]
        builder.true("now", layouts[state.layout_index])
        for k, s1, s2, d in spots.layout_links:
            builder.true("llink", layouts[k], objects.spots[s1], objects.spots[s2])
            builder.num("ldist", d, layouts[k], objects.spots[s1], objects.spots[s2])


def _agent_facts(builder: _Builder, state: State, spots: SpotGraph, objects: _Objects,
                 encoding: str) -> None:
    """Where the modelled cooks stand, which spots are vacant and what they hold."""
    occupied = {state.agent_pos[a] for a in objects.agents}
    for s in spots.spots:
        if s not in occupied:
            builder.true("vacant", objects.spots[s])
    for a, name in objects.agents.items():
        builder.true("agent_at", name, objects.spots[state.agent_pos[a]])
        if encoding == "temporal":
            builder.true("idle", name)
        held = state.agent_hand[a]
        if held < 0:
            builder.true("free_hand", name)
        else:
            builder.true("holding", name, objects.items[held])


def _pan_times(state: State) -> tuple[int, int]:
    """(cook, burn) ticks of the record that heats steak (the pan's; an oven's)."""
    tables = state.rules.tables
    heat = tables.station_of(int(Item.STEAK))
    return tables.duration_at(heat), tables.overrun_at(heat)


def _rule_numbers(builder: _Builder, state: State) -> None:
    rules, tables = state.rules, state.rules.tables
    for j, p in enumerate(tables.processes):  # chop_full, wash_full
        if not p.timed:
            builder.num(f"{p.verb}_full", tables.duration[j])
    cook, burn = _pan_times(state)
    builder.num("cook_cost_full", cook + 1)
    builder.num("cook_lo_full", cook)
    builder.num("cook_hi_full", max(cook, burn - 1))
    builder.true("plates_get_dirty" if rules.dirty_plates else "plates_stay_clean")


def _item_facts(builder: _Builder, state: State, objects: _Objects,
                initial_contents: dict[int, tuple[Item, ...]]) -> list[tuple[int, int]]:
    """Each item's kind, state, progress and where it is; returns the steaks heating on a
    pan (their facts come from :func:`_pans`)."""
    geo = state.geo
    terrain = geo.terrains[state.layout_index]
    by_kind = sorted(range(state.n_items), key=lambda i: (geo.item_kind[i], i))
    for x, y in itertools.combinations(by_kind, 2):
        builder.true("lt", objects.items[x], objects.items[y])
    cooking: list[tuple[int, int]] = []
    for i in range(state.n_items):
        name, kind = objects.items[i], Item(geo.item_kind[i])
        item_state, progress = ItemState(state.item_state[i]), state.item_progress[i]
        if kind == Item.PLATE:
            builder.true("is_plate", name)
            builder.true("plate_has", name, objects.contents[initial_contents[i]])
        else:
            builder.true("ingredient", name)
            builder.true("is_steak" if kind == Item.STEAK else "is_veg", name)
            builder.true("kind_of", name, objects.kinds[kind])
        where, loc = state.item_where[i], state.item_loc[i]
        heating = (where == Where.CELL and terrain[loc] in _HEATS
                   and item_state != ItemState.BURNT)
        partial = progress > 0 and item_state in (ItemState.FRESH, ItemState.DIRTY)
        builder.true("partly" if partial else "untouched", name)
        if not heating:  # a steak cooking on a pan gets its state flag in _pans()
            builder.true(_STATE_FLAG[item_state], name)
        if partial and kind == Item.STEAK:
            cook, burn = _pan_times(state)
            builder.num("cook_cost_left", cook - progress + 1, name)
            builder.num("cook_lo", max(1, cook - progress), name)
            builder.num("cook_hi", max(1, cook - progress, burn - progress - 1), name)
        elif partial:  # chop_left, wash_left
            tables = state.rules.tables
            j = next(j for j, p in enumerate(tables.processes) if kind in p.takes)
            builder.num(f"{tables.processes[j].verb}_left",
                        max(1, tables.duration[j] - progress), name)
        if where == Where.PLATE:
            builder.true("on_plate", name, objects.items[loc])
        elif where == Where.WAITING:
            builder.true("waiting", name)
        elif heating:
            cooking.append((i, loc))
        elif where != Where.HAND:
            builder.true("item_at", name, objects.places[loc])
    return cooking


def _switch_literals(builder: _Builder, state: State, spot_name: dict[int, str]) -> None:
    """Timed initial literals for the coming layout switches: ``open`` of the switching
    cells (cells granularity) or ``now`` of the layout (stations).

    Plan time ``tau`` is the state after ``tau`` more simulator steps; the simulator
    switches at the end of the step that reaches ``next_switch`` (a switch already due
    and waiting is assumed to happen after the next step). Switches are listed up to
    the episode's horizon: a plan that outlasts the episode is not modelled past it.
    Assumes no switch waits: an agent standing on a closing cell or an item on a
    vanishing counter delays it in the simulator, not in the model (the executive
    replans on the event).
    """
    from unified_planning.model import GlobalStartTiming

    rules, geo = state.rules, state.geo
    if not rules.dynamic or len(geo.walkables) < 2:
        return
    layout = state.layout_index
    tau = max(1, state.next_switch - state.t)
    switching = [s for s in spot_name if s in set(geo.switch_cells)]
    stations = "now" in builder.dom.fluents
    fl = builder.dom.fluents["now" if stations else "open"]
    while state.t + tau <= rules.horizon:
        at = GlobalStartTiming(tau)
        if stations:
            builder.problem.add_timed_effect(at, fl(builder.objects[f"layout{layout}"]), False)
        layout = 1 - layout
        if stations:
            builder.problem.add_timed_effect(at, fl(builder.objects[f"layout{layout}"]), True)
        for s in ([] if stations else switching):
            builder.problem.add_timed_effect(at, fl(builder.objects[spot_name[s]]),
                                       bool(geo.walkables[layout][s]))
        tau += rules.map_switch_step


def _pans(builder: _Builder, state: State, comp: Compiled, cooking: list[tuple[int, int]],
          objects: _Objects) -> None:
    """Steaks on a pan at compile time (not burnt yet): see the model's docstring."""
    cook, burn = _pan_times(state)
    occupied = {state.agent_pos[a] for a in objects.agents}
    doomed = set()
    if comp.encoding == "temporal":
        from unified_planning.model import GlobalStartTiming

        for i, pan in cooking:
            ticks = state.item_progress[i]
            builder.true("on_heat", objects.items[i], objects.places[pan])
            builder.true(_STATE_FLAG[ItemState(state.item_state[i])], objects.items[i])
            opens = max(0, cook - ticks)
            closes = burn - ticks + 1
            steak = builder.objects[objects.items[i]]
            fl = builder.dom.fluents
            if opens == 0:
                builder.true("window", objects.items[i])
            else:
                builder.problem.add_timed_effect(GlobalStartTiming(opens), fl["window"](steak), True)
            builder.problem.add_timed_effect(GlobalStartTiming(closes), fl["window"](steak), False)
            builder.problem.add_timed_effect(GlobalStartTiming(closes), fl["overdone"](steak), True)
        builder.true("calm")
        return
    rescued = False
    for i, pan in cooking:
        ticks = state.item_progress[i]
        offers = []
        if not rescued:
            for a in objects.agents:
                if state.agent_hand[a] >= 0:
                    continue
                here = state.agent_pos[a]
                # the rescue is the plan's first action: the other cooks stand still
                others = frozenset(q for q in occupied if q != here)
                for s, p in comp.spots.adjacent:
                    if p != pan or (s in occupied and s != here):
                        continue
                    d = walk_distance(state, here, s, others)
                    if d is None or ticks + d > burn:
                        continue
                    wait = max(0, cook - ticks - d)
                    offers.append((d + wait + 1, a, s))
        best: dict[int, tuple[int, int, int]] = {}
        for cost, a, s in sorted(offers):
            best.setdefault(a, (cost, a, s))
        if best:
            rescued = True
            builder.true("cooking_on", objects.items[i], objects.places[pan])
            builder.true(_STATE_FLAG[ItemState(state.item_state[i])], objects.items[i])
            for cost, a, s in best.values():
                builder.true("can_rescue", objects.agents[a], objects.items[i], objects.spots[s])
                builder.num("rescue_cost", cost, objects.agents[a], objects.items[i])
        else:
            doomed.add(i)
            builder.true("item_at", objects.items[i], objects.places[pan])
            builder.true("burnt", objects.items[i])
    if not rescued:
        builder.true("calm")
    comp.doomed = frozenset(doomed)


__all__ = ["Compiled", "compile"]

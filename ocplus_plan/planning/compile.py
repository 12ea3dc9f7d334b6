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
from ._build import Builder as _Builder
from ._build import new_problem as _new_problem
from .model import BUMP_DONE_KINDS, build_domain
from .names import MappedAction, Names
from .spots import SpotGraph, build_spots, walk_distance

_HOLDERS = frozenset(int(c) for c in COUNTERS)
#: an empty hand picks up anything here (a board chops a fresh vegetable instead, a
#: sink washes a dirty plate: those have their own pick actions)
_GRABBABLE = _HOLDERS | {int(Cell.PAN)}
#: a held clean plate takes a ready ingredient from here
_TAKES_FROM = _HOLDERS | {int(Cell.BOARD), int(Cell.PAN)}
_PLACE_FLAGS = {int(Cell.BOARD): "board", int(Cell.PAN): "pan", int(Cell.SINK): "sink",
                int(Cell.TRASH): "trash", int(Cell.DELIVERY): "serving"}
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
        )

    def _number(self, name: str, args: tuple[str, ...]) -> int:
        return self.numbers.get((name, args), 1 if name == "move" else 0)


def _k_of(problem: Any) -> int:
    return max(int(a.name[len("deliver"):].split("_")[0]) for a in problem.actions
               if a.name.startswith("deliver"))


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
    from unified_planning.model.metrics import MinimizeActionCosts, MinimizeMakespan

    if max_orders is not None and max_orders < 0:
        raise CompileError(f"max_orders must be >= 0, got {max_orders}")
    if anticipate_switches and encoding != "temporal":
        raise CompileError(
            "anticipate_switches needs encoding='temporal': the coming layout switches are "
            "timed initial literals, which classical PDDL cannot express"
        )
    rules = state.rules
    geo = state.geo
    cooks = tuple(range(state.n_agents)) if agents is None else tuple(sorted(set(agents)))
    if not cooks or any(not 0 <= a < state.n_agents for a in cooks):
        raise CompileError(f"agents={agents!r}: the kitchen has cooks 0..{state.n_agents - 1}")
    left_out = [a for a in range(state.n_agents) if a not in cooks and state.agent_hand[a] >= 0]
    if left_out:
        raise CompileError(f"cooks {left_out} hold an item: they must be among agents={cooks}")
    goal = list(state.orders if orders is None else orders)
    if max_orders is not None:
        goal = goal[:max_orders]
    order_ids = [o.order_id for o in state.orders]
    for o in goal:
        if o.order_id not in order_ids:
            raise CompileError(f"order {o.order_id} is not open in this state")
    last = max((order_ids.index(o.order_id) for o in goal), default=-1)
    model_orders = state.orders[: last + 1]

    plates = [i for i, k in enumerate(geo.item_kind) if k == Item.PLATE]
    initial_contents = {q: tuple(sorted(Item(geo.item_kind[i]) for i in state.plate_contents(q)))
                        for q in plates}
    k_max = max([3] + [len(r) for r in rules.recipes] + [len(c) for c in initial_contents.values()])
    switches = anticipate_switches and granularity == "stations"
    dom = build_domain(encoding, granularity, k_max, switches)
    spots = build_spots(state, granularity, extra_counters, every_layout=anticipate_switches)
    problem = _new_problem(f"ocplus_{encoding}_{granularity}", dom, _fast)
    comp = Compiled(problem, Names(), encoding, granularity, spots,
                    tuple(o.order_id for o in goal), geometry=geo, switches=switches)
    b = _Builder(problem, dom, comp, _fast)

    T = dom.types
    agent_obj = {a: b.obj("agents", f"a{a}", a, T["agent"]) for a in cooks}
    spot_name = {s: b.obj("cells", "s_{}_{}".format(*geo.rc(s)), geo.rc(s), T["spot"])
                 for s in spots.spots}
    terrain = geo.terrains[state.layout_index]
    place_name = {}
    for p in spots.places:
        label = Cell(terrain[p]).name.lower()
        place_name[p] = b.obj("cells", "{}_{}_{}".format(label, *geo.rc(p)), geo.rc(p),
                              T["place"])
    item_name = [b.obj("items", geo.item_names[i], i, T["item"]) for i in range(state.n_items)]
    kind_name = {k: b.obj("kinds", f"k_{v}", v, T["kind"]) for k, v in _KIND_NAMES.items()}

    # --- contents: every sub-multiset of a goal recipe, plus what plates hold now
    useful: set[tuple[Item, ...]] = set()
    for o in goal:
        for size in range(len(o.recipe) + 1):
            useful.update(tuple(sorted(c)) for c in itertools.combinations(o.recipe, size))
    useful.add(())
    all_contents = useful | set(initial_contents.values())
    content_name = {}
    for c in sorted(all_contents, key=lambda c: (len(c), c)):
        label = "_".join(_KIND_NAMES[k] for k in c) or "empty"
        content_name[c] = b.obj("contents", f"c_{label}", tuple(_KIND_NAMES[k] for k in c),
                                T["content"])
    for c, cname in content_name.items():
        if c:
            b.true(f"size{len(c)}", cname)
        else:
            b.true("empty", cname)
        if c in useful:
            for k in set(_KIND_NAMES):
                nxt = tuple(sorted(c + (k,)))
                if nxt in useful:
                    b.true("next_content", cname, kind_name[k], content_name[nxt])

    # --- orders: served oldest first among equal recipes; the chain ends in o_none
    order_name = {o.order_id: b.obj("orders", f"o{o.order_id}", o.order_id, T["order"])
                  for o in model_orders}
    sentinel = b.obj("orders", "o_none", -1, T["order"])
    by_recipe: dict[tuple[Item, ...], list[Order]] = {}
    for o in model_orders:
        by_recipe.setdefault(tuple(o.recipe), []).append(o)
        if tuple(sorted(o.recipe)) in content_name:
            b.true("serves", content_name[tuple(sorted(o.recipe))], order_name[o.order_id])
    for chain in by_recipe.values():
        b.true("up_next", order_name[chain[0].order_id])
        for older, newer in zip(chain, chain[1:] + [None]):
            b.true("next_order", order_name[older.order_id],
                   order_name[newer.order_id] if newer else sentinel)
    for o in goal:
        problem.add_goal(dom.fluents["served"](b.objects[order_name[o.order_id]]))

    # --- places
    home_place = {}
    waiting_homes = {geo.item_home[i] for i in range(state.n_items)
                     if state.item_where[i] == Where.WAITING}
    for p, pname in place_name.items():
        code = terrain[p]
        if code in _HOLDERS:
            b.true("holder", pname)
        if code in _GRABBABLE:
            b.true("grabbable", pname)
        if code in _TAKES_FROM:
            b.true("takes_from", pname)
        if code in _PLACE_FLAGS:
            b.true(_PLACE_FLAGS[code], pname)
        if state.cell_item[p] < 0:
            b.true("free", pname)
        if p not in waiting_homes:
            b.true("nowait", pname)
    plain_counters = [p for p in spots.places if terrain[p] == Cell.COUNTER]
    for i in range(state.n_items):
        home = geo.item_home[i]
        home_place[i] = place_name[home]
        b.true("home", item_name[i], place_name[home])
        b.true("drop_ok", item_name[i], place_name[home])
        for p in plain_counters:
            b.true("drop_ok", item_name[i], place_name[p])
    for s, p in spots.adjacent:
        b.true("adj", spot_name[s], place_name[p])
    walk_now = geo.walkables[state.layout_index]
    if granularity == "cells":
        for s in spots.spots:
            if walk_now[s]:
                b.true("open", spot_name[s])
    for s1, s2, d in ([] if switches else spots.links):
        b.true("link", spot_name[s1], spot_name[s2])
        if granularity == "stations":
            b.num("dist", d, spot_name[s1], spot_name[s2])
    if switches:
        layout_name = [b.obj("layouts", f"layout{k}", k, T["layout"])
                       for k in range(len(geo.walkables))]
        b.true("now", layout_name[state.layout_index])
        for k, s1, s2, d in spots.layout_links:
            b.true("llink", layout_name[k], spot_name[s1], spot_name[s2])
            b.num("ldist", d, layout_name[k], spot_name[s1], spot_name[s2])

    # --- agents
    occupied = {state.agent_pos[a] for a in cooks}
    for s in spots.spots:
        if s not in occupied:
            b.true("vacant", spot_name[s])
    for a, name in agent_obj.items():
        b.true("agent_at", name, spot_name[state.agent_pos[a]])
        if encoding == "temporal":
            b.true("idle", name)
        held = state.agent_hand[a]
        if held < 0:
            b.true("free_hand", name)
        else:
            b.true("holding", name, item_name[held])

    # --- rule numbers
    b.num("chop_full", rules.chop_steps)
    b.num("wash_full", rules.wash_steps)
    b.num("cook_cost_full", rules.cook_time + 1)
    b.num("cook_lo_full", rules.cook_time)
    b.num("cook_hi_full", max(rules.cook_time, rules.burn_time - 1))
    b.true("plates_get_dirty" if rules.dirty_plates else "plates_stay_clean")

    # --- items
    order_key = sorted(range(state.n_items), key=lambda i: (geo.item_kind[i], i))
    for x, y in itertools.combinations(order_key, 2):
        b.true("lt", item_name[x], item_name[y])
    cooking: list[tuple[int, int]] = []
    for i in range(state.n_items):
        name, kind = item_name[i], Item(geo.item_kind[i])
        st, prog = ItemState(state.item_state[i]), state.item_progress[i]
        if kind == Item.PLATE:
            b.true("is_plate", name)
            contents = initial_contents[i]
            b.true("plate_has", name, content_name[contents])
        else:
            b.true("ingredient", name)
            b.true("is_steak" if kind == Item.STEAK else "is_veg", name)
            b.true("kind_of", name, kind_name[kind])
        where, loc = state.item_where[i], state.item_loc[i]
        heating = (where == Where.CELL and terrain[loc] == Cell.PAN and st != ItemState.BURNT)
        partial = prog > 0 and st in (ItemState.FRESH, ItemState.DIRTY)
        b.true("partly" if partial else "untouched", name)
        if not heating:  # a steak cooking on a pan gets its state flag in _pans()
            b.true(_STATE_FLAG[st], name)
        if partial and kind == Item.STEAK:
            b.num("cook_cost_left", rules.cook_time - prog + 1, name)
            b.num("cook_lo", max(1, rules.cook_time - prog), name)
            b.num("cook_hi", max(1, rules.cook_time - prog, rules.burn_time - prog - 1), name)
        elif partial and kind == Item.PLATE:
            b.num("wash_left", max(1, rules.wash_steps - prog), name)
        elif partial:
            b.num("chop_left", max(1, rules.chop_steps - prog), name)
        if where == Where.HAND:
            continue
        if where == Where.PLATE:
            b.true("on_plate", name, item_name[loc])
        elif where == Where.WAITING:
            b.true("waiting", name)
        elif heating:
            cooking.append((i, loc))
        else:
            b.true("item_at", name, place_name[loc])
    _pans(b, state, comp, cooking, spot_name, place_name, item_name, agent_obj)

    if encoding == "classical":
        if not hasattr(dom, "_metric"):
            dom._metric = MinimizeActionCosts(dom.costs, default=None)  # type: ignore[attr-defined]
        problem.add_quality_metric(dom._metric)
    else:
        problem.add_quality_metric(MinimizeMakespan())
        if anticipate_switches:
            _switch_literals(b, state, spot_name)
    b.flush()
    return comp


def _switch_literals(b: _Builder, state: State, spot_name: dict[int, str]) -> None:
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
    stations = "now" in b.dom.fluents
    fl = b.dom.fluents["now" if stations else "open"]
    while state.t + tau <= rules.horizon:
        at = GlobalStartTiming(tau)
        if stations:
            b.problem.add_timed_effect(at, fl(b.objects[f"layout{layout}"]), False)
        layout = 1 - layout
        if stations:
            b.problem.add_timed_effect(at, fl(b.objects[f"layout{layout}"]), True)
        for s in ([] if stations else switching):
            b.problem.add_timed_effect(at, fl(b.objects[spot_name[s]]),
                                       bool(geo.walkables[layout][s]))
        tau += rules.map_switch_step


def _pans(b: _Builder, state: State, comp: Compiled, cooking: list[tuple[int, int]],
          spot_name: dict[int, str], place_name: dict[int, str], item_name: list[str],
          agent_obj: dict[int, str]) -> None:
    """Steaks on a pan at compile time (not burnt yet): see the model's docstring."""
    rules = state.rules
    occupied = {state.agent_pos[a] for a in agent_obj}
    doomed = set()
    if comp.encoding == "temporal":
        from unified_planning.model import GlobalStartTiming

        for i, pan in cooking:
            ticks = state.item_progress[i]
            b.true("on_heat", item_name[i], place_name[pan])
            b.true(_STATE_FLAG[ItemState(state.item_state[i])], item_name[i])
            opens = max(0, rules.cook_time - ticks)
            closes = rules.burn_time - ticks + 1
            steak = b.objects[item_name[i]]
            fl = b.dom.fluents
            if opens == 0:
                b.true("window", item_name[i])
            else:
                b.problem.add_timed_effect(GlobalStartTiming(opens), fl["window"](steak), True)
            b.problem.add_timed_effect(GlobalStartTiming(closes), fl["window"](steak), False)
            b.problem.add_timed_effect(GlobalStartTiming(closes), fl["overdone"](steak), True)
        b.true("calm")
        return
    rescued = False
    for i, pan in cooking:
        ticks = state.item_progress[i]
        offers = []
        if not rescued:
            for a in agent_obj:
                if state.agent_hand[a] >= 0:
                    continue
                here = state.agent_pos[a]
                # the rescue is the plan's first action: the other cooks stand still
                others = frozenset(q for q in occupied if q != here)
                for s, p in comp.spots.adjacent:
                    if p != pan or (s in occupied and s != here):
                        continue
                    d = walk_distance(state, here, s, others)
                    if d is None or ticks + d > rules.burn_time:
                        continue
                    wait = max(0, rules.cook_time - ticks - d)
                    offers.append((d + wait + 1, a, s))
        best: dict[int, tuple[int, int, int]] = {}
        for cost, a, s in sorted(offers):
            best.setdefault(a, (cost, a, s))
        if best:
            rescued = True
            b.true("cooking_on", item_name[i], place_name[pan])
            b.true(_STATE_FLAG[ItemState(state.item_state[i])], item_name[i])
            for cost, a, s in best.values():
                b.true("can_rescue", agent_obj[a], item_name[i], spot_name[s])
                b.num("rescue_cost", cost, agent_obj[a], item_name[i])
        else:
            doomed.add(i)
            b.true("item_at", item_name[i], place_name[pan])
            b.true("burnt", item_name[i])
    if not rescued:
        b.true("calm")
    comp.doomed = frozenset(doomed)


__all__ = ["Compiled", "compile"]

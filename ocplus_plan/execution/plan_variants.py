"""Variants of a plan the schedule tries: idle work dropped, dishes reordered, identical
stations swapped, plating routes changed (see :mod:`.schedule`). Each variant is checked
cell by cell (:func:`_cells_agree`) and scored by the list scheduler (:mod:`.scheduler`).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, replace

from ..sim.codes import COUNTERS, Cell, ItemState, Where
from ..sim.queries import distances, interaction_spots
from ..sim.state import State
from .plans import PlanStep
from .scheduler import (
    KEEP,
    RELEASE,
    TAKE,
    _plates,
    _Scheduler,
    _Walks,
    segments,
)

def without_idle_work(steps: list[tuple[PlanStep, str, int]],
                      state: State) -> list[tuple[PlanStep, str, int]]:
    """The plan without the segments that serve nothing: no delivery in them, and no later
    step touches a cell or item they touch (so no later step needs what they did), over and
    over until none is left. A satisficing planner's plan may fetch an ingredient no order
    needs and leave it on a board (Kairos on easy, seed 9, step 159: an onion fetched after
    the onion order was served, four steps before the lettuce the last order wanted). A
    segment of a cook that holds an item now stays (it frees the hand), and so does a plan
    that delivers nothing (a piece of work, not a plan for orders)."""
    if all(step.kind != "deliver" for step, _, _ in steps):
        return steps
    while True:
        segs = segments(steps, state)
        needed = set().union(*(seg.deps for seg in segs)) if segs else set()
        idle = {id(entry) for k, seg in enumerate(segs)
                if k not in needed and seg.pinned is None
                and all(step.kind != "deliver" for step, _, _ in seg.steps)
                for entry in seg.steps}
        if not idle:
            return steps
        steps = [entry for entry in steps if id(entry) not in idle]


#: passes of the stays' coordinate descent (:func:`_best_stations`)
STATION_PASSES = 2
#: at most this many dishes are put in every order (their permutations are each scheduled)
MAX_DISHES_REORDERED = 3


def dish_orders(steps: list[tuple[PlanStep, str, int]],
                state: State) -> list[list[tuple[PlanStep, str, int]]]:
    """The plan, and the same plan with its dishes served in every other order.

    A plan for several orders serves them in an order the planner chose for nothing but
    its cost; with one plate, the dish served first holds the plate and the other waits,
    even when its ingredients are ready first. A *dish group* is every step that handles
    one delivered dish's ingredients, and the steps that carry its plate from the plate's
    previous delivery to this one. Groups can be played in any order when they share no
    ingredient (an ingredient served twice is the same respawned item), every step belongs
    to a group (steps after the last delivery stay last), every plate starts empty and clean
    at its spawn tile and plates come back clean (no dirty plates): each group then starts
    from what the plan's start offers and leaves its stations as it found them. Otherwise
    only the plan itself is returned."""
    rules = state.rules
    delivers = [i for i, (s, _, _) in enumerate(steps) if s.kind == "deliver"]
    if len(delivers) < 2 or len(delivers) > MAX_DISHES_REORDERED or rules.dirty_plates:
        return [steps]
    plates = _plates(state)
    for q in plates:
        if (state.item_where[q] != int(Where.CELL) or state.item_loc[q] != state.geo.item_home[q]
                or state.item_state[q] != int(ItemState.CLEAN)
                or any(state.item_where[i] == int(Where.PLATE) and state.item_loc[i] == q
                       for i in range(len(state.item_where)))):
            return [steps]
    dish_of: dict[int, int] = {}  # ingredient -> its dish (index into delivers)
    for k, i in enumerate(delivers):
        for item in steps[i][0].items:
            if item in plates:
                continue
            if item in dish_of:
                return [steps]  # served twice: the second dish waits for the respawn
            dish_of[item] = k
    last = delivers[-1]
    groups: list[list[int]] = [[] for _ in delivers]
    for i, (step, _, _) in enumerate(steps[: last + 1]):
        ingredients = {dish_of.get(item, -1) for item in step.items if item not in plates}
        if ingredients:
            if len(ingredients) != 1 or -1 in ingredients:
                return [steps]
            groups[ingredients.pop()].append(i)
            continue
        held = [item for item in step.items if item in plates]
        if not held:
            return [steps]
        # a plate alone: it belongs to the tour that ends with its next delivery
        k = next((k for k, d in enumerate(delivers) if d >= i and held[0] in steps[d][0].items),
                 None)
        if k is None:
            return [steps]
        groups[k].append(i)
    tail = steps[last + 1:]
    out = [steps]
    for perm in itertools.permutations(range(len(delivers))):
        if list(perm) != sorted(perm):
            order = [steps[i] for k in perm for i in groups[k]] + tail
            if _cells_agree(order, state):
                out.append(order)
    return out


def _cells_agree(steps: Sequence[tuple[PlanStep, str, int]], state: State) -> bool:
    """Does every step find its cell as it needs it, played in this order from ``state``
    (something to pick up or chop there, room to put something down)?"""
    on = {c: i for c, i in enumerate(state.cell_item) if i >= 0}
    plates = _plates(state)
    for step, _, _ in steps:
        here = on.get(step.target)
        if step.kind == "putdown":
            if here is not None:
                return False
            on[step.target] = step.items[0]
        elif step.kind in ("pickup", "chop", "wash"):
            if here is None or here not in step.items:
                return False
            if step.kind == "pickup":
                del on[step.target]
        elif step.kind == "plate" and here is not None and here not in plates:
            if here not in step.items:
                return False
            del on[step.target]  # a plate in the hand took it
        elif step.kind == "deliver":  # the plate and its ingredients respawn
            for item in step.items:  # (one whose tile is taken waits: a later pick fails)
                on.setdefault(state.geo.item_home[item], item)
    return True


#: station kinds whose cells are interchangeable for the schedule
_SWAPPABLE = (int(Cell.BOARD), int(Cell.PAN), int(Cell.SINK))
_COUNTER = int(Cell.COUNTER)
#: free counters an item's stay on a counter may move to (the nearest ones that the same
#: parts of the kitchen reach): a counter is a hand-over place, and a planner that hands two
#: items over through one counter makes the second hand-over wait for the first
COUNTER_CHOICES = 3


@dataclass
class Stay:
    """An item's stay on a station in a plan: the plan steps that target the station
    while the item lies there (put, chops or washes, take)."""

    station: int
    kind: int  # the station's cell code
    steps: list[int]  # indices into the plan
    first: int  # plan index of the put (-1: the item was there before the plan)
    last: int  # plan index of the take (len(plan): still there at the end)


def station_stays(steps: Sequence[tuple[PlanStep, str, int]], state: State,
                  counters: bool = False) -> list[Stay]:
    """Every item's stays on boards, pans and sinks in a plan, in plan order (and on
    counters, with ``counters``: a plate lying there stays while food is put on it)."""
    terrain = state.geo.terrains[state.layout_index]
    kinds = (*_SWAPPABLE, _COUNTER) if counters else _SWAPPABLE
    plates = _plates(state)
    open_: dict[int, Stay] = {}
    lying: dict[int, int] = {}  # cell -> the item its open stay is about
    out: list[Stay] = []
    for cell, item in enumerate(state.cell_item):
        if item >= 0 and terrain[cell] in kinds:
            open_[cell] = Stay(cell, terrain[cell], [], -1, len(steps))
            lying[cell] = item
            out.append(open_[cell])
    for i, (step, effect, _) in enumerate(steps):
        cell = step.target
        if terrain[cell] not in kinds:
            continue
        stay = open_.get(cell)
        if stay is None:
            if effect == RELEASE:  # something is put on the empty station
                open_[cell] = stay = Stay(cell, terrain[cell], [i], i, len(steps))
                lying[cell] = step.items[0] if step.items else -1
                out.append(stay)
            continue
        stay.steps.append(i)
        onto_plate = step.kind == "plate" and lying.get(cell) in plates
        if effect == TAKE or (step.kind == "plate" and not onto_plate):
            stay.last = i  # taken off (in a hand, onto a held plate)
            del open_[cell]
    return out


def counter_choices(state: State) -> dict[int, list[int]]:
    """For every counter a cook can use now: the other counters (at most
    :data:`COUNTER_CHOICES`, nearest first) reached from every part of the kitchen it is
    reached from (so a hand-over counter is swapped only for another hand-over counter)."""
    geo, walk = state.geo, state.geo.walkables[state.layout_index]
    part = [-1] * len(walk)
    for cell, ok in enumerate(walk):
        if ok and part[cell] < 0:
            for c, d in enumerate(distances(geo.neighbors, walk, [cell])):
                if d >= 0:
                    part[c] = cell
    sides = {c: frozenset(part[s] for s in interaction_spots(geo.neighbors, walk, c))
             for c, code in enumerate(geo.terrains[state.layout_index]) if code == _COUNTER}
    sides = {c: p for c, p in sides.items() if p}
    out: dict[int, list[int]] = {}
    for c, p in sides.items():
        (r, k) = geo.rc(c)
        near = sorted((abs(r - geo.rc(o)[0]) + abs(k - geo.rc(o)[1]), o)
                      for o, q in sides.items() if o != c and q >= p)
        out[c] = [o for _, o in near[:COUNTER_CHOICES]]
    return out


def _relabel(steps: list[tuple[PlanStep, str, int]], stay: Stay,
             cell: int) -> list[tuple[PlanStep, str, int]]:
    out = list(steps)
    for i in stay.steps:
        step, effect, bumps = out[i]
        out[i] = (replace(step, target=cell), effect, bumps)
    return out


def _free_over(stays: Sequence[Stay], cell: int, stay: Stay) -> bool:
    """Is ``cell`` free from ``stay``'s first step to its last in plan order?"""
    return all(o is stay or o.station != cell or o.last < stay.first or o.first > stay.last
               for o in stays)


def _best_stations(steps: list[tuple[PlanStep, str, int]], state: State,
                   agents: tuple[int, ...], walks: _Walks, lookahead: int = 0,
                   counters: bool = False) -> list[tuple[PlanStep, str, int]]:
    """Move stays to other stations of their kind, one at a time in plan order, when the
    plain rule's schedule ends better (coordinate descent, a few schedules per stay).
    ``counters``: move the stays on counters instead, each to one of its
    :func:`counter_choices` (with two cooks or more: a counter is where they hand over)."""
    terrain = state.geo.terrains[state.layout_index]
    walk = state.geo.walkables[state.layout_index]
    by_kind: dict[int, list[int]] = {}
    if counters:
        by_kind = counter_choices(state) if len(agents) > 1 else {}
    else:
        for cell, code in enumerate(terrain):
            if code in _SWAPPABLE and interaction_spots(state.geo.neighbors, walk, cell):
                by_kind.setdefault(code, []).append(cell)
    if all(len(cells) < 2 - counters for cells in by_kind.values()):
        return steps

    def cost(plan: list[tuple[PlanStep, str, int]]) -> tuple[int, int, int, int] | None:
        out = _Scheduler(plan, state, agents, walks, lookahead).run()
        return None if out is None else out[1]

    # a plan the list scheduler cannot schedule as it is (two cooks' segments interleave on
    # one board) may schedule once a stay moves to another station: any schedule beats none
    best = cost(steps)
    stays = station_stays(steps, state, counters)
    # a second pass: a move late in the plan can make the plan schedulable (or free a cook)
    # only then, and an earlier stay's move pays after it (hard, 2 cooks, seed 4, step 120:
    # the plate and a lettuce queued on one hand-over counter left a cook idle 27 steps)
    for _ in range(STATION_PASSES):
        moved = False
        for stay in stays:
            if stay.first < 0 or (stay.kind == _COUNTER) != counters:
                continue
            home = stay.station
            for cell in by_kind.get(stay.station if counters else stay.kind, []):
                if cell == stay.station or not _free_over(stays, cell, stay):
                    continue
                trial = _relabel(steps, stay, cell)
                if counters and not _cells_agree(trial, state):
                    continue
                c = cost(trial)
                if c is not None and (best is None or c < best):
                    best, steps, stay.station = c, trial, cell
            moved = moved or stay.station != home
        if not moved:
            break
    return steps


@dataclass
class PlateTrip:
    """A plate's trip in a plan: one cook picks it up from a counter, bumps it against the
    stations of its ingredients (scoops) and delivers it or puts it down again."""

    pickup: int  # plan index of the plate's pickup
    scoops: list[int]  # plan indices of the scoops, in plan order
    deliver: int  # plan index of the delivery or the put-down that ends the trip


def plate_trips(steps: Sequence[tuple[PlanStep, str, int]], state: State) -> list[PlateTrip]:
    """Every trip of a plate from a counter through at least one scoop to the window or
    to a counter."""
    plates = _plates(state)
    terrain = state.geo.terrains[state.layout_index]
    out = []
    for i, (step, effect, _) in enumerate(steps):
        if (step.kind != "pickup" or effect != TAKE or step.items not in [(q,) for q in plates]
                or terrain[step.target] not in COUNTERS):
            continue
        plate, scoops = step.items[0], []
        for j in range(i + 1, len(steps)):
            nxt, nxt_effect, _ = steps[j]
            if nxt.agent != step.agent:
                continue
            if nxt.kind == "plate" and nxt_effect == KEEP and len(nxt.items) == 2 \
                    and nxt.items[1] == plate:
                scoops.append(j)
                continue
            if scoops and (nxt.kind == "deliver" and plate in nxt.items
                           or nxt.kind == "putdown" and nxt.items == (plate,)):
                out.append(PlateTrip(i, scoops, j))
            break
    return out


def plate_carries(steps: list[tuple[PlanStep, str, int]], trip: PlateTrip,
                  state: State) -> list[list[tuple[PlanStep, str, int]]]:
    """The plan with the trip's first scoops turned into carries: each of those ingredients
    is picked up by hand and put on the plate where the plate lies, in every order, and the
    plate is picked up after the last of them (not at all when every scoop is carried and
    the trip puts the plate back on the same counter). The carries take the place of the
    last scoop they replace, so a variant is left out when anything else touches the
    plate's counter, the plate, a carried ingredient or its station in between, or when the
    cells disagree (:func:`_cells_agree`)."""
    pick = steps[trip.pickup][0]
    plate, counter = pick.items[0], pick.target
    out = []
    for m in range(1, len(trip.scoops) + 1):
        carried, last = trip.scoops[:m], trip.scoops[m - 1]
        if any(counter == steps[i][0].target or plate in steps[i][0].items
               for i in range(trip.pickup + 1, last) if i not in carried):
            continue
        if any(steps[i][0].target == steps[s][0].target or steps[s][0].items[0] in steps[i][0].items
               for s in carried for i in range(s + 1, last + 1) if i not in carried):
            continue
        for perm in itertools.permutations(carried):
            block: list[tuple[PlanStep, str, int]] = []
            for s in perm:
                scoop = steps[s][0]
                block += [(replace(scoop, kind="pickup", items=scoop.items[:1]), TAKE, 1),
                          (replace(scoop, kind="plate", target=counter), RELEASE, 1)]
            tail = steps[last + 1:]
            end = steps[trip.deliver][0]
            if m == len(trip.scoops) and end.kind == "putdown" and end.target == counter:
                # every scoop carried and the plate put back where it was: it never moves
                tail = [e for i, e in enumerate(tail, last + 1) if i != trip.deliver]
            else:
                block.append(steps[trip.pickup])
            variant = [e for i, e in enumerate(steps[:last]) if i != trip.pickup
                       and i not in carried] + block + tail
            if _cells_agree(variant, state):
                out.append(variant)
    return out


def plate_stays_home(steps: list[tuple[PlanStep, str, int]],
                     state: State) -> list[list[tuple[PlanStep, str, int]]]:
    """The plan without a move of a plate from one counter to another: a cook picks a
    plate up from a counter and, as its next step, puts it on another (or the same one),
    where ingredients are carried to it until it is picked up again. A planner minimising
    one cook's walk brings the plate near the boards; with several cooks it may as well
    stay where it was and the ingredients come to it. One variant per move (the stay's
    steps relabelled to the plate's counter, the pick-up and put-down dropped), and one
    with every move dropped, one after the other; each kept when the cells agree
    (:func:`_cells_agree`)."""
    plates, terrain = _plates(state), state.geo.terrains[state.layout_index]
    out = []
    for i in range(len(steps)):
        variant = _plate_stays(steps, i, state, plates, terrain)
        if variant is not None:
            out.append(variant)
    if len(out) > 1:
        every = out[0]
        for _ in range(len(steps)):
            nxt = next((v for i in range(len(every))
                        if (v := _plate_stays(every, i, state, plates, terrain)) is not None),
                       None)
            if nxt is None:
                break
            every = nxt
        out.append(every)
    return out


def _plate_stays(steps: list[tuple[PlanStep, str, int]], i: int, state: State,
                 plates: set[int],
                 terrain: Sequence[int]) -> list[tuple[PlanStep, str, int]] | None:
    """:func:`plate_stays_home` for the plate picked up at plan index ``i`` (None: no
    move of a plate from a counter there, or the cells disagree)."""
    step, effect, _ = steps[i]
    if step.kind != "pickup" or effect != TAKE or len(step.items) != 1 \
            or step.items[0] not in plates or terrain[step.target] not in COUNTERS:
        return None
    plate, home = step.items[0], step.target
    put = next((j for j in range(i + 1, len(steps)) if steps[j][0].agent == step.agent), None)
    if put is None or steps[put][0].kind != "putdown" or steps[put][0].items != (plate,):
        return None
    away = steps[put][0].target
    if terrain[away] not in COUNTERS:  # a sink (the plate is washed there), not a counter
        return None
    stay = []  # the steps at the other counter while the plate lies there
    if away != home:
        for j in range(put + 1, len(steps)):
            nxt = steps[j][0]
            if nxt.target == home:
                break
            if nxt.target == away:
                if plate not in nxt.items:
                    break
                stay.append(j)
                if nxt.kind == "pickup":
                    break
        if not stay or steps[stay[-1]][0].kind != "pickup":
            return None
    variant = [(replace(s, target=home), e, b) if j in stay else (s, e, b)
               for j, (s, e, b) in enumerate(steps) if j not in (i, put)]
    return variant if _cells_agree(variant, state) else None


def unparked(steps: list[tuple[PlanStep, str, int]],
             state: State) -> list[list[tuple[PlanStep, str, int]]]:
    """The plan with an ingredient put straight where it goes next: an ingredient put down
    on a counter, picked up there later and, as that cook's next step, put on a station
    (Kairos parks a tomato on a counter on its way to the board) is put on that station
    the first time, and the pick-up and second put-down go. One variant per parking, kept
    when the cells agree (:func:`_cells_agree`)."""
    plates = _plates(state)
    terrain = state.geo.terrains[state.layout_index]
    out = []
    for i, (step, effect, _) in enumerate(steps):
        if step.kind != "putdown" or effect != RELEASE or len(step.items) != 1 \
                or step.items[0] in plates or terrain[step.target] not in COUNTERS:
            continue
        item, counter = step.items[0], step.target
        later = [j for j in range(i + 1, len(steps))
                 if item in steps[j][0].items or steps[j][0].target == counter]
        if not later or steps[later[0]][0].kind != "pickup" or item not in steps[later[0]][0].items:
            continue
        take = later[0]
        cook = steps[take][0].agent
        put = next((j for j in range(take + 1, len(steps)) if steps[j][0].agent == cook), None)
        if put is None or steps[put][0].kind != "putdown" or steps[put][0].items != (item,):
            continue
        variant = [(replace(s, target=steps[put][0].target), e, b) if j == i else (s, e, b)
                   for j, (s, e, b) in enumerate(steps) if j not in (take, put)]
        if _cells_agree(variant, state):
            out.append(variant)
    return out


def plating_variants(steps: list[tuple[PlanStep, str, int]],
                     state: State) -> list[list[tuple[PlanStep, str, int]]]:
    """Every plan one plating change away: a plate that stays home (:func:`plate_stays_home`)
    or a plate trip whose first scoops become carries (:func:`plate_carries`), and a plate
    that stays home with its trip's scoops carried (a move towards the boards and a scoop
    there are one detour: dropping either alone may not pay); and an ingredient put
    straight on its station instead of parked on a counter first (:func:`unparked`)."""
    homes = plate_stays_home(steps, state)
    out = list(homes) + unparked(steps, state)
    for plan in [steps, *homes]:
        for trip in plate_trips(plan, state):
            out += plate_carries(plan, trip, state)
    return out


#: rounds of plating changes tried one after the other (each from the best plan so far)
PLATING_ROUNDS = 2
#: per round, the variants that schedule best as they are get their stations chosen
PLATING_SETTLED = 3


def _best_plating(steps: list[tuple[PlanStep, str, int]], state: State,
                  agents: tuple[int, ...], walks: _Walks, lookahead: int = 0,
                  swap_stations: bool = True) -> list[tuple[PlanStep, str, int]]:
    """The plan, or one of its plating variants (:func:`plating_variants`) with its
    stations chosen (:func:`_best_stations`), whichever schedules best; up to
    :data:`PLATING_ROUNDS` changes, each from the best plan of the round before. A change
    of the plate's route often pays only with another board for an ingredient, so the
    :data:`PLATING_SETTLED` variants that schedule best as they are get their own choice
    of stations before they are compared."""

    def settle(plan: list[tuple[PlanStep, str, int]]) -> list[tuple[PlanStep, str, int]]:
        return _best_stations(plan, state, agents, walks, lookahead) if swap_stations else plan

    def cost(plan: list[tuple[PlanStep, str, int]]) -> tuple[int, int, int, int] | None:
        out = _Scheduler(plan, state, agents, walks, lookahead).run()
        return None if out is None else out[1]

    steps = settle(steps)
    best = cost(steps)  # None: not schedulable as it is; any variant that is wins
    for _ in range(PLATING_ROUNDS):
        improved = False
        raw = [(c, i, v) for i, v in enumerate(plating_variants(steps, state))
               if (c := cost(v)) is not None]
        for _, _, variant in sorted(raw, key=lambda x: x[:2])[:PLATING_SETTLED]:
            variant = settle(variant)
            c = cost(variant)
            if c is not None and (best is None or c < best):
                best, found, improved = c, variant, True
        if not improved:
            break
        steps = found
    return steps



__all__ = ["COUNTER_CHOICES", "MAX_DISHES_REORDERED", "PLATING_ROUNDS", "PLATING_SETTLED", "PlateTrip", "Stay",
           "dish_orders", "plate_carries", "plate_stays_home", "plate_trips", "plating_variants",
           "counter_choices", "station_stays", "unparked", "without_idle_work"]

"""Schedule a sequential plan over the cooks: who does each piece of work, and in what order.

A classical planner minimises the *sum* of its actions' costs, so for several cooks it
has no reason to share the work: on easy with two cooks Fast Downward's optimal plan
for two orders costs the same as with one cook, and one cook does nearly everything.
The executive runs each cook's steps in parallel, so the makespan is what matters.

This module lifts a sequential plan into a parallel one, the way a scheduler does after
a planner (partial-order lifting plus list scheduling):

* the plan is cut into *segments*: the steps one cook does from picking an item up to
  letting it go (a hand-over through a counter ends a segment), and every free-handed
  step (a chop, a wash) alone. A segment must stay with one cook, in its order;
* a segment depends on every segment with an earlier step that touches a cell or item
  one of its steps touches later (the order the sequential plan relies on); two segments
  that would have to interleave leave the plan as it is;
* list scheduling: segments are taken in the plan's order (the planner chose it for its
  cost), each by the cook that would *finish* it first, with walking times from the
  kitchen's shortest walks, bumps as the plan's costs and a steak's remaining cooking
  time on the pan; a cook that would wait (a steak still cooking) first does a later
  segment that does not delay it (backfilling). A cook that holds an item now does its
  own segment first. (Placing whichever available segment finishes first instead gave the
  same dishes with two cooks and walked a single cook further, off its cost-optimal order.)
* lookahead (a one-step rollout): at each choice the first few ready segments are also
  tried with every cook allowed to do them, the rest of the schedule is finished with the
  rule above, and the choice whose schedule ends best is kept (no steak left on a pan past
  its burn time, then the makespan, then the earliest deliveries): a cook that puts a
  steak on the pan goes to chop while it cooks even when that does not fit exactly in the
  wait, and another cook may plate it;
* identical stations: the planner does not care which of two boards (pans, sinks) an item
  goes on, the schedule does; an item's stay on a station moves to another one of its kind
  that is free over that stretch of the plan when the schedule then ends sooner;
* dish order: a plan's dishes that share no ingredient are also scheduled in their other
  orders (:func:`dish_orders`), so a dish whose ingredients are ready first need not wait
  for the plate behind one the planner happened to list first;
* plating route: a plate can go to its ingredients (picked up, then bumped against each
  ingredient's board or pan) or the ingredients can come to the plate (each carried by hand
  onto it where it lies, the plate picked up last). The planner picks one for its cost; the
  first is a single segment one cook must walk, the second is one segment per ingredient
  that any cook can carry while another waits at the pan. The schedule tries carrying the
  first scoops of each plate trip to the plate, in each order (:func:`plate_carries`),
  leaving a plate where it lies instead of moving it from counter to counter
  (:func:`plate_stays_home`) and putting an ingredient straight on its station instead of
  parking it on a counter first (:func:`unparked`), and keeps what ends sooner;
* idle work: a segment that delivers nothing and that no later step needs is dropped
  (:func:`without_idle_work`; a satisficing planner may fetch an ingredient no order wants).
* layout switches (``switches``): walks are timed over the coming switches (a cook cut
  off now waits for the switch that opens its way; one free now may be cut off later).

The result is the plan's steps (with the plating and idle-work changes above) with cooks
reassigned, renumbered in scheduled order and stamped with their estimated start (a
time-triggered plan's own times are replaced); the executive then routes, monitors and
recovers as for any plan. The planner decides *what* is served from which items; the
schedule decides *who*, *when*, and which of the equivalent routes. Nothing here changes a
rule: the times are estimates (collisions are ignored) used only to order and assign, and
every plating variant and dish order is checked cell by cell (:func:`_cells_agree`).
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

from ..sim.codes import COUNTERS, Cell, Item, ItemState, Where
from ..sim.queries import (
    distances,
    interaction_spots,
    switching_walks,
    ticks_until_burnt,
    ticks_until_cooked,
    walkable_in_any_layout,
)
from ..sim.state import State
from .paths import DistanceOracle
from .plans import PlanStep

#: what a step does to its cook's hand
TAKE, RELEASE, KEEP = "take", "release", "keep"


@dataclass
class Segment:
    """Steps one cook must do together, from an empty hand to an empty hand."""

    steps: list[tuple[PlanStep, str, int]]  # (step, hand effect, bumps it takes)
    pinned: int | None = None  # the cook that must do it (it holds the item now)
    deps: set[int] = field(default_factory=set)
    open_end: bool = False  # the plan leaves the item in the hand


def segments(steps: Sequence[tuple[PlanStep, str, int]], state: State) -> list[Segment]:
    """Cut a plan (steps in plan order with their hand effects) into segments."""
    holding = {a: state.agent_hand[a] >= 0 for a in range(state.n_agents)}
    current: dict[int, int] = {}  # cook -> index of its open segment
    out: list[Segment] = []
    last: dict[tuple[str, int], int] = {}  # resource -> segment of the last step touching it
    for entry in steps:
        step, effect, _ = entry
        a = step.agent
        k = current.get(a)
        if k is None:
            k = len(out)
            out.append(Segment([], pinned=a if holding[a] else None))
            if holding[a] or effect == TAKE:
                current[a] = k
        seg = out[k]
        for res in _resources(step):
            if last.get(res, k) != k:
                seg.deps.add(last[res])
            last[res] = k
        seg.steps.append(entry)
        if effect == TAKE:
            holding[a] = True
        elif effect == RELEASE:
            holding[a] = False
        if not holding[a]:
            current.pop(a, None)
    for k in current.values():
        out[k].open_end = True
    return out


class _Walks:
    """Walking estimates for the schedule: current layout first, any layout as a fallback.
    With ``switches`` (a switching map), a walk that starts ``at`` steps from now is timed
    over the coming layout switches instead (:class:`~ocplus_plan.sim.queries.SwitchingWalks`:
    it may wait for a switch to open its way). Answers are kept: one schedule call asks the
    same walks for every candidate it tries."""

    def __init__(self, state: State, oracle: DistanceOracle, switches: bool = False) -> None:
        self.geo, self.layout, self.oracle = state.geo, state.layout_index, oracle
        self.walk = state.geo.walkables[state.layout_index]
        self.any_walk = walkable_in_any_layout(state.geo)
        self.detour = max(1, state.rules.map_switch_step) if state.rules.dynamic else 0
        self._any: dict[int, list[int]] = {}
        self._known: dict[tuple[int, int, int, int], tuple[int, int]] = {}
        self.timed = None
        if switches and state.rules.dynamic and len(state.geo.walkables) == 2:
            self.timed = switching_walks(state.geo, state.rules.map_switch_step)
            self.due = max(0, state.next_switch - state.t)

    def to(self, pos: int, target: int, at: int = 0) -> tuple[int, int]:
        """(steps to reach a spot of ``target`` from ``pos``, the spot reached), leaving
        ``at`` steps from now."""
        if self.timed is None:
            key = (pos, target, 0, 0)
        else:  # the walk depends on the layout then and on when it next switches
            key = (pos, target, *self.timed.phase(self.layout, self.due, at))
        if key not in self._known:
            self._known[key] = self._to(pos, target) if self.timed is None \
                else self._timed(pos, target, key[2], key[3])
        return self._known[key]

    def _timed(self, pos: int, target: int, layout: int, due: int) -> tuple[int, int]:
        assert self.timed is not None
        found = self.timed.arrival(pos, target, layout, due)
        return found if found is not None else (10 * len(self.walk), pos)

    def _to(self, pos: int, target: int) -> tuple[int, int]:
        spots = interaction_spots(self.geo.neighbors, self.walk, target)
        best = None
        for s in spots:
            d = self.oracle.to_goals(self.layout, [s])[pos]
            if d >= 0 and (best is None or d < best[0]):
                best = (d, s)
        if best is not None:
            return best
        # cut off in this layout: walk over every layout's floor and wait for a switch
        for s in interaction_spots(self.geo.neighbors, self.any_walk, target):
            if s not in self._any:
                self._any[s] = distances(self.geo.neighbors, self.any_walk, [s])
            d = self._any[s][pos]
            if d >= 0 and (best is None or d < best[0]):
                best = (d + self.detour, s)
        return best if best is not None else (10 * len(self.walk), pos)


class _Partial:
    """A schedule under construction: when each cook is free and where, and what is placed."""

    def __init__(self, agents: Sequence[int], state: State) -> None:
        self.free_at = {a: 0 for a in agents}
        self.pos = {a: state.agent_pos[a] for a in agents}
        self.busy_until: dict[tuple[str, int], int] = {}  # resource -> when its last step ends
        self.pan_ready: dict[int, int] = {}  # pan cell -> when its steak is cooked
        self.pan_burnt: dict[int, int] = {}  # pan cell -> when its steak burns
        for pan in state.geo.pans:
            steak = state.cell_item[pan]
            if steak >= 0:
                ticks = state.item_progress[steak]
                self.pan_ready[pan] = ticks_until_cooked(state.rules, ticks)
                self.pan_burnt[pan] = ticks_until_burnt(state.rules, ticks)
        self.closed: set[int] = set()  # cooks that keep an item to the end of the plan
        self.waiting_pin: set[int | None] = set()
        self.done: set[int] = set()
        #: (start, order, step, the cook that does it)
        self.placed: list[tuple[int, int, PlanStep, int]] = []
        self.served: set[int] = set()  # items delivered so far: they come back fresh
        self.late = 0  # steps by which takes from a pan come after its steak burns

    def copy(self) -> _Partial:
        out = copy.copy(self)
        for name in ("free_at", "pos", "busy_until", "pan_ready", "pan_burnt"):
            setattr(out, name, dict(getattr(self, name)))
        for name in ("closed", "waiting_pin", "done", "served"):
            setattr(out, name, set(getattr(self, name)))
        out.placed = list(self.placed)
        return out

    def cost(self) -> tuple[int, int, int]:
        """What the lookahead minimises: burnt steaks first, then the makespan, then how
        early the dishes go out (the sum of the deliveries' starts)."""
        makespan = max(self.free_at.values(), default=0)
        served = sum(start for start, _, step, _ in self.placed if step.kind == "deliver")
        return self.late, makespan, served


class _Scheduler:
    """List scheduling of a plan's segments, with a rollout lookahead (see :func:`schedule`)."""

    def __init__(self, steps: Sequence[tuple[PlanStep, str, int]], state: State,
                 agents: tuple[int, ...], walks: _Walks, lookahead: int) -> None:
        self.state, self.agents, self.lookahead = state, agents, lookahead
        self.walks = walks
        self.segs = segments(steps, state)
        #: each step's resources (cells and items), asked for at every simulated step
        self.resources = {id(step): _resources(step) for step, _, _ in steps}

    def simulate(self, p: _Partial, k: int, a: int, t: int | None = None,
                 here: int | None = None) -> tuple[int, list[int], int]:
        """(end, each step's start, where the cook ends) if cook ``a`` does segment ``k``
        next, from time ``t`` and cell ``here`` (default: when and where it is free)."""
        t = p.free_at[a] if t is None else t
        here = p.pos[a] if here is None else here
        starts = []
        for step, effect, bumps in self.segs[k].steps:
            walk, here = self.walks.to(here, step.target, t)
            t += walk
            ready = max((p.busy_until.get(r, 0) for r in self.resources[id(step)]), default=0)
            if step.target in p.pan_ready and _takes(step, effect):
                ready = max(ready, p.pan_ready[step.target])
            t = max(t, ready)
            starts.append(t)
            t += max(1, bumps)
        return t, starts, here

    def cooks_for(self, p: _Partial, k: int) -> list[int]:
        seg = self.segs[k]
        if seg.pinned is not None:
            return [seg.pinned]
        return [a for a in self.agents if a not in p.waiting_pin and a not in p.closed]

    def ready(self, p: _Partial) -> list[int]:
        return [k for k in range(len(self.segs))
                if k not in p.done and self.segs[k].deps <= p.done]

    def best_cook(self, p: _Partial, k: int) -> tuple[int, int, list[int], int] | None:
        """(cook, end, starts, where it ends) for the cook that finishes segment ``k`` first."""
        out = None
        first = self.segs[k].steps[0][0].agent
        for a in self.cooks_for(p, k):
            end, starts, here = self.simulate(p, k, a)
            key = (end, a != first, a)
            if out is None or key < out[0]:
                out = (key, end, starts, here)
        return None if out is None else (out[0][2], out[1], out[2], out[3])

    def base_choice(self, p: _Partial) -> tuple[int, int] | None:
        """The plain list-scheduling rule: the plan's next segment by the cook that finishes
        it first, unless that cook would wait and a later segment fits in the wait
        (backfilling). None when nobody may take what is left."""
        ready = self.ready(p)
        options = {k: opt for k in ready if (opt := self.best_cook(p, k)) is not None}
        if not options:
            return None
        head = ready[0]
        if head not in options:  # the plan's next segment has no free cook yet
            k = min(options, key=lambda j: (options[j][1], options[j][0], j))
            return k, options[k][0]
        a, end, _, _ = options[head]
        for k2 in ready[1:]:
            if k2 not in options or a not in self.cooks_for(p, k2):
                continue
            end2, _, here2 = self.simulate(p, k2, a)
            if self.simulate(p, head, a, end2, here2)[0] <= end:  # fits in the wait
                return k2, a
        return head, a

    def place(self, p: _Partial, k: int, a: int) -> None:
        seg = self.segs[k]
        end, starts, here = self.simulate(p, k, a)
        for (step, effect, bumps), start in zip(seg.steps, starts):
            p.placed.append((start, len(p.placed), step, a))
            for r in self.resources[id(step)]:
                p.busy_until[r] = start + max(1, bumps)
            if step.target in p.pan_burnt and _takes(step, effect):
                p.late += max(0, start - p.pan_burnt.pop(step.target) + _BURN_MARGIN)
                p.pan_ready.pop(step.target, None)
            if step.kind == "deliver":
                p.served.update(step.items)
            if effect == RELEASE and step.target in self.state.geo.pans and step.items:
                # a steak served earlier in the plan comes back raw (chained orders)
                steak = step.items[0]
                ticks = 0 if steak in p.served else self.state.item_progress[steak]
                p.pan_ready[step.target] = start + 1 + ticks_until_cooked(self.state.rules, ticks)
                p.pan_burnt[step.target] = start + 1 + ticks_until_burnt(self.state.rules, ticks)
        p.free_at[a], p.pos[a] = end, here
        p.done.add(k)
        p.waiting_pin.discard(seg.pinned)
        if seg.open_end:
            p.closed.add(a)

    def rollout(self, p: _Partial) -> _Partial | None:
        """Finish ``p`` with the plain rule; None when it gets stuck."""
        while len(p.done) < len(self.segs):
            choice = self.base_choice(p)
            if choice is None:
                return None
            self.place(p, *choice)
        return p

    def choose(self, p: _Partial) -> tuple[int, int] | None:
        """The next (segment, cook): the plain rule's choice, or one of the first ready
        segments with any cook allowed to do it when finishing the schedule from there with
        the plain rule ends better (a one-step rollout: never worse than the plain rule by
        the schedule's own estimate)."""
        base = self.base_choice(p)
        if base is None or self.lookahead <= 0:
            return base
        done = self.rollout(self._after(p, base))
        best, best_cost = base, (done.cost() if done is not None else None)
        for k in self.ready(p)[: self.lookahead]:
            for a in self.cooks_for(p, k):
                if (k, a) == base:
                    continue
                done = self.rollout(self._after(p, (k, a)))
                if done is not None and (best_cost is None or done.cost() < best_cost):
                    best, best_cost = (k, a), done.cost()
        return best

    def _after(self, p: _Partial, choice: tuple[int, int]) -> _Partial:
        q = p.copy()
        self.place(q, *choice)
        return q

    def run(self) -> tuple[list[PlanStep], tuple[int, int, int]] | None:
        """The scheduled steps and the schedule's cost; None when it gets stuck."""
        p = _Partial(self.agents, self.state)
        p.waiting_pin = {s.pinned for s in self.segs if s.pinned is not None}
        while len(p.done) < len(self.segs):
            choice = self.choose(p)
            if choice is None:
                return None
            self.place(p, *choice)
        placed = sorted(p.placed, key=lambda x: (x[0], x[1]))
        return [replace(step, index=i, agent=a, start=float(start))
                for i, (start, _, step, a) in enumerate(placed)], p.cost()


#: steps of slack the schedule keeps before a steak would burn on its pan: the executive
#: replans when no queued step takes a steak with 6 ticks left (``burn_risk``), and a plan
#: made in a hurry may trash the steak; Kairos on medium with one cook served 2.2-2.3 dishes
#: with 2-4 steps of slack (a burn-risk replan in most episodes), 3.1-3.2 with 5-10
#: (experiments/bench_executive.py, 10 seeds), Fast Downward 3.5 with 2 and with 6
_BURN_MARGIN = 6
#: how many of the first ready segments the rollout lookahead tries at each choice
LOOKAHEAD = 4


def schedule(steps: Sequence[tuple[PlanStep, str, int]], state: State,
             agents: Sequence[int], oracle: DistanceOracle | None = None,
             lookahead: int = LOOKAHEAD, swap_stations: bool = True,
             reorder_dishes: bool = True, carry_to_plates: bool = True,
             switches: bool = False, fallback: bool = True) -> list[PlanStep] | None:
    """Reassign and reorder a sequential plan's steps over ``agents`` (see the module doc).

    ``steps`` are in plan order, each with its hand effect (TAKE, RELEASE, KEEP) and the
    bumps it takes. The plain rule: segments are taken in the plan's order (the planner
    chose it for its cost), each by the cook that finishes it first, and a cook that would
    wait for the next one (a steak still cooking, a board still busy) first does a later
    segment that does not delay it (backfilling). With ``lookahead=K`` each choice also
    tries the first K ready segments with every cook allowed to do them, finishes the
    schedule from each with the plain rule, and keeps the one that ends best: no steak left
    to burn, then the shortest makespan, then the earliest deliveries (a cook that puts a
    steak on the pan goes to chop while it cooks and another cook may plate it).

    ``swap_stations``: a planner minimising cost does not care which of two identical
    boards (pans, sinks) it uses, but the schedule does: two vegetables planned on one board
    must be chopped one after the other. Each stay of an item on a station (from the step
    that puts it there to the one that takes it off) may move to another station of the
    same kind that is free over that stretch of the plan (:func:`station_stays`); a stay is
    moved when the plain rule's schedule then ends better.

    ``reorder_dishes``: the plan's dishes are also scheduled in every other order they can
    be served in (:func:`dish_orders`), and the schedule that ends best is kept.

    ``carry_to_plates``: the plan's plating route may change (:func:`plating_variants`: a
    plate that stays where it lies while its ingredients are carried to it, an ingredient
    put straight on its station); the variant whose schedule ends best is kept.

    ``switches`` (a switching map): walks are timed over the coming layout switches (a cook
    cut off now waits for the switch that opens its way; one free now may be cut off when
    it gets there), so the work goes to the cook that can get there at that time.

    Work that serves no order is dropped first (:func:`without_idle_work`). A plan with
    steps of cooks outside ``agents`` is left as it is, and so is a plan whose segments
    cannot be scheduled (two cooks' segments that must interleave), unless ``fallback`` is
    False: then None says so (the caller may schedule a shorter plan)."""
    agents = tuple(agents)
    if not agents or any(s.agent not in agents for s, _, _ in steps):
        return _in_plan_order(steps)
    walks = _Walks(state, oracle or DistanceOracle(state.geo), switches)
    steps = without_idle_work(list(steps), state)
    best = None
    for order in dish_orders(steps, state) if reorder_dishes else [steps]:
        if carry_to_plates:
            order = _best_plating(order, state, agents, walks, lookahead, swap_stations)
        elif swap_stations:
            order = _best_stations(order, state, agents, walks, lookahead)
        out = _Scheduler(order, state, agents, walks, lookahead).run()
        if out is not None and (best is None or out[1] < best[1]):
            best = out
    if best is None:
        return _in_plan_order(steps) if fallback else None
    return best[0]


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


@dataclass
class Stay:
    """An item's stay on a station in a plan: the plan steps that target the station
    while the item lies there (put, chops or washes, take)."""

    station: int
    kind: int  # the station's cell code
    steps: list[int]  # indices into the plan
    first: int  # plan index of the put (-1: the item was there before the plan)
    last: int  # plan index of the take (len(plan): still there at the end)


def station_stays(steps: Sequence[tuple[PlanStep, str, int]], state: State) -> list[Stay]:
    """Every item's stays on boards, pans and sinks in a plan, in plan order."""
    terrain = state.geo.terrains[state.layout_index]
    open_: dict[int, Stay] = {}
    out: list[Stay] = []
    for cell, item in enumerate(state.cell_item):
        if item >= 0 and terrain[cell] in _SWAPPABLE:
            open_[cell] = Stay(cell, terrain[cell], [], -1, len(steps))
            out.append(open_[cell])
    for i, (step, effect, _) in enumerate(steps):
        cell = step.target
        if terrain[cell] not in _SWAPPABLE:
            continue
        stay = open_.get(cell)
        if stay is None:
            if effect == RELEASE:  # something is put on the empty station
                open_[cell] = stay = Stay(cell, terrain[cell], [i], i, len(steps))
                out.append(stay)
            continue
        stay.steps.append(i)
        if effect == TAKE or step.kind == "plate":  # taken off (in a hand, onto a plate)
            stay.last = i
            del open_[cell]
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
                   agents: tuple[int, ...], walks: _Walks,
                   lookahead: int = 0) -> list[tuple[PlanStep, str, int]]:
    """Move stays to other stations of their kind, one at a time in plan order, when the
    plain rule's schedule ends better (coordinate descent, a few schedules per stay)."""
    terrain = state.geo.terrains[state.layout_index]
    walk = state.geo.walkables[state.layout_index]
    by_kind: dict[int, list[int]] = {}
    for cell, code in enumerate(terrain):
        if code in _SWAPPABLE and interaction_spots(state.geo.neighbors, walk, cell):
            by_kind.setdefault(code, []).append(cell)
    if all(len(cells) < 2 for cells in by_kind.values()):
        return steps

    def cost(plan: list[tuple[PlanStep, str, int]]) -> tuple[int, int, int] | None:
        out = _Scheduler(plan, state, agents, walks, lookahead).run()
        return None if out is None else out[1]

    best = cost(steps)
    if best is None:
        return steps
    stays = station_stays(steps, state)
    for stay in stays:
        if stay.first < 0 or len(by_kind.get(stay.kind, ())) < 2:
            continue
        home = stay.station
        for cell in by_kind[stay.kind]:
            if cell == home or not _free_over(stays, cell, stay):
                continue
            trial = _relabel(steps, stay, cell)
            c = cost(trial)
            if c is not None and c < best:
                best, steps, stay.station = c, trial, cell
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

    def cost(plan: list[tuple[PlanStep, str, int]]) -> tuple[int, int, int] | None:
        out = _Scheduler(plan, state, agents, walks, lookahead).run()
        return None if out is None else out[1]

    steps = settle(steps)
    best = cost(steps)
    if best is None:
        return steps
    for _ in range(PLATING_ROUNDS):
        improved = False
        raw = [(c, i, v) for i, v in enumerate(plating_variants(steps, state))
               if (c := cost(v)) is not None]
        for _, _, variant in sorted(raw, key=lambda x: x[:2])[:PLATING_SETTLED]:
            variant = settle(variant)
            c = cost(variant)
            if c is not None and c < best:
                best, found, improved = c, variant, True
        if not improved:
            break
        steps = found
    return steps


def _plates(state: State) -> set[int]:
    """The kitchen's plates (item ids)."""
    return {q for q, kind in enumerate(state.geo.item_kind) if kind == int(Item.PLATE)}


def _takes(step: PlanStep, effect: str) -> bool:
    """Does the step take what lies on its cell (into the hand, or onto a held plate)?"""
    return effect == TAKE or step.kind == "plate"


def _in_plan_order(steps: Sequence[tuple[PlanStep, str, int]]) -> list[PlanStep]:
    return [replace(s, index=i) for i, (s, _, _) in enumerate(steps)]


def _resources(step: PlanStep) -> list[tuple[str, int]]:
    return [("c", step.target), *(("i", i) for i in step.items)]


__all__ = ["KEEP", "RELEASE", "TAKE", "PlateTrip", "Segment", "Stay", "dish_orders",
           "plate_carries", "plate_trips", "schedule", "segments", "station_stays",
           "unparked", "without_idle_work"]

"""The list scheduler behind :func:`~.schedule.schedule`: segments, walks and partial schedules.

A plan (steps in plan order with their hand effects) is cut into segments (:func:`segments`),
and :class:`Scheduler` assigns them to cooks by list scheduling with a one-step rollout
lookahead (see :mod:`.schedule` for the whole method). Walking times come from
:class:`Walks`; a :class:`Partial` is a schedule under construction.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

from ..sim.codes import Item
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
        #: on a switching map, the sum of every step's start is the cost's last term
        self.early_work = state.rules.dynamic

    def copy(self) -> _Partial:
        out = copy.copy(self)
        for name in ("free_at", "pos", "busy_until", "pan_ready", "pan_burnt"):
            setattr(out, name, dict(getattr(self, name)))
        for name in ("closed", "waiting_pin", "done", "served"):
            setattr(out, name, set(getattr(self, name)))
        out.placed = list(self.placed)
        return out

    def cost(self) -> tuple[int, int, int, int]:
        """What the lookahead (and every choice between schedules) minimises: burnt steaks
        first, then the makespan, then how early the dishes go out (the sum of the
        deliveries' starts), then, on a switching map, how early all the work is done (the
        sum of every step's start): work a cook can do while another waits for a switch or
        a hand-over is done then rather than later. On static kitchens that last term cost
        easy with two cooks dishes (seeds 2 and 4: 12 against 15) and is 0."""
        makespan = max(self.free_at.values(), default=0)
        served = sum(start for start, _, step, _ in self.placed if step.kind == "deliver")
        flow = sum(start for start, _, _, _ in self.placed) if self.early_work else 0
        return self.late, makespan, served, flow


class _Scheduler:
    """List scheduling of a plan's segments, with a rollout lookahead (see :func:`schedule`)."""

    def __init__(self, steps: Sequence[tuple[PlanStep, str, int]], state: State,
                 agents: tuple[int, ...], walks: _Walks, lookahead: int) -> None:
        self.state, self.agents, self.lookahead = state, agents, lookahead
        self.walks = walks
        self.segs = segments(steps, state)
        #: each step's resources (cells and items, and the floor cell it is worked from
        #: when that is the station's only one: one cook stands there at a time), asked for
        #: at every simulated step
        only = {t: c[0] for t in {step.target for step, _, _ in steps}
                if len(c := interaction_spots(state.geo.neighbors, walks.walk, t)) == 1}
        self.resources = {id(step): _resources(step) + ([("s", only[step.target])]
                                                       if step.target in only else [])
                          for step, _, _ in steps}

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

    def run(self) -> tuple[list[PlanStep], tuple[int, int, int, int]] | None:
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




#: public names of the scheduler's parts (the variant passes build on them)
Walks, Partial, Scheduler = _Walks, _Partial, _Scheduler

__all__ = ["KEEP", "LOOKAHEAD", "RELEASE", "TAKE", "Partial", "Scheduler", "Segment", "Walks",
           "segments"]

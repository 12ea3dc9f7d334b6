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

The result is the same steps with cooks reassigned, renumbered in scheduled order and
stamped with their estimated start (a time-triggered plan's own times are replaced);
the executive then routes, monitors and recovers as for any plan. The planner decides
*what* is done; the schedule decides *who* and *when*. Nothing here changes a rule: the
times are estimates (collisions are ignored) used only to order and assign.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

from ..sim.queries import (
    distances,
    interaction_spots,
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
    """Walking estimates for the schedule: current layout first, any layout as a fallback."""

    def __init__(self, state: State, oracle: DistanceOracle) -> None:
        self.geo, self.layout, self.oracle = state.geo, state.layout_index, oracle
        self.walk = state.geo.walkables[state.layout_index]
        self.any_walk = walkable_in_any_layout(state.geo)
        self.detour = max(1, state.rules.map_switch_step) if state.rules.dynamic else 0
        self._any: dict[int, list[int]] = {}

    def to(self, pos: int, target: int) -> tuple[int, int]:
        """(steps to reach a spot of ``target`` from ``pos``, the spot reached)."""
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


def schedule(steps: Sequence[tuple[PlanStep, str, int]], state: State,
             agents: Sequence[int], oracle: DistanceOracle | None = None) -> list[PlanStep]:
    """Reassign and reorder a sequential plan's steps over ``agents`` (see the module doc).

    ``steps`` are in plan order, each with its hand effect (TAKE, RELEASE, KEEP) and the
    bumps it takes. Segments are taken in the plan's order (the planner chose it for its
    cost), each by the cook that finishes it first, and a cook that would wait for the next
    one (a steak still cooking, a board still busy) first does a later segment that does
    not delay it (backfilling); with one cook only that backfilling changes anything. A plan
    with steps of cooks outside ``agents`` is left as it is."""
    agents = tuple(agents)
    if not agents or any(s.agent not in agents for s, _, _ in steps):
        return _in_plan_order(steps)
    walks = _Walks(state, oracle or DistanceOracle(state.geo))
    segs = segments(steps, state)
    free_at = {a: 0 for a in agents}
    pos = {a: state.agent_pos[a] for a in agents}
    busy_until: dict[tuple[str, int], int] = {}  # resource -> when its last step ends
    pan_ready: dict[int, int] = {}  # pan cell -> when its steak is cooked
    closed: set[int] = set()  # cooks that keep an item to the end of the plan
    waiting_pin = {s.pinned for s in segs if s.pinned is not None}
    done: set[int] = set()
    placed: list[tuple[int, int, PlanStep]] = []  # (start, order, step with its cook)

    def simulate(seg: Segment, a: int, t: int | None = None,
                 here: int | None = None) -> tuple[int, list[int], int]:
        t = free_at[a] if t is None else t
        here = pos[a] if here is None else here
        starts = []
        for step, effect, bumps in seg.steps:
            walk, here = walks.to(here, step.target)
            t += walk
            ready = max((busy_until.get(r, 0) for r in _resources(step)), default=0)
            if effect == TAKE and step.target in pan_ready:
                ready = max(ready, pan_ready[step.target])
            t = max(t, ready)
            starts.append(t)
            t += max(1, bumps)
        return t, starts, here

    def cooks_for(seg: Segment) -> list[int]:
        if seg.pinned is not None:
            return [seg.pinned]
        return [a for a in agents if a not in waiting_pin and a not in closed]

    def best_cook(k: int) -> tuple[tuple[int, bool, int], int, list[int], int] | None:
        seg, out = segs[k], None
        for a in cooks_for(seg):
            end, starts, here = simulate(seg, a)
            key = (end, a != seg.steps[0][0].agent, a)
            if out is None or key < out[0]:
                out = (key, end, starts, here)
        return out

    def place(k: int, a: int, starts: list[int], end: int, here: int) -> None:
        seg = segs[k]
        for (step, effect, bumps), start in zip(seg.steps, starts):
            placed.append((start, len(placed), replace(step, agent=a)))
            for r in _resources(step):
                busy_until[r] = start + max(1, bumps)
            if effect == RELEASE and step.target in state.geo.pans and step.items:
                steak = step.items[0]
                pan_ready[step.target] = start + 1 + ticks_until_cooked(
                    state.rules, state.item_progress[steak])
        free_at[a], pos[a] = end, here
        done.add(k)
        waiting_pin.discard(seg.pinned)
        if seg.open_end:
            closed.add(a)

    while len(done) < len(segs):
        ready = [k for k in range(len(segs)) if k not in done and segs[k].deps <= done]
        options = {k: opt for k in ready if (opt := best_cook(k)) is not None}
        if not options:  # nobody may take what is left: keep the plan's own cooks
            return _in_plan_order(steps)
        head = ready[0]
        if head not in options:  # the plan's next segment has no free cook yet
            k = min(options, key=lambda j: (options[j][0], j))
            key, end, starts, here = options[k]
            place(k, key[2], starts, end, here)
            continue
        key, end, starts, here = options[head]
        a = key[2]
        for k2 in ready[1:]:
            if k2 not in options or a not in cooks_for(segs[k2]):
                continue
            end2, starts2, here2 = simulate(segs[k2], a)
            if simulate(segs[head], a, end2, here2)[0] <= end:  # fits in the wait: backfill
                place(k2, a, starts2, end2, here2)
                break
        else:
            place(head, a, starts, end, here)
    placed.sort(key=lambda x: (x[0], x[1]))
    return [replace(step, index=i, start=float(start))
            for i, (start, _, step) in enumerate(placed)]


def _in_plan_order(steps: Sequence[tuple[PlanStep, str, int]]) -> list[PlanStep]:
    return [replace(s, index=i) for i, (s, _, _) in enumerate(steps)]


def _resources(step: PlanStep) -> list[tuple[str, int]]:
    return [("c", step.target), *(("i", i) for i in step.items)]


__all__ = ["KEEP", "RELEASE", "TAKE", "Segment", "schedule", "segments"]

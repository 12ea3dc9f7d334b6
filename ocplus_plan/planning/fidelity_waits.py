"""A time-triggered plan realised in the kitchen with waits: the judge's second try at a
temporal plan whose strict timed replay (:mod:`.fidelity_temporal`) is blocked.

The planning model does not represent cooks as obstacles to each other, so a plan's walk
may run through a cook that stands still (e.g. one waiting at a pan). Here every cook
carries out its own actions in the plan's order, and no activity starts

* before its planned start (simulator step ``floor(start)``, as in the timed replay), nor
* before every activity of any cook that *ends* in the plan no later than it *starts* is
  done (the causal order the plan's timing implies: an effect an action may rely on
  happened at or before its start; actions that overlap in the plan may interleave).

Each plan action is one activity, except a cook envelope (``cook``/``cook_rest``), which
is two: ``?a1`` puts the steak on at its start and ``?a2`` takes it off at its end, no
sooner than the envelope's planned number of pan ticks after the steak went on. A walk
goes along a shortest path around the other cooks, one cell per simulator step; when
every path is blocked by a cook, a blocking cook that has nothing to do yet (or is
waiting for its time, or walks later in the plan) steps aside to the nearest free cell
off the path, and a cook put aside walks back to the cell it must act from. Each
interaction bumps as in the timed replay (``chop``/``wash``: one bump per planned step;
the rest: one bump) and must make the kitchen react (an event of that cook).

The realisation fails, with the plan step (index in ``plan.timed_actions``), when the
kitchen refuses a delivery, a steak the plan does not give up burns, a bump does
nothing, or the cooks stay stuck; at the end every goal order must have been served.
``waits`` counts the cook-steps spent blocked, stepping aside or walking further than
planned.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ..sim import transition
from ..sim.codes import Action
from ..sim.queries import direction, walk_actions, walk_to, walks
from ..sim.state import State
from .compile import Compiled

_STAY = int(Action.STAY)
#: simulator steps with no cook moving and no activity ending (nobody waiting for the
#: clock) after which the cooks are stuck
STUCK_STEPS = 40


@dataclass
class _Act:
    """One thing one cook does: walk, bump (``bumps`` times), or nothing (``noop``)."""

    index: int
    agent: int | None
    start: Fraction
    end: Fraction
    kind: str  # walk, bump, noop
    spot: int | None = None
    place: int | None = None
    bumps: int = 0
    items: tuple[int, ...] = ()
    step_kind: str = ""
    #: take-off of a cook envelope: (the put-on activity, pan ticks it needs)
    after_put: tuple[int, int] | None = None
    deps: list[int] = field(default_factory=list)
    ready: bool = False
    done: bool = False
    bumped_at: int = -1
    reacted: bool = False
    walked: int = 0
    planned_walk: int = 0


@dataclass
class Realisation:
    """The outcome: ``ok``, the failing plan step and why, simulator steps, waits, served."""

    ok: bool
    failed_step: int | None = None
    reason: str = ""
    steps: int = 0
    waits: int = 0
    served: list[int] = field(default_factory=list)
    #: the kitchen where the realisation ended
    final: State | None = None


def _activities(compiled: Compiled, plan: Any, state: State) -> list[_Act]:
    geo = state.geo
    acts: list[_Act] = []

    def flat(rc: tuple[int, int] | None) -> int | None:
        return None if rc is None else geo.flat(*rc)

    for index, (start, ai, duration) in enumerate(plan.timed_actions):
        start = Fraction(start)
        dur = Fraction(duration or 0)
        step = compiled.map_back(ai, float(start), float(dur))
        if step.kind == "cook" and step.other_agent is not None:
            end = start + dur
            acts.append(_Act(index, step.agent, start, start, "bump", flat(step.spot),
                             flat(step.place), 1, step.items, "put on"))
            ticks = math.floor(end) - math.floor(start)
            acts.append(_Act(index, step.other_agent, end, end, "bump", flat(step.other_spot),
                             flat(step.place), 1, step.items, "take off",
                             after_put=(len(acts) - 1, ticks)))
            continue
        if step.kind in ("wait", "abandon") or step.agent is None or step.spot is None:
            acts.append(_Act(index, step.agent, start, start + dur, "noop", items=step.items,
                             step_kind=step.kind))
        elif step.kind == "move":
            acts.append(_Act(index, step.agent, start, start + dur, "walk", flat(step.spot),
                             step_kind="move", planned_walk=int(dur)))
        else:
            bumps = int(dur) if step.kind in ("chop", "wash") else 1
            acts.append(_Act(index, step.agent, start, start + dur, "bump", flat(step.spot),
                             flat(step.place), max(1, bumps), step.items, step.kind))
    for a, act in enumerate(acts):  # the causal order the plan's timing implies
        act.deps = [b for b, other in enumerate(acts) if b != a and _precedes(other, b, act, a)]
    return acts


def _precedes(b: _Act, ib: int, a: _Act, ia: int) -> bool:
    """Whether ``b`` must be done before ``a`` starts: it ends no later than ``a`` starts
    (ties between activities that start and end at one time: the plan's order)."""
    if b.end < a.start:
        return True
    if b.end > a.start:
        return False
    return b.start < a.start or (b.start == a.start and ib < ia)


class _Kitchen:
    """The simulator copy and each cook's queue of activities."""

    def __init__(self, compiled: Compiled, state: State, acts: list[_Act]) -> None:
        self.state, self.acts = state, acts
        self.queues: list[list[int]] = [[] for _ in range(state.n_agents)]
        for i in sorted(range(len(acts)), key=lambda j: (acts[j].start, j)):
            if acts[i].agent is not None:
                self.queues[acts[i].agent].append(i)
        self.loose = [i for i, a in enumerate(acts) if a.agent is None]
        self.k = 0  # simulator steps since the plan's start
        self.events: list[Any] = []
        self.doomed = set(compiled.doomed)
        self.waits = 0
        self.aside: dict[int, int] = {}

    def current(self, agent: int) -> int | None:
        queue = self.queues[agent]
        while queue and self.acts[queue[0]].done:
            queue.pop(0)
        return queue[0] if queue else None

    def startable(self, i: int) -> bool:
        """Due by the clock and by the causal order (``ready`` once true stays true)."""
        act = self.acts[i]
        if not act.ready:
            act.ready = self.k >= math.floor(act.start) and all(
                self.acts[d].done for d in act.deps)
        return act.ready

    def clock_bound(self, i: int) -> bool:
        """Waiting for the clock only (its time, or a steak's ticks on the pan)."""
        act = self.acts[i]
        deps_done = all(self.acts[d].done for d in act.deps)
        if deps_done and self.k < math.floor(act.start):
            return True
        return act.after_put is not None and deps_done and not self._ticks_ok(act)

    def _ticks_ok(self, act: _Act) -> bool:
        if act.after_put is None:
            return True
        put, ticks = act.after_put
        return self.acts[put].bumped_at >= 0 and self.k >= self.acts[put].bumped_at + ticks

    def finish(self, i: int) -> None:
        act = self.acts[i]
        act.done = True
        if act.step_kind == "abandon":
            self.doomed.update(act.items)
        elif act.step_kind.startswith("trash"):
            self.doomed.difference_update(act.items)

    # ------------------------------------------------------------ one simulator step
    def settle(self) -> bool:
        """Finish what takes no simulator step: due no-ops, walks already at their cell."""
        changed, any_done = True, False
        while changed:
            changed = False
            for i in self.loose:
                if not self.acts[i].done and self.startable(i):
                    self.finish(i)
                    changed = True
            for agent in range(self.state.n_agents):
                cur = self.current(agent)
                if cur is None or not self.startable(cur):
                    continue
                act = self.acts[cur]
                if act.kind == "noop" or (act.kind == "walk"
                                          and self.state.agent_pos[agent] == act.spot):
                    self.finish(cur)
                    changed = any_done = True
        return any_done

    def _goal(self, agent: int) -> tuple[int | None, bool, bool]:
        """(the cell ``agent`` walks to or None, whether it bumps now, whether it may be
        asked to step aside). A cook sent aside goes there first, unless it is at its spot
        and due to bump."""
        cur = self.current(agent)
        here = self.state.agent_pos[agent]
        if cur is None or not self.startable(cur):
            return self.aside.get(agent), False, True
        act = self.acts[cur]
        waiting = not self._ticks_ok(act)  # a take-off waiting for the steak: free to go
        if act.kind == "bump" and here == act.spot and not waiting:
            self.aside.pop(agent, None)
            return None, True, False
        target = self.aside.get(agent, act.spot)
        return (None if target == here else target), False, waiting

    def decide(self) -> tuple[list[int], dict[int, int], str, int | None]:
        """The joint action: (actions, agent -> bumping activity, trouble, its activity)."""
        st, geo = self.state, self.state.geo
        walkable = geo.walkables[st.layout_index]
        joint = [_STAY] * st.n_agents
        bumping: dict[int, int] = {}
        goals: dict[int, int] = {}
        yields: set[int] = set()
        for agent in range(st.n_agents):
            goal, bump, may_yield = self._goal(agent)
            cur = self.current(agent)
            if bump and cur is not None:
                act = self.acts[cur]
                bumping[agent] = cur
                joint[agent] = direction(geo, act.spot, act.place)
            elif goal is not None and goal != st.agent_pos[agent]:
                goals[agent] = goal
            if may_yield:
                yields.add(agent)
        reserved: set[int] = set()
        order = sorted(goals, key=lambda a: (a not in self.aside, self._priority(a)))
        for agent in order:
            here = st.agent_pos[agent]
            others = {p for b, p in enumerate(st.agent_pos) if b != agent} | reserved
            path = walk_actions(geo.neighbors, walkable, here, goals[agent], others)
            if path:
                joint[agent] = path[0]
                reserved.add(geo.neighbors[here][path[0]])
                self._count_walk(agent)
                continue
            cells = walk_to(walks(geo.neighbors, walkable, [here]), goals[agent])
            if cells is None:
                cur = self.current(agent)
                return joint, bumping, (f"cook {agent} cannot reach {geo.rc(goals[agent])} "
                                        "at all"), cur
            if agent not in self.aside:
                self.waits += 1
            for other in range(st.n_agents):
                if other != agent and st.agent_pos[other] in set(cells) and (
                        other in yields or self._priority(other) > self._priority(agent)):
                    self._send_aside(other, set(cells) | {here})
        return joint, bumping, "", None

    def _priority(self, agent: int) -> tuple[Fraction, int]:
        cur = self.current(agent)
        if cur is None:
            return (Fraction(10**9), 10**9)
        return (self.acts[cur].start, cur)

    def _count_walk(self, agent: int) -> None:
        cur = self.current(agent)
        if agent in self.aside or cur is None or not self.startable(cur):
            self.waits += 1  # stepping aside, or back after it
            return
        act = self.acts[cur]
        act.walked += 1
        if act.walked > act.planned_walk:
            self.waits += 1

    def _send_aside(self, other: int, keep_off: set[int]) -> None:
        from ..sim.queries import distances

        if other in self.aside and self.aside[other] not in keep_off:
            return
        st, geo = self.state, self.state.geo
        walkable = geo.walkables[st.layout_index]
        busy = {p for b, p in enumerate(st.agent_pos) if b != other}
        near = distances(geo.neighbors, walkable, [st.agent_pos[other]], busy)
        free = [c for c in range(len(near)) if near[c] > 0 and c not in keep_off]
        if free:
            self.aside[other] = min(free, key=lambda c: (near[c], c))

    def after(self, bumping: dict[int, int], events: list[Any]) -> tuple[str, int | None]:
        """Book the step's bumps and arrivals; ('', None) or (trouble, its activity)."""
        st, geo = self.state, self.state.geo
        for e in events:
            if e.kind in ("wrong_delivery", "move_blocked"):
                cur = self.current(e.agent) if e.agent >= 0 else None
                return f"the kitchen reported {e.kind} (cook {e.agent})", cur
            if e.kind == "burnt" and e.item not in self.doomed:
                return f"a steak burnt in the kitchen (item {e.item})", self._touching(e.item)
        for agent, i in bumping.items():
            act = self.acts[i]
            if act.bumped_at < 0:
                act.bumped_at = self.k
            act.bumps -= 1
            act.reacted |= any(e.agent == agent for e in events)
            if act.bumps == 0:
                if not act.reacted:
                    return (f"cook {agent} bumped {geo.rc(act.place)} to {act.step_kind} and "
                            "the kitchen did nothing"), i
                self.finish(i)
        for agent in range(st.n_agents):
            if self.aside.get(agent) == st.agent_pos[agent]:
                del self.aside[agent]
            cur = self.current(agent)
            if cur is not None and self.acts[cur].kind == "walk" and \
                    st.agent_pos[agent] == self.acts[cur].spot and self.startable(cur):
                self.finish(cur)
        return "", None

    def _touching(self, item: int | None) -> int | None:
        """The earliest pending activity (of ``item`` where one is pending)."""
        pending = [i for i, a in enumerate(self.acts) if not a.done]
        touching = [i for i in pending if item in self.acts[i].items]
        return min(touching or pending, key=lambda i: (self.acts[i].start, i), default=None)

    def earliest(self) -> int | None:
        return self._touching(None)


def realise_timed(compiled: Compiled, plan: Any, state: State) -> Realisation:
    """Realise a ``TimeTriggeredPlan`` of ``compiled`` in a copy of ``state`` (see the
    module): the kitchen carries it out to its goal with waits, or the step that fails."""
    acts = _activities(compiled, plan, state)
    kitchen = _Kitchen(compiled, state.copy(), acts)
    st = kitchen.state
    limit = math.floor(max((a.end for a in acts), default=Fraction(0))) + 20 * len(acts) + 200
    stuck = 0

    def fail(reason: str, i: int | None) -> Realisation:
        return Realisation(False, None if i is None else acts[i].index, reason, kitchen.k,
                           kitchen.waits, [e.value for e in kitchen.events
                                           if e.kind == "delivery"], st)

    while True:
        done_now = kitchen.settle()
        if all(a.done for a in acts):
            break
        if kitchen.k > limit:
            return fail(f"the plan did not end within {limit} simulator steps",
                        kitchen.earliest())
        joint, bumping, trouble, at = kitchen.decide()
        if trouble:
            return fail(trouble, at)
        before = list(st.agent_pos)
        events = transition(st, joint).events
        kitchen.events.extend(events)
        trouble, at = kitchen.after(bumping, events)
        if trouble:
            return fail(trouble, at)
        kitchen.k += 1
        clock = any(cur is not None and kitchen.clock_bound(cur)
                    for cur in map(kitchen.current, range(st.n_agents)))
        moved = before != list(st.agent_pos) or bumping or done_now
        stuck = 0 if moved or clock else stuck + 1
        if stuck > STUCK_STEPS:
            return fail(f"the cooks are stuck for {STUCK_STEPS} simulator steps (cooks at "
                        f"{[st.geo.rc(p) for p in st.agent_pos]})", kitchen.earliest())
    out = Realisation(True, steps=kitchen.k, waits=kitchen.waits,
                      served=[e.value for e in kitchen.events if e.kind == "delivery"],
                      final=st)
    missing = sorted(set(compiled.goal_orders) - set(out.served))
    if missing:
        out.ok, out.reason = False, f"the plan ends with orders {missing} not served"
    return out


__all__ = ["STUCK_STEPS", "Realisation", "realise_timed"]

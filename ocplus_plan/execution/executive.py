"""The executive: run a plan in the simulator, watch the world, and replan when it disagrees.

A plan arrives as a list of :class:`PlanStep` (one interaction each: "agent A bumps cell X
to pick up / put down / chop / ... items I"); moves in the plan are not needed, because
every step names the cell to bump and :mod:`.paths` routes the agents there with space-time
reservations (a cell a partner keeps stepping into with our cook: :mod:`.livelock`). Steps
become per-agent task queues; a step waits for the earlier steps of other agents that touch
the same cell or item (a plan's causal links, recovered from the sequential order).

Each call to :meth:`Executive.act` reads the state, settles the bumps of the
previous step (the effect is checked on the state, so it works with or without
:meth:`observe`), looks for surprises, asks for a new plan when the policy says so,
and returns one action per driven agent. Surprises are recorded as triggers with
their reason and time: ``layout_switch``, ``burnt``, ``burn_risk``, ``new_order``,
``action_failed``, ``taken`` (a cook we do not drive took an item of a step, and the plan
could not be repaired: :mod:`.partner`), ``blocked``, ``deadlock``, ``livelock`` (blocked
again and again with no step done: one cook gives way, :mod:`.livelock`), ``stall`` (no
progress toward any order: :mod:`.stall`; the strategies in :mod:`.strategy`), ``rejoin``
(a cook that gave way is back with nothing to do), ``stalled``, ``unreachable``, ``plan_finished``,
``planner_failed`` (the planner timed out or failed: the last valid plan is kept
and agents without work step out of the way; nothing raises).
"""

from __future__ import annotations

import time
from collections import Counter, deque
from collections.abc import Callable, Sequence

from ..errors import ConfigError
from ..sim.codes import Action, Cell, ItemState, Where
from ..sim.queries import (
    direction,
    distances,
    interaction_spots,
    ticks_until_burnt,
    walkable_in_any_layout,
)
from ..sim.state import State
from .paths import (DistanceOracle, PathRequest, hub_cells, layout_connects, layout_schedule,
                    plan_paths)
from .plans import (
    STEP_KINDS,
    PlanFunction,
    PlanOutcome,
    PlanStep,
    Policy,
    causal_dependencies,
)
from .claims import PartnerClaims
from .livelock import Contests, LivelockWatch
from .partner import (PartnerModel, Prediction, await_partner_plates, brings, hand_off,
                      held_by_partner, plan_around, reserved_walks, shut_out, vacate)
from .queue_check import check_queues, known_when_planned
from .stall import STALL_PATIENCE, StallWatch
from .strategy import give_way, rejoining, stall_strategy
from .tasks import BumpRecord, Task, already_done, pan_eta, ready, snapshot

_PAN = int(Cell.PAN)
_HAND, _STAY = int(Where.HAND), int(Action.STAY)
_RAW, _CHOPPED, _CLEAN = int(ItemState.FRESH), int(ItemState.CHOPPED), int(ItemState.CLEAN)


class Executive:
    """Turns plans into joint actions for the driven agents and decides when to replan."""

    def __init__(
        self, planner: PlanFunction, policy: str | Policy = "on_event", *,
        anticipate_switches: bool = False, path_horizon: int = 40,
        retry_after: int = 5, patience: int = 25, block_patience: int = 6,
        deliver_plan: Callable[[int], bool] | None = None,
    ) -> None:
        self.planner = planner
        self.policy = Policy.parse(policy)
        self.anticipate = anticipate_switches
        self.path_horizon = path_horizon
        self.retry_after = retry_after
        self.patience = patience
        self.block_patience = block_patience
        #: message-loss hook: False means the agent does not receive its new task list
        self.deliver_plan = deliver_plan or (lambda agent: True)
        self.agent_ids: tuple[int, ...] = ()
        #: predicts the cooks we do not drive (:mod:`.partner`); None: they stand still
        self.partner_model: PartnerModel | None = None

    # ------------------------------------------------------------------ episode
    def reset(self, state: State, agent_ids: Sequence[int] | None = None) -> None:
        self.agent_ids = tuple(range(state.n_agents)) if agent_ids is None else tuple(agent_ids)
        bad = [a for a in self.agent_ids if not 0 <= a < state.n_agents]
        if bad:
            raise ConfigError(f"agents {bad} do not exist: the kitchen has {state.n_agents}")
        self.oracle = DistanceOracle(state.geo)
        dynamic = state.rules.dynamic and len(state.geo.walkables) > 1
        #: where idle agents wait on a switching map (empty: they just keep out of the way)
        self.hubs = hub_cells(state.geo) if dynamic else frozenset()
        #: cells walkable in some layout (where a walk across switches may go)
        self.any_layout = walkable_in_any_layout(state.geo)
        self.failures_in_row = 0
        self.no_progress = 0
        self.queues: dict[int, deque[Task]] = {a: deque() for a in self.agent_ids}
        self.done_steps: set[int] = set()
        self.planned_orders: set[int] = set()
        #: the orders open when the current plan was made, and the cooks it gave no work
        self.seen_orders: set[int] = set()
        self.idle_in_plan: set[int] = set()
        self.pending: dict[int, BumpRecord] = {}
        self.last_pos: dict[int, int] = {a: state.agent_pos[a] for a in self.agent_ids}
        self.stuck: Counter[int] = Counter()
        self.closest: dict[int, tuple[int, int]] = {}  # cook -> (its step, nearest it got)
        self.boosted: dict[int, int] = {}
        self.prev_layout = state.layout_index
        #: switch times the current plan was made for (anticipate_switches)
        self.expected_switches: frozenset[int] = frozenset()
        #: the current plan was made on the relaxed kitchen (``PlanOutcome.relaxed``)
        self.plan_relaxed = False
        #: the current plan's schedule knew the coming switches (``PlanOutcome.over_switches``)
        self.plan_over_switches = False
        self.prev_burns = state.stats["burns"]
        self.last_plan_t: int | None = None
        self.next_retry = 0
        self.waited_on: tuple | None = None  # the items' places at the last ``waiting`` answer
        self.handed: set[int] = set()  # items our cooks handed off after a livelock
        self.warned: set[tuple[str, int]] = set()
        self.triggers: list[tuple[int, str]] = []
        self.unhandled: list[str] = []  # triggers not yet answered by a replan
        self.replans: list[tuple[int, str]] = []
        self.statuses: Counter[str] = Counter()
        self.failure_messages: Counter[str] = Counter()  # why planner calls failed
        self.planner_calls = 0
        self.planning_time = self.act_time = 0.0
        self.steps_done = 0
        self.failed_bumps = self.messages_lost = self.blocked_moves = 0
        self.plan_id = 0
        self.now = state.t
        self.livelock = LivelockWatch(2 * self.block_patience)
        self.contests = Contests()  # a cell a partner steps into as our cook does
        self.claims = PartnerClaims()  # items a partner keeps taking up (:mod:`.claims`)
        #: cooks giving way after a livelock: left out of the plans until that step
        self.yielding: dict[int, int] = {}
        self.gave_way = 0
        self.stall = StallWatch(state)
        self.stall_steps = 0  # steps of the current stall that were not a wait for a switch
        self.predicted: tuple[int, dict[int, Prediction]] = (-1, {})
        self.repairs = 0
        self.vacated = 0  # boards freed for a partner (:func:`~.partner.vacate`)
        self.stall_strategies: Counter[str] = Counter()

    def observe(self, state: State, events: Sequence[object]) -> None:
        """Optional: count blocked moves of the driven agents (everything else is read
        from the state in :meth:`act`)."""
        for e in events:
            if getattr(e, "kind", "") == "move_blocked" and getattr(e, "agent", -1) in self.queues:
                self.blocked_moves += 1

    # ------------------------------------------------------------------ main loop
    def act(self, state: State) -> list[int]:
        """One action per driven agent, in ``agent_ids`` order."""
        t0 = time.perf_counter()
        self.now = state.t
        reasons = self._monitor(state)
        reason = self._decide(state, reasons)
        if reason is not None:
            self._replan(state, reason)
        actions = self._actions(state)
        self.act_time += time.perf_counter() - t0
        return [actions[a] for a in self.agent_ids]

    def _trigger(self, state: State, reason: str, out: list[str]) -> None:
        self.triggers.append((state.t, reason))
        out.append(reason)
        self.unhandled.append(reason)

    def _monitor(self, state: State) -> list[str]:
        """Settle last step's bumps and compare the world with the plan's expectations."""
        out: list[str] = []
        self.claims.see(state, self.agent_ids)
        # no progress toward any order (:mod:`.stall`), not counting steps the plan waits
        # for a layout switch that is still to come (a wait in the plan is no reason to
        # change strategy; one that is overdue, held up by a cook on a closing cell, is)
        if not self.stall.update(state):
            self.stall_steps = 0
        elif not (self._waiting_for_switch(state) and state.next_switch > state.t):
            self.stall_steps += 1
            if self.stall_steps % STALL_PATIENCE == 0:
                self._trigger(state, "stall", out)
        if rejoining(self, state):  # a cook that gave way is back, with nothing to do
            self._trigger(state, "rejoin", out)
        for a, bump in list(self.pending.items()):
            self._settle(state, a, bump, out)
        self.pending.clear()
        if state.layout_index != self.prev_layout:
            self.prev_layout = state.layout_index
            # an anticipated switch on time is what the plan was made for; a late one
            # (somebody stood on a closing cell) is a surprise; a plan made on the relaxed
            # kitchen expects every switch (it waits where a way is still closed) unless the
            # new layout lets the cooks reach every station: the real kitchen may then be
            # plannable again (two cooks on MapC), and a plan for it is made
            expected = (self.anticipate and state.t in self.expected_switches) or \
                self.plan_over_switches or (self.plan_relaxed and not layout_connects(
                    state.geo, state.layout_index,
                    [state.agent_pos[a] for a in self.agent_ids]))
            if (not expected and self._switch_matters(state)) or self.failures_in_row:
                self._trigger(state, "layout_switch", out)
        if state.stats["burns"] > self.prev_burns:
            self.prev_burns = state.stats["burns"]
            self._trigger(state, "burnt", out)
        open_ids = {o.order_id for o in state.orders}
        idle = {a for a, q in self.queues.items() if not q}
        left_out = open_ids - self.planned_orders
        if self.last_plan_t is not None and left_out and idle and (
                left_out - self.seen_orders or idle - self.idle_in_plan):
            # a new order is planned for as soon as a driven agent has nothing to do
            # (replanning at once would cost a planner call per dish while everybody is busy
            # anyway); one the plan left out, once a cook that had work in it runs out (a
            # cook the plan gave nothing would get nothing from the same call again)
            self.planned_orders |= open_ids
            self._trigger(state, "new_order", out)
        self._check_burn_risk(state, out)
        for a in self.agent_ids:
            pos = state.agent_pos[a]
            task = self._current(a)
            dist = -1 if task is None else \
                self.oracle.to_station(state.layout_index, task.step.target)[pos]
            moving = dist >= 0 and pos not in self._spots(state, task.step.target)
            # no way made: not closer to its target than it has been (stepping to and fro
            # in a one-lane way makes none, as standing still makes none)
            key = -1 if task is None else task.step.index
            closer = self.closest.get(a, (key, dist + 1))
            if closer[0] != key or dist < closer[1]:
                self.closest[a] = (key, dist)
            self.stuck[a] = self.stuck[a] + 1 if moving and pos == self.last_pos[a] or (
                moving and closer[0] == key and dist >= closer[1]) else 0
            self.last_pos[a] = pos
            # right of way until it gets there; not for a cook waiting for another cook's
            # step: it would take the spot the other cook needs first
            if self.stuck[a] >= 3 and a not in self.boosted and task.deps <= self.done_steps:
                self.boosted[a] = state.t
            if self.stuck[a] and self.stuck[a] % self.block_patience == 0:
                self._trigger(state, "blocked", out)
                self.livelock.on_blocked()
            if self.stuck[a] == 2 and getattr(self.partner_model, "by_policy", False) and \
                    shut_out(state, self._spots(state, task.step.target), self._predict(state)):
                self._trigger(state, "livelock", out)  # a partner that stays holds the way in
            if task is not None and task.waited == self.patience:
                self._trigger(state, "stalled", out)
            if task is not None and not task.unreachable and \
                    self._out_of_reach(state, pos, task.step.target):
                task.unreachable = True  # once per task: the planner is told by a replan
                self._trigger(state, "unreachable", out)
        moved, repairs = check_queues(state, self.queues, self.done_steps, self._predict(
            state), self.warned) if state.n_agents > len(self.agent_ids) else (False, 0)
        self.repairs += repairs
        if self.partner_model is not None:  # free a board a partner waits for (:func:`vacate`)
            self.vacated += vacate(state, self.queues, self._predict(state),
                                   self.plan_id * 100_000 + 99_990 - 2 * self.vacated, self.warned) // 2
        if moved:  # a partner took or moved an item the plan needs (:mod:`.partner`)
            self._trigger(state, "taken", out)
        if any(self.queues.values()) and not self._waiting_for_switch(state):
            self.no_progress += 1
            if self.no_progress % (4 * self.block_patience) == 0:
                self._trigger(state, "deadlock", out)  # nobody finished a step for a long time
        if self.last_plan_t is not None and state.orders and not any(self.queues.values()):
            self._trigger(state, "plan_finished", out)
        if not any(self.queues.values()):
            self.livelock.progress(state.t)  # nobody has work: nothing to livelock over
        elif (sum(1 for q in self.queues.values() if q) >= 2
              or state.n_agents > len(self.agent_ids)) and self.livelock.check(state.t):
            self._trigger(state, "livelock", out)
        return out

    def _decide(self, state: State, reasons: list[str]) -> str | None:
        if self.last_plan_t is None:
            return "initial" if state.t >= self.next_retry else None
        if state.t < self.next_retry and not {"layout_switch", "stall"} & set(self.unhandled) \
                and held_by_partner(state, self.handed, self.agent_ids) is None:
            return None
        empty = not any(self.queues.values()) and bool(state.orders)
        kind = self.policy.kind
        if kind == "on_event" and self.unhandled:
            # a deadlock beside a stall first: it is the stations abstraction that failed
            first = [r for r in ("livelock", "deadlock", "stall") if r in self.unhandled]
            return first[0] if first else self.unhandled[0]
        if kind == "periodic" and state.t - self.last_plan_t >= self.policy.period:
            return "periodic"
        if empty:
            return "plan_finished"
        return None

    def _replan(self, state: State, reason: str) -> None:
        if reason == "stall":
            reason = stall_strategy(self, state, self.stall_steps)
        if reason == "livelock" and not give_way(self, state):
            # a lone cook blocked by cooks it does not drive drops its plan, puts what it holds
            # where a partner takes it on (:func:`~.partner.hand_off`), steps aside and waits
            self.replans.append((state.t, reason))
            self.unhandled.clear()
            self.handed = {h for a in self.agent_ids if (h := state.agent_hand[a]) >= 0}
            for a in self.agent_ids:
                self.queues[a].clear()
                self.queues[a].extend(hand_off(state, a, self.plan_id * 100_000 + 99_999,
                                               self._predict(state)))
            self.next_retry = state.t + 2 * self.block_patience
            return
        self.planner_calls += 1
        self.handed = set()  # asked once the partner took it on: not again while plans fail
        t0 = time.perf_counter()
        planned = tuple(a for a in self.agent_ids if self.yielding.get(a, -1) <= state.t)
        try:  # around the partners' predicted next bumps (:func:`~.partner.plan_around`)
            preds = self._predict(state) if self.partner_model else None
            claims = self.claims.claimed(state.t, preds)
            self.claims.plans += bool(claims)
            outcome = plan_around(self.planner, state, planned or self.agent_ids, reason, preds,
                                  claims)
        except Exception as exc:  # noqa: BLE001 - a planner must never crash the episode
            outcome = PlanOutcome("error", [], time.perf_counter() - t0, repr(exc))
        spent = outcome.planning_time or (time.perf_counter() - t0)
        self.planning_time += spent
        self.statuses[outcome.status] += 1
        self.replans.append((state.t, reason))
        self.unhandled.clear()
        if not outcome.ok:
            # keep the last valid plan; try again later, backing off while it keeps failing
            # (a layout switch retries at once: it may be what made the problem unsolvable;
            # ``waiting`` for a partner's hand-over, :func:`~.partner.plan_around`, does not
            # back off after an item moved: the hand-over may have come)
            self.triggers.append((state.t, "planner_failed"))
            self.failure_messages[f"{outcome.status}: {outcome.message}"[:300]] += 1
            self.failures_in_row += 1
            items = (tuple(state.item_where), tuple(state.item_loc))
            soon, self.waited_on = outcome.status == "waiting" and items != self.waited_on, items
            self.next_retry = state.t + (self.retry_after if soon else min(
                4 * self.retry_after, self.retry_after * self.failures_in_row))
            return
        self.failures_in_row = 0
        self.last_plan_t = state.t
        self.plan_id += 1
        self.plan_relaxed = outcome.relaxed
        self.plan_over_switches = outcome.over_switches
        self.planned_orders = {o.order_id for o in state.orders} if outcome.orders is None \
            else set(outcome.orders)
        self.seen_orders = {o.order_id for o in state.orders}
        self.install(outcome.steps, state)
        self.idle_in_plan = {a for a, q in self.queues.items() if not q}
        # a target out of reach already when the plan was made (planned on a relaxed kitchen,
        # waiting for a switch) is not a surprise: only one that becomes unreachable is
        for a in self.agent_ids:
            pos = state.agent_pos[a]
            for task in self.queues[a]:
                if self.oracle.to_station(state.layout_index, task.step.target)[pos] < 0:
                    task.unreachable = True
        if self.anticipate and state.rules.dynamic:
            period = state.rules.map_switch_step
            first = max(state.t + 1, state.next_switch)
            self.expected_switches = frozenset(range(first, state.rules.horizon + 1, period))

    def _predict(self, state: State) -> dict[int, Prediction]:
        """The partner model's predictions for this step (asked once per step)."""
        if self.partner_model is None:
            return {}
        if self.predicted[0] != state.t:
            self.predicted = (state.t, dict(self.partner_model(state)))
        return self.predicted[1]

    def _waits_for_switches(self) -> bool:
        """Does the current plan expect the layout to switch (anticipated switches, a plan
        made on the relaxed kitchen or scheduled over the switches)? Then a cut-off way is
        waited for, not replanned."""
        return self.anticipate or self.plan_relaxed or self.plan_over_switches

    def _waiting_for_switch(self, state: State) -> bool:
        """With a plan that expects switches: is a driven agent's next target out of reach
        until the layout switches? Such a wait is in the plan, not a deadlock."""
        return self._waits_for_switches() and any(
            (task := self._current(a)) is not None and self.oracle.to_station(
                state.layout_index, task.step.target)[state.agent_pos[a]] < 0
            for a in self.agent_ids)

    def _out_of_reach(self, state: State, pos: int, target: int) -> bool:
        """Is ``target`` cut off from ``pos``? With a plan that expects switches, only if no
        walk over the cells of every layout reaches it (the plan may cross in several
        layouts, waiting for each switch)."""
        if not self._waits_for_switches():
            return self.oracle.to_station(state.layout_index, target)[pos] < 0
        geo = state.geo
        reach = distances(geo.neighbors, self.any_layout, [pos])
        return not any(nb >= 0 and reach[nb] >= 0 for nb in geo.neighbors[target])

    def install(self, steps: Sequence[PlanStep], state: State | None = None) -> None:
        """Replace the task queues with a new plan (agents the plan does not reach keep theirs).
        With ``state``, steps at stations worked from one same single cell wait for each
        other in the plan's order (:func:`causal_dependencies`)."""
        base = self.plan_id * 100_000
        steps = [PlanStep(base + i, s.agent, s.kind, s.target, s.items, s.start, s.duration, s.via)
                 for i, s in enumerate(sorted(steps, key=lambda s: (s.start or 0.0, s.index)))]
        spots = {} if state is None else {t: self._spots(state, t) for t in {s.target for s in steps}}
        deps = causal_dependencies(steps, {t: c[0] for t, c in spots.items() if len(c) == 1})
        queues: dict[int, deque[Task]] = {a: deque() for a in self.agent_ids}
        for s in steps:
            if s.agent in queues:
                queues[s.agent].append(Task(s, deps[s.index]))
        # a dependency on a step of an agent we do not drive cannot be waited for
        mine = {s.index for s in steps if s.agent in queues}
        for q in queues.values():
            for task in q:
                task.deps = frozenset(d for d in task.deps if d in mine)
        self.done_steps = set()
        # where each item lies now is what the plan was made knowing: no news to the check
        self.warned = set()
        if state is not None:
            predictions = self._predict(state)
            self.warned = known_when_planned(state, queues, predictions)
            await_partner_plates(state, queues, predictions)
        for a in self.agent_ids:
            if self.deliver_plan(a):
                self.queues[a] = queues[a]
            else:
                self.messages_lost += 1
        self.boosted.clear()

    # ------------------------------------------------------------------ tasks
    def _current(self, agent: int) -> Task | None:
        q = self.queues.get(agent)
        return q[0] if q else None

    def _spots(self, state: State, cell: int) -> list[int]:
        return interaction_spots(state.geo.neighbors, state.geo.walkables[state.layout_index], cell)

    def _finish(self, agent: int) -> None:
        task = self.queues[agent].popleft()
        self.done_steps.add(task.step.index)
        self.steps_done += 1
        self.no_progress = 0
        self.livelock.progress(self.now)
        self.stuck[agent] = 0
        self.boosted.pop(agent, None)

    def _settle(self, state: State, agent: int, bump: BumpRecord, out: list[str]) -> None:
        task = bump.task
        if self._current(agent) is not task:
            return
        now = snapshot(state, task, agent)
        if task.step.kind in ("chop", "wash"):
            if bump.here >= 0 and state.item_state[bump.here] in (_CHOPPED, _CLEAN) \
                    and state.item_state[bump.here] != bump.here_state[0]:
                self._finish(agent)
                return
            progressed = now.here_state != bump.here_state
        else:
            progressed = (now.hand, now.here, now.plate_sizes) != (bump.hand, bump.here, bump.plate_sizes)
            if progressed:
                self._finish(agent)
                return
        if not progressed:
            task.failures += 1
            self.failed_bumps += 1
            if task.failures % 5 == 2:
                self._trigger(state, "action_failed", out)

    def _switch_matters(self, state: State) -> bool:
        """Did the switch cut a driven agent off its next target or change its distance?"""
        old = 1 - state.layout_index
        for a in self.agent_ids:
            task = self._current(a)
            if task is None:
                continue
            d_new = self.oracle.to_station(state.layout_index, task.step.target)[state.agent_pos[a]]
            if d_new < 0:
                return True
            if not self.anticipate:
                d_old = self.oracle.to_station(old, task.step.target)[state.agent_pos[a]]
                if d_old != d_new:
                    return True
        return False

    def _check_burn_risk(self, state: State, out: list[str]) -> None:
        rules = state.rules
        for pan in state.geo.pans:
            steak = state.cell_item[pan]
            if steak < 0 or state.item_state[steak] not in (_RAW, int(ItemState.COOKED)):
                continue
            # steps in which it can still be taken (the last tick burns it)
            left = ticks_until_burnt(rules, state.item_progress[steak]) - 1
            eta = self._eta(state, pan)
            key = (f"burn{self.plan_id}", steak)
            if key in self.warned:
                continue
            if (eta is None and left <= 6) or (eta is not None and eta >= left):
                self.warned.add(key)
                self._trigger(state, "burn_risk", out)

    def _eta(self, state: State, pan: int) -> int | None:
        """Estimated steps until a queued task bumps ``pan`` to take its steak (:func:`pan_eta`)."""
        return pan_eta(state, pan, {a: self.queues[a] for a in self.agent_ids}, self.oracle,
                       self.plan_over_switches)

    # ------------------------------------------------------------------ actions
    def _actions(self, state: State) -> dict[int, int]:
        geo = state.geo
        actions: dict[int, int] = {}
        requests: list[tuple[tuple[int, int, int], PathRequest]] = []
        for a in self.agent_ids:
            pos = state.agent_pos[a]
            while (task := self._current(a)) is not None and already_done(state, task, self.done_steps):
                self._finish(a)
            task = self._current(a)
            if task is None:
                park = self.hubs if pos not in self.hubs else frozenset()
                requests.append(((3, 0, a), PathRequest(a, pos, park)))
                continue
            if task.step.kind == "goto":  # a cell-level move of the plan, in the plan's order
                waiting = not task.deps <= self.done_steps
                goal = frozenset({pos}) if waiting else frozenset({task.step.target})
                requests.append(((2, 0, a) if waiting else (1, 1, a), PathRequest(a, pos, goal)))
                continue
            spots = frozenset(self._spots(state, task.step.target))
            if self.hubs and not self._waits_for_switches() and \
                    self.oracle.to_station(state.layout_index, task.step.target)[pos] < 0:
                # cut off by the layout: wait where the next layout will connect us (a plan
                # that expects switches walks on: its paths know when each switch comes)
                park = self.hubs if pos not in self.hubs else frozenset()
                requests.append(((3, 0, a), PathRequest(a, pos, park)))
                continue
            if pos in spots and (not task.deps <= self.done_steps and self._needed_by_other(
                    state, a, pos) or brings(state, task, self._predict(state), self.queues)):
                # (or a partner carries the step's item to this station: it needs the spot)
                # waiting on its own spot for someone who needs that very spot: step aside
                requests.append(((3, 0, a), PathRequest(a, pos, frozenset())))
                continue
            if pos in spots and ready(state, a, task, self.done_steps):
                actions[a] = direction(geo, pos, task.step.target)
                self.pending[a] = snapshot(state, task, a)
                task.bumps += 1
                task.waited = 0
                continue
            if pos in spots:
                task.waited += 1
            # right of way: agents stuck for a while, then work at a pan (burn deadlines),
            # then agents whose task can start; agents waiting for another agent's step
            # come after those (they must not hold a spot the other one needs), idle ones last
            if a in self.boosted:
                prio = (0, self.boosted[a], a)
            elif not task.deps <= self.done_steps:
                prio = (2, 0, a)
            else:
                urgent = geo.terrains[state.layout_index][task.step.target] == _PAN
                prio = (1, 0 if urgent else 1, a)
            requests.append((prio, PathRequest(a, pos, spots)))
        if requests:
            requests.sort(key=lambda x: x[0])
            # agents we do not drive, and our agents that bump this step, stay where they are
            others = {b: state.agent_pos[b] for b in actions}
            others.update(reserved_walks(state, self._predict(state), self.queues))
            walk_at = layout_schedule(state, self._waits_for_switches())
            paths = plan_paths(geo, [r for _, r in requests], others,
                               horizon=self.path_horizon, walk_at=walk_at)
            for a, res in paths.items():
                actions[a] = res.next_action(geo)
        out = {a: actions.get(a, _STAY) for a in self.agent_ids}  # greedy settles its own
        return out if getattr(self.partner_model, "by_policy", False) else \
            self.contests.settle(state, out)

    def _needed_by_other(self, state: State, agent: int, cell: int) -> bool:
        """Does another driven agent's ready task have ``cell`` as its only way in?"""
        for b in self.agent_ids:
            task = self._current(b)
            if b == agent or task is None or not task.deps <= self.done_steps:
                continue
            if self._spots(state, task.step.target) == [cell]:
                return True
        return False

    # ------------------------------------------------------------------ reporting
    def info(self) -> dict[str, object]:
        self.livelock.close(self.now)
        return {
            "policy": str(self.policy),
            "planner_calls": self.planner_calls,
            "planning_time": round(self.planning_time, 4),
            "executive_time": round(self.act_time, 4),
            "statuses": dict(self.statuses),
            "failure_messages": dict(self.failure_messages.most_common(3)),
            "replans": len(self.replans),
            "replans_by_reason": dict(Counter(r for _, r in self.replans)),
            "triggers_by_reason": dict(Counter(r for _, r in self.triggers)),
            "replan_log": list(self.replans),
            "steps_done": self.steps_done,
            "failed_bumps": self.failed_bumps,
            "blocked_moves": self.blocked_moves,
            "messages_lost": self.messages_lost,
            "gave_way": self.gave_way,
            "partner_repairs": self.repairs, "boards_vacated": self.vacated,
            "claimed_plans": self.claims.plans,
            **self.livelock.info(),
            **self.stall.info(),
            "stall_strategies": dict(self.stall_strategies),
        }


__all__ = ["STEP_KINDS", "Executive", "PlanFunction", "PlanOutcome", "PlanStep", "Policy", "Task",
           "causal_dependencies"]

"""From a planner's plan to executive steps: compile the state, solve it, map the plan back.

:func:`compile_and_solve` makes the :data:`~.plans.PlanFunction` a planner-backed controller
hands to the :class:`~.executive.Executive`: it compiles the state (``planning.compile``),
solves it with a registered planner (``planning.engines``), maps every plan action back to
a simulator interaction (:func:`steps_from_record`, :func:`plan_entries`) and schedules the
work over the driven cooks (:mod:`.schedule`). The planning layer is imported lazily.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from ..errors import ConfigError
from ..sim.state import State
from .paths import cooks_in_one_lane
from .plans import PlanFunction, PlanOutcome, PlanStep
from .proven import PROVEN_STATUSES, ProvenOutcomes, problem_key, reach_key
from .schedule import KEEP, RELEASE, TAKE, schedule
from .spec import DEFAULT_PLANNER, walks_over_switches

#: failed planner answers (timeouts, errors; not proofs) before a fallback is tried: every
#: cook modelled for a one-cook problem, the default planner for another planner
FAILURES_BEFORE_FALLBACK = 2

#: map-back kinds (``planning.names.MappedAction.kind``) -> the executive's step kinds
_KINDS = {
    "pick": "pickup", "rescue": "pickup", "take_off": "pickup",
    "put": "putdown", "chop": "chop", "wash": "wash",
    "plate_put": "plate", "plate_take": "plate", "deliver": "deliver", "trash": "trash",
}
#: kinds with nothing to do in the simulator (moves are routed by the executive itself)
_SKIP = frozenset({"move", "abandon", "wait"})


def _flat(state: State, rc: Any) -> int | None:
    if rc is None:
        return None
    if isinstance(rc, int):
        return rc
    return state.geo.flat(int(rc[0]), int(rc[1]))


def steps_from_record(record: Any, state: State, index: int,
                      follow_moves: bool = False) -> list[PlanStep]:
    """One map-back record (``planning.names.MappedAction``) -> executive steps (none for a move).

    A classical ``cook`` (put the steak on the pan, wait, take it off) becomes two steps
    of its agent; a temporal cook envelope becomes a put by ``agent`` at its start and a
    take-off by ``other_agent`` at its end. Unknown kinds become a generic bump.
    """
    kind = str(getattr(record, "kind", "")).lower()
    agent = getattr(record, "agent", None)
    if kind == "move" and follow_moves and agent is not None:
        # cell granularity: the plan's moves respect occupancy, so they are followed in order
        dest = _flat(state, getattr(record, "spot", None))
        if dest is not None:
            return [PlanStep(index, int(agent), "goto", dest,
                             via=_flat(state, getattr(record, "from_spot", None)))]
    target = _flat(state, getattr(record, "place", None))
    if kind in _SKIP or agent is None or target is None:
        return []
    items = tuple(int(i) for i in (getattr(record, "items", ()) or ()))
    start = getattr(record, "start", None)
    duration = getattr(record, "duration", None)
    start = None if start is None else float(start)
    if kind == "cook":
        other = getattr(record, "other_agent", None)
        end = None if start is None else start + float(duration or 0)
        taker = agent if other is None else int(other)
        return [PlanStep(index, int(agent), "putdown", target, items, start, None),
                PlanStep(index + 1, taker, "pickup", target, items,
                         end if other is not None else start, None)]
    return [PlanStep(index, int(agent), _KINDS.get(kind, "bump"), target, items, start,
                     None if duration is None else float(duration))]


def orders_to_plan(state: State, orders_per_plan: int | str | None) -> int | None:
    """How many open orders (oldest first) one planner call should cover.

    ``"auto"``: all of them while they hold at most 4 ingredients in total (small
    problems that classical planners solve in about a second), else only the oldest;
    the executive asks again when that part of the work is done. An int is a fixed cap,
    None means all."""
    if orders_per_plan == "auto":
        total = sum(len(o.recipe) for o in state.orders)
        return None if total <= 4 else 1
    if orders_per_plan is None:
        return None
    if isinstance(orders_per_plan, int) and orders_per_plan >= 1:
        return orders_per_plan
    raise ConfigError(f"orders_per_plan must be 'auto', None or a positive int, "
                      f"got {orders_per_plan!r}")



#: the compiled problem of a question answered from the record of proven answers
NOT_COMPILED = object()


class _Pipeline:
    """The planner calls behind one :func:`compile_and_solve` plan function."""

    def __init__(self, planner: str, encoding: str, granularity: str, anticipate_switches: bool,
                 timeout: float, validate: bool, orders_per_plan: int | str | None,
                 schedule_cooks: bool, plan_cooks: str, chain_orders: int,
                 over_switches: bool | None) -> None:
        self.planner, self.encoding, self.granularity = planner, encoding, granularity
        self.anticipate, self.timeout, self.validate = anticipate_switches, timeout, validate
        self.orders_per_plan, self.schedule_cooks = orders_per_plan, schedule_cooks
        self.plan_cooks, self.chain_orders = plan_cooks, chain_orders
        self.over_switches = over_switches  # None: on for a chained plan (spec.py)
        #: the CPU seconds of every planner call (``PlannerAgent.info``: ``planning_cpu_s``)
        self.cpu_seconds = [0.0]
        self.proven = ProvenOutcomes()
        self.failed_calls = 0  # planner calls in a row that found no plan (not proofs)
        self.fell_back = False

    def modelled_cooks(self, state: State, agents: tuple[int, ...], gran: str,
                       every_driven: bool = False) -> list[int] | None:
        """The cooks the problem models (None: all of them). Cooks the executive does not
        drive (partners) are left out, unless they hold an item (the compiler needs the
        item's place); ``one-cook`` models the driven cooks that hold an item, or the first
        one, unless ``every_driven``."""
        holders = {a for a in range(state.n_agents) if state.agent_hand[a] >= 0}
        partners_holding = holders - set(agents)
        if self.plan_cooks == "one" and gran == "stations" and not every_driven:
            return sorted(set(sorted(holders & set(agents)) or [agents[0]]) | partners_holding)
        if set(agents) >= set(range(state.n_agents)):
            return None
        return sorted(set(agents) | partners_holding)

    def attempt(self, problem_state: State, agents: tuple[int, ...], max_orders: int | None,
                gran: str, every_driven: bool = False) -> tuple[Any, Any]:
        """Compile and solve one problem: (compiled, PlanResult), or (None, why not).

        A problem that models fewer cooks than are driven and is proven unsolvable is asked
        again at once with every driven cook, and that reach is remembered
        (:mod:`.proven`); a question whose answer was proven is answered from the record
        (the compiled problem is then :data:`NOT_COMPILED`)."""
        modelled = self.modelled_cooks(problem_state, agents, gran, every_driven)
        full = self.modelled_cooks(problem_state, agents, gran, every_driven=True)
        fewer = modelled != full
        if fewer and reach_key(problem_state, modelled or (), max_orders) \
                in self.proven.too_few_cooks:
            modelled, fewer = full, False
        compiled, result = self.solve_once(problem_state, modelled, max_orders, gran)
        status = getattr(result, "status", "error")
        if fewer and status in PROVEN_STATUSES:
            self.proven.too_few_cooks.add(reach_key(problem_state, modelled or (), max_orders))
            self.proven.fallbacks += 1
            compiled, result = self.solve_once(problem_state, full, max_orders, gran)
        elif fewer and status != "solved":
            # failures are not proofs, but one that keeps failing here (timeouts) is given
            # up for every cook, as a proof would be (``failure_fallbacks``)
            key = reach_key(problem_state, modelled or (), max_orders)
            self.proven.failures[key] = self.proven.failures.get(key, 0) + 1
            if self.proven.failures[key] >= FAILURES_BEFORE_FALLBACK:
                self.proven.too_few_cooks.add(key)
                self.proven.failure_fallbacks += 1
                compiled, result = self.solve_once(problem_state, full, max_orders, gran)
        return compiled, result

    def solve_once(self, problem_state: State, modelled: list[int] | None,
                   max_orders: int | None, gran: str) -> tuple[Any, Any]:
        """One question to the planner (or to the record of proven answers)."""
        from ..errors import CompileError
        from ..planning.compile import compile as compile_state  # optional layer: lazy
        from ..planning.engines import solve

        key = problem_key(problem_state, modelled, max_orders, gran,
                          temporal=self.encoding == "temporal")
        known = self.proven.get(key)
        if known is not None:
            return NOT_COMPILED, known
        try:
            compiled = compile_state(problem_state, None, encoding=self.encoding,
                                     granularity=gran, max_orders=max_orders,
                                     anticipate_switches=self.anticipate, agents=modelled)
        except CompileError as exc:
            return None, f"compile: {exc}"
        if self.failed_calls >= FAILURES_BEFORE_FALLBACK and self.encoding == "classical":
            self.fell_back = True  # this planner keeps failing here: the default one from now
        planner = DEFAULT_PLANNER if self.fell_back else self.planner
        self.proven.planner_fallbacks += planner != self.planner
        result = solve(compiled.problem, planner, timeout=self.timeout, validate=self.validate)
        self.cpu_seconds[0] += getattr(result, "cpu_time", None) or 0.0
        self.proven.put(key, result)
        return compiled, result

    def chained(self, compiled: Any, plan: Any, state: State,
                agents: tuple[int, ...]) -> list[tuple[list[Entry], tuple[int, ...]]]:
        """Plans for the next open orders, each from the state the previous plan leaves:
        (its entries, the orders it serves) per plan."""
        from ..planning.fidelity import advance

        out: list[tuple[list[Entry], tuple[int, ...]]] = []
        for _ in range(self.chain_orders - 1):
            after = advance(compiled, plan, state, freeze_layout=state.rules.dynamic)
            if after is None or not after.orders:
                break
            compiled, result = self.attempt(after, agents, 1, self.granularity)
            if compiled is None or result.status != "solved" or result.plan is None:
                break
            plan, state = result.plan, after
            out.append((plan_entries(compiled, plan, state), compiled.goal_orders))
        return out

    def __call__(self, state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
        t0 = time.perf_counter()
        # a deadlock means the stations abstraction (agents jump past each other) failed
        # here: plan this once with cells, whose moves respect occupancy, and follow them;
        # so does every plan for several cooks on one lane (:func:`.paths.cooks_in_one_lane`)
        # and a stall that lasts (``stall_all``: every driven cook modelled, one order at a
        # time), which leaves a cook and a partner waiting for each other to pass
        lane = cooks_in_one_lane(state, agents)
        every = reason == "stall_all"
        gran = "cells" if (reason == "deadlock" or every or lane) and not self.anticipate \
            else self.granularity
        cap = 1 if every else orders_to_plan(state, self.orders_per_plan)
        attempts = [(cap, state)] if cap == 1 or len(state.orders) <= 1 else [(cap, state),
                                                                                 (1, state)]
        outcome = PlanOutcome("error", [], 0.0, "no open order")
        tried_relaxed = False
        while attempts:
            max_orders, problem_state = attempts.pop(0)
            compiled, result = self.attempt(problem_state, agents, max_orders, gran, every)
            if compiled is None:
                outcome = PlanOutcome("error", [], time.perf_counter() - t0, result)
                continue
            if result.status == "unsolvable" and not tried_relaxed and not self.anticipate \
                    and state.rules.dynamic and len(state.geo.walkables) > 1:
                # nothing is reachable enough in this layout alone (MapC never connects every
                # station at once): plan as if every switching cell were open, and let the
                # executive wait for the switch where the way is still closed
                from ..planning.spots import relaxed_state

                tried_relaxed = True
                attempts = [(1, relaxed_state(state))]
            self.failed_calls = 0 if result.status in ("solved", *PROVEN_STATUSES) \
                else self.failed_calls + 1
            if result.status == "solved" and result.plan is not None:
                relaxed = problem_state is not state and tried_relaxed
                return self.solved(compiled, result.plan, state, problem_state, agents,
                                   max_orders, gran, relaxed, t0)
            outcome = PlanOutcome(result.status, [], time.perf_counter() - t0, result.reason)
            if (lane or every) and not attempts and gran != self.granularity \
                    and result.status not in PROVEN_STATUSES:
                gran, attempts = self.granularity, [(1, state)]  # no cells plan in time
        return outcome

    def solved(self, compiled: Any, plan: Any, state: State, problem_state: State,
               agents: tuple[int, ...], max_orders: int | None, gran: str, relaxed: bool,
               t0: float) -> PlanOutcome:
        """The outcome of a solved problem: its plan (chained on) scheduled over the cooks."""
        parts = [plan_entries(compiled, plan, state, gran == "cells")]
        served = [compiled.goal_orders]
        if max_orders == 1 and gran == "stations":
            # (a relaxed plan chains on in the relaxed kitchen)
            for more, goals in self.chained(compiled, plan, problem_state, agents):
                parts.append(more)
                served.append(goals)
        scheduled = self.schedule_cooks and gran == "stations"
        timed = scheduled and walks_over_switches(self.over_switches, self.chain_orders,
                                                  state.rules.dynamic)
        steps = None if scheduled else renumber([s for part in parts for s, _, _ in part])
        while steps is None:
            # chained plans whose work cannot be scheduled together (a plate trip
            # that must interleave with another cook's work) are left for later:
            # the executive plans the next order when a cook runs out of work
            steps = schedule([e for part in parts for e in part], state, agents,
                             switches=timed, fallback=len(parts) == 1)
            parts = parts if steps is not None else parts[:-1]
        # a chain cut short says which orders it still serves (the executive plans
        # the rest when a cook runs out of work); otherwise the plan stands for every
        # open order until it is done (replanning a one-order plan whenever a cook
        # runs out of work cost the default planner a dish on hard, seeds 1 and 9)
        orders = None if len(parts) == len(served) else \
            tuple(o for goals in served[:len(parts)] for o in goals)
        return PlanOutcome("solved", steps, time.perf_counter() - t0, relaxed=relaxed,
                           over_switches=timed, orders=orders)


def compile_and_solve(
    planner: str, encoding: str = "classical", granularity: str = "stations",
    anticipate_switches: bool = False, timeout: float = 10.0, validate: bool = False,
    orders_per_plan: int | str | None = "auto", schedule_cooks: bool = True,
    plan_cooks: str = "all", chain_orders: int = 1, over_switches: bool | None = None,
) -> PlanFunction:
    """A :data:`PlanFunction` that compiles the state and solves it with a named planner.

    When a plan for several orders is not found in time, the oldest order alone is tried
    (decomposition by order). A compile error (a state the model cannot express) is
    reported as status ``error``; nothing raises.

    ``plan_cooks="one"`` (stations): the problem models only the cooks that hold an item,
    or one cook when nobody does; the plan's work is then scheduled over every driven cook
    (``schedule_cooks``). A classical planner minimising total cost gains nothing from a
    second cook, and each modelled cook multiplies any planner's search space.

    ``chain_orders=K`` (stations): after a plan for the oldest order, the
    next open orders are planned one at a time from the state the previous plan leaves
    (:func:`~ocplus_plan.planning.fidelity.advance` runs it in a copy of the simulator; a
    temporal plan is replayed at its planned times; on a switching map the copy keeps the
    current layout, as the plan's model does), up to K orders; the chained plans are
    scheduled together, so a cook can prepare the next dish while another serves this one.
    K small problems are solved much faster than one problem with K orders.

    ``over_switches`` (stations, switching maps): the plan's work is scheduled with walks
    timed over the coming layout switches (:func:`~ocplus_plan.execution.schedule.schedule`
    with ``switches``), and the executive then expects every switch instead of replanning
    on it (cut-off cooks walk on, waiting where the next layout opens their way). None
    (the default): on for a chained plan, off for one order
    (:func:`~ocplus_plan.execution.spec.walks_over_switches`)."""
    if not isinstance(chain_orders, int) or chain_orders < 1:
        raise ConfigError(f"chain_orders must be a positive int, got {chain_orders!r}")
    if plan_cooks not in ("all", "one"):
        raise ConfigError(f"plan_cooks must be 'all' or 'one', got {plan_cooks!r}")
    if not (orders_per_plan in ("auto", None) or
            (isinstance(orders_per_plan, int) and orders_per_plan >= 1)):
        raise ConfigError(f"orders_per_plan must be 'auto', None or a positive int, "
                          f"got {orders_per_plan!r}")

    return _Pipeline(planner, encoding, granularity, anticipate_switches, timeout, validate,
                     orders_per_plan, schedule_cooks, plan_cooks, chain_orders, over_switches)


def hand_effects(record: Any) -> list[tuple[str, int]]:
    """What each executive step of one map-back record does to its cook's hand (the model's
    ``MappedAction.hand``) and how many bumps it takes, aligned with :func:`steps_from_record`."""
    kind = str(getattr(record, "kind", "")).lower()
    if kind == "cook":  # put the steak on, (wait,) take it off: two steps
        return [(RELEASE, 1), (TAKE, 1)]
    bumps = max(1, int(getattr(record, "duration", 1) or 1)) if kind in ("chop", "wash") else 1
    return [(str(getattr(record, "hand", KEEP)), bumps)]


#: an executive step with its hand effect and bumps, as the scheduler takes them
Entry = tuple[PlanStep, str, int]


def plan_entries(compiled: Any, plan: Any, state: State, follow_moves: bool = False) -> list[Entry]:
    """Map a UP sequential or time-triggered plan back to executive steps, each with its hand
    effect and bumps (:func:`hand_effects`), in the order the plan does them."""
    timed = hasattr(plan, "timed_actions")
    if timed:
        actions = [(ai, float(start), None if dur is None else float(dur))
                   for start, ai, dur in plan.timed_actions]
    else:
        actions = [(ai, None, None) for ai in plan.actions]
    entries: list[Entry] = []
    for ai, start, dur in actions:
        record = compiled.map_back(ai, start, dur)
        steps = steps_from_record(record, state, len(entries), follow_moves)
        effects = hand_effects(record)[:len(steps)]
        effects += [(KEEP, 1)] * (len(steps) - len(effects))
        entries += [(s, e, b) for s, (e, b) in zip(steps, effects)]
    if timed:  # a time-triggered plan, read in the order its steps start
        entries.sort(key=lambda x: (x[0].start or 0.0, x[0].index))
    return entries


def renumber(steps: Sequence[PlanStep]) -> list[PlanStep]:
    """The steps with indices 0, 1, ... in their order (chained plans restart at 0)."""
    from dataclasses import replace

    return [replace(s, index=i) for i, s in enumerate(steps)]


__all__ = ["Entry", "compile_and_solve", "hand_effects", "orders_to_plan", "plan_entries",
           "renumber", "steps_from_record"]

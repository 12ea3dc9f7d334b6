"""Fidelity of temporal plans: a time-triggered replay of a plan in the simulator.

UP has no temporal simulator, so the model side here applies a
``TimeTriggeredPlan``'s happenings itself: starting from the problem's initial
values, every plan action's at-start effects at its start time, its at-end
effects at start + duration, and the problem's timed initial literals at their
times (effects are ground by substituting the action's parameters; conditional
effects are evaluated against the current model state; each happening's
conditions and each action's duration bounds are checked too). Happenings at one
time are applied ends first, then timed literals, then starts: PDDL 2.1 requires
simultaneous happenings to be non-interfering (VAL rejects a plan otherwise), so
the order only fixes a deterministic reading.

The simulator side is time-triggered: every agent performs its own actions at
their planned start times and stays while nothing is scheduled for it. The time
conventions (plan time ``tau``; simulator state ``T`` = steps since the compiled
state; durations at the stations granularity are simulator steps):

* an action of duration ``n`` starting at ``tau`` occupies its agent's simulator
  steps ``floor(tau) .. floor(tau) + n - 1`` (a move walks one cell per step along
  a shortest path, a chop or a wash bumps ``n`` times, every other interaction
  bumps once), so its at-end effects are simulator state ``floor(tau + n)``.
  Kairos separates dependent happenings by an epsilon (0.001), so plan times drift
  above the integers; ``floor`` keeps an agent's steps disjoint whatever the drift
  (an action that starts at or after ``tau + n`` gets step ``floor(tau) + n`` or
  later);
* the cook envelope's ends are bumps: its agent ``a1`` puts the steak on the pan
  at step ``floor(S)`` and its agent ``a2`` takes it off at step ``floor(E)``
  (visible in states ``floor(S) + 1`` and ``floor(E) + 1``). The steak has then
  been on the pan ``floor(E) - floor(S)`` ticks (the take-off bump comes before
  the step's tick), which is within ``[lo, hi]`` whenever ``E - S`` is and
  ``lo``, ``hi`` are integers: the model's ``[cook_time, burn_time - 1]`` means
  cooked (``cook_time`` ticks) and not burnt (more than ``burn_time`` ticks);
* a timed initial literal at integer time ``t`` holds from simulator state ``t``:
  a steak with ``k`` ticks on a pan at compile time is cooked from state
  ``cook_time - k`` (``window``) and burnt from state ``burn_time - k + 1``
  (``overdone``); a take-off bump at step ``floor(tau)`` sees ``k + floor(tau)``
  ticks.

The two worlds are compared at the end time ``tau_e`` of every action: the model
state after every happening at or before ``tau_e`` against simulator state
``floor(tau_e)``, through :class:`~.fidelity_view.ModelView` (where every item is and
its state, where every agent stands), skipping only the items and agents that
are parameters of an action in progress at ``tau_e`` (for a cook envelope: the
steak from its start until one step after its end, each bumping agent for the
step of its bump). After the last action everything is compared and the served
orders must agree. The first disagreement ends the replay with a message and a
category: ``initial``, ``model`` (a condition or duration bound the model itself
breaks), ``timing`` (an agent scheduled for two things in one simulator step),
``blocked`` (a walk not possible in its planned steps, or a collision),
``layout_switch``, ``effect``, ``orders``.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, NamedTuple

from ..sim import transition
from ..sim.codes import Action
from ..sim.queries import direction, walk_actions
from ..sim.state import State
from .compile import Compiled
from .fidelity_view import ModelView, Replay, failed

#: happenings at one time: ends, then timed initial literals, then starts
_END, _TIL, _START = 0, 1, 2
#: map-back kinds the simulator has nothing to do for
_NO_STEPS = frozenset({"wait", "abandon"})


class _Mismatch(Exception):
    def __init__(self, message: str, category: str) -> None:
        super().__init__(message)
        self.message, self.category = message, category


# ---------------------------------------------------------------- model side
class GroundEffect(NamedTuple):
    """One effect with its parameters substituted (``condition`` None when unconditional)."""

    fluent: Any
    value: Any
    condition: Any = None
    change: str = "assign"


def _ground(eff: Any, sub: Any) -> GroundEffect:
    if eff.is_forall():
        raise ValueError(f"the temporal replay has no forall effects: {eff}")
    change = "increase" if eff.is_increase() else "decrease" if eff.is_decrease() else "assign"
    if not (change != "assign" or eff.is_assignment()):
        raise ValueError(f"the temporal replay applies assignments, increases and decreases, "
                         f"not {eff}")
    return GroundEffect(sub(eff.fluent), sub(eff.value),
                        sub(eff.condition) if eff.is_conditional() else None, change)


@dataclass
class Happening:
    """The effects (and conditions) of one plan action's start or end, or a timed literal."""

    time: Fraction
    rank: int
    index: int  # plan index, -1 for a timed initial literal
    label: str
    effects: list[Any] = field(default_factory=list)
    conditions: list[Any] = field(default_factory=list)

    @property
    def key(self) -> tuple[Fraction, int, int]:
        return (self.time, self.rank, self.index)


class ModelState:
    """The values of a problem's fluents, changed by applying happenings.

    ``get_value`` answers like a UP state (a constant FNode), so
    :class:`~.fidelity_view.ModelView` reads it as it reads the sequential simulator's.
    """

    def __init__(self, problem: Any) -> None:
        self.problem = problem
        self.em = problem.environment.expression_manager
        self.values: dict[Any, Any] = dict(problem.explicit_initial_values)
        self.defaults = {f: problem.fluents_defaults[f] for f in problem.fluents}

    def get_value(self, fluent_exp: Any) -> Any:
        value = self.values.get(fluent_exp)
        return value if value is not None else self.defaults[fluent_exp.fluent()]

    def evaluate(self, expr: Any) -> Any:
        """A ground expression's value: a bool, an int or a Fraction (or an object)."""
        if expr.is_fluent_exp():
            return self.evaluate(self.get_value(expr))
        if expr.is_bool_constant():
            return expr.bool_constant_value()
        if expr.is_int_constant():
            return expr.int_constant_value()
        if expr.is_real_constant():
            return expr.real_constant_value()
        if expr.is_object_exp():
            return expr.object()
        args = [self.evaluate(a) for a in expr.args]
        if expr.is_not():
            return not args[0]
        if expr.is_and():
            return all(args)
        if expr.is_or():
            return any(args)
        if expr.is_implies():
            return (not args[0]) or args[1]
        if expr.is_equals() or expr.is_iff():
            return args[0] == args[1]
        if expr.is_le():
            return args[0] <= args[1]
        if expr.is_lt():
            return args[0] < args[1]
        if expr.is_plus():
            return sum(args)
        if expr.is_minus():
            return args[0] - args[1]
        raise ValueError(f"the temporal replay cannot evaluate {expr}")

    def apply(self, effects: list[GroundEffect]) -> None:
        """Apply ground effects together: every value is read before any is written."""
        writes = []
        for eff in effects:
            if eff.condition is not None and not self.evaluate(eff.condition):
                continue
            value = self.evaluate(eff.value)
            if eff.change == "increase":
                value = self.evaluate(eff.fluent) + value
            elif eff.change == "decrease":
                value = self.evaluate(eff.fluent) - value
            writes.append((eff.fluent, value))
        for fluent, value in writes:
            if isinstance(value, bool):
                self.values[fluent] = self.em.Bool(value)
            elif isinstance(value, int):
                self.values[fluent] = self.em.Int(value)
            else:
                self.values[fluent] = self.em.Real(Fraction(value))


def happenings(problem: Any, plan: Any) -> list[Happening]:
    """Every start, end and timed literal of a time-triggered plan, in application order."""
    env = problem.environment
    em, subst = env.expression_manager, env.substituter
    out = []

    def ground(eff: Any, subs: dict[Any, Any]) -> GroundEffect:
        return _ground(eff, lambda e: subst.substitute(e, subs))

    for index, (start, ai, duration) in enumerate(plan.timed_actions):
        action = ai.action
        subs = {em.ParameterExp(p): v for p, v in zip(action.parameters, ai.actual_parameters)}
        label = str(ai)
        start = Fraction(start)
        end = start + Fraction(duration or 0)
        at = {_START: Happening(start, _START, index, label),
              _END: Happening(end, _END, index, label)}
        for timing, effects in action.effects.items():
            rank = _END if timing.is_from_end() else _START
            if timing.delay != 0:
                raise ValueError(f"{action.name}: effects at {timing} are not start or end")
            at[rank].effects.extend(ground(e, subs) for e in effects)
        for interval, conds in action.conditions.items():
            ground_conds = [subst.substitute(c, subs) for c in conds]
            lower, upper = interval.lower, interval.upper
            if lower == upper:
                at[_END if lower.is_from_end() else _START].conditions.extend(ground_conds)
            else:  # over all: checked right after the start and right before the end
                at[_START].conditions.extend(("after", c) for c in ground_conds)
                at[_END].conditions.extend(ground_conds)
        out.extend(at.values())
    for timing, effects in problem.timed_effects.items():
        h = Happening(Fraction(timing.delay), _TIL, -1, f"timed literals at {timing.delay}")
        h.effects.extend(_ground(e, lambda x: x) for e in effects)
        out.append(h)
    return sorted(out, key=lambda h: h.key)


def apply_happening(model: ModelState, h: Happening) -> str:
    """Apply one happening; returns the first condition the model breaks, or ''."""
    for cond in h.conditions:
        if not isinstance(cond, tuple) and not model.evaluate(cond):
            return f"{h.label}: condition {cond} is false at {float(h.time):g}"
    model.apply(h.effects)
    for cond in h.conditions:
        if isinstance(cond, tuple) and not model.evaluate(cond[1]):
            return f"{h.label}: condition {cond[1]} is false after its start"
    return ""


def _duration_problem(model: ModelState, ai: Any, duration: Any) -> str:
    """'' when the planned duration lies in the action's bounds (read from the model)."""
    env = model.problem.environment
    subs = {env.expression_manager.ParameterExp(p): v
            for p, v in zip(ai.action.parameters, ai.actual_parameters)}
    bounds = ai.action.duration
    lo = model.evaluate(env.substituter.substitute(bounds.lower, subs))
    hi = model.evaluate(env.substituter.substitute(bounds.upper, subs))
    d = Fraction(duration)
    if d < lo or d > hi or (bounds.is_left_open() and d == lo) or (
            bounds.is_right_open() and d == hi):
        return f"{ai}: duration {float(d):g} outside [{lo}, {hi}]"
    return ""


# ---------------------------------------------------------------- simulator side
@dataclass
class _Activity:
    """What one agent does in the simulator for one plan action (or one envelope end)."""

    agent: int
    first: int
    steps: int
    walk: bool
    label: str
    spot: int
    place: int = -1
    path: list[int] = field(default_factory=list)


class _Schedule:
    """Per agent and simulator step, the activity to perform (and any double booking)."""

    def __init__(self, n_agents: int) -> None:
        self.by_step: list[dict[int, _Activity]] = [{} for _ in range(n_agents)]
        self.clash: dict[int, str] = {}
        self.last = 0

    def add(self, act: _Activity) -> None:
        for k in range(act.first, act.first + act.steps):
            other = self.by_step[act.agent].get(k)
            if other is not None and k not in self.clash:
                self.clash[k] = (f"agent {act.agent} is due to do {other.label} and "
                                 f"{act.label} in the same simulator step {k}")
            self.by_step[act.agent].setdefault(k, act)
        self.last = max(self.last, act.first + act.steps)


class _TimedWorld:
    """The simulator side: advances the copy step by step along the schedule."""

    def __init__(self, state: State, schedule: _Schedule) -> None:
        self.state, self.schedule = state, schedule
        self.k = 0
        self.events: list[Any] = []

    def advance_to(self, target: int) -> None:
        while self.k < target:
            self._step(self.k)
            self.k += 1

    def _step(self, k: int) -> None:
        if k in self.schedule.clash:
            raise _Mismatch(self.schedule.clash[k], "timing")
        st, geo = self.state, self.state.geo
        joint = [int(Action.STAY)] * st.n_agents
        walkable = geo.walkables[st.layout_index]
        for a in range(st.n_agents):
            act = self.schedule.by_step[a].get(k)
            if act is None:
                continue
            here = st.agent_pos[a]
            if act.walk:
                if k == act.first:
                    others = frozenset(p for b, p in enumerate(st.agent_pos) if b != a)
                    path = walk_actions(geo.neighbors, walkable, here, act.spot, others)
                    if path is None or len(path) != act.steps:
                        path = walk_actions(geo.neighbors, walkable, here, act.spot)
                    if path is None or len(path) != act.steps:
                        raise _Mismatch(
                            f"{act.label}: the walk from {geo.rc(here)} to {geo.rc(act.spot)} "
                            f"takes {'no path' if path is None else len(path)} steps, "
                            f"planned {act.steps}", self._category("blocked"))
                    act.path = path
                joint[a] = act.path[k - act.first]
            else:
                if here != act.spot:
                    raise _Mismatch(f"{act.label}: agent {a} is at {geo.rc(here)}, not at "
                                    f"{geo.rc(act.spot)} (step {k})", self._category("effect"))
                joint[a] = direction(geo, act.spot, act.place)
        events = transition(st, joint).events
        self.events.extend(events)
        kinds = {e.kind for e in events}
        if "move_blocked" in kinds:
            raise _Mismatch(f"step {k}: a planned walk was blocked", self._category("blocked"))
        if "wrong_delivery" in kinds:
            raise _Mismatch(f"step {k}: the simulator refused a delivery", self._category("effect"))

    def _category(self, category: str) -> str:
        return "layout_switch" if any(e.kind == "layout_switch" for e in self.events) else category


def _floor(x: Fraction) -> int:
    return math.floor(x)


def _cells(state: State, rc: Any) -> int:
    return state.geo.flat(*rc)


def _plan_activities(compiled: Compiled, timed: list, copy: State, model: ModelState
                     ) -> tuple[_Schedule, list[tuple[Fraction, Fraction, frozenset[str],
                                                       frozenset[str]]], list[Fraction]]:
    """What each agent does at which simulator step for a plan's timed actions: the
    ``_Schedule``, the (from, until, item names, agent names) spans skipped in comparisons
    while in progress, and the times to compare at. Raises :class:`_Mismatch` when the
    model itself breaks a duration bound or an action lasts no whole number of steps."""
    names = compiled.names
    schedule = _Schedule(copy.n_agents)
    #: (from, until, item and agent names) skipped in comparisons while in progress
    busy: list[tuple[Fraction, Fraction, frozenset[str], frozenset[str]]] = []
    checkpoints: list[Fraction] = []
    for start, ai, duration in timed:
        start = Fraction(start)
        duration = Fraction(duration or 0)
        bad = _duration_problem(model, ai, duration)
        if bad:
            raise _Mismatch(bad, "model")
        step = compiled.map_back(ai, start, duration)
        label = f"{ai} at {float(start):g}"
        args = [str(p.object()) for p in ai.actual_parameters]
        item_args = frozenset(x for x in args if x in names.items)
        agent_args = frozenset(x for x in args if x in names.agents)
        end = start + duration
        if step.kind == "cook" and step.other_agent is not None:
            place = _cells(copy, step.place)
            a1, a2 = names.agent(step.agent), names.agent(step.other_agent)
            schedule.add(_Activity(step.agent, _floor(start), 1, False, f"{label} (put on)",
                                   _cells(copy, step.spot), place))
            schedule.add(_Activity(step.other_agent, _floor(end), 1, False,
                                   f"{ai} at {float(end):g} (take off)",
                                   _cells(copy, step.other_spot), place))
            busy.append((start, end + 1, item_args, frozenset()))
            busy.append((start, start + 1, frozenset(), frozenset({a1})))
            busy.append((end, end + 1, frozenset(), frozenset({a2})))
            continue
        busy.append((start, end, item_args, agent_args))
        checkpoints.append(end)
        if step.kind in _NO_STEPS or step.agent is None:
            continue
        if duration.denominator != 1:
            raise _Mismatch(f"{label}: a {step.kind} lasting {float(duration):g} steps", "model")
        n = int(duration)
        if step.kind == "move":
            schedule.add(_Activity(step.agent, _floor(start), n, True, label,
                                   _cells(copy, step.spot)))
        else:
            bumps = n if step.kind in ("chop", "wash") else 1
            if bumps != n:
                raise _Mismatch(f"{label}: a {step.kind} modelled as {n} steps", "model")
            schedule.add(_Activity(step.agent, _floor(start), n, False, label,
                                   _cells(copy, step.spot), _cells(copy, step.place)))
    return schedule, busy, checkpoints


# ---------------------------------------------------------------- the replay
def replay_temporal(compiled: Compiled, plan: Any, state: State,
                    freeze_layout: bool = False, until_horizon: bool = False) -> Replay:
    """Replay a ``TimeTriggeredPlan`` of ``compiled`` in a copy of ``state`` (see the module doc).

    ``until_horizon``: check only what happens before the episode's horizon (a problem
    with anticipated switches models them up to there); a longer plan is then
    ``outlasted`` and its served orders are not compared.
    """
    from ..sim.rules import with_overrides

    copy = state.copy()
    if freeze_layout and copy.rules.dynamic:
        copy.rules = with_overrides(copy.rules, dynamic=False)
    problem = compiled.problem
    names = compiled.names
    view = ModelView(compiled)
    model = ModelState(problem)
    out = Replay(ok=True)

    problem_before = view.diff(model, copy, frozenset())
    if problem_before:
        return Replay(False, 0, 0, f"before the plan: {problem_before}", "initial")

    timed = list(plan.timed_actions)
    try:
        schedule, busy, checkpoints = _plan_activities(compiled, timed, copy, model)
    except _Mismatch as m:
        return failed(out, m.message, m.category)
    out.actions = len(timed)

    world = _TimedWorld(copy, schedule)
    pending = deque(happenings(problem, plan))
    last_time = max([h.time for h in pending if h.index >= 0], default=Fraction(0))
    final = max(last_time, Fraction(schedule.last))
    checkpoints = sorted(set(checkpoints)) + [final]
    limit = copy.rules.horizon - copy.t
    if until_horizon and final > limit:
        out.outlasted = True
        checkpoints = [c for c in checkpoints if c <= limit]
    try:
        for n, when in enumerate(checkpoints):
            while pending and pending[0].time <= when:
                bad = apply_happening(model, pending.popleft())
                if bad:
                    raise _Mismatch(bad, "model")
            world.advance_to(_floor(when))
            skip_items: set[str] = set()
            skip_agents: set[str] = set()
            for lo, hi, items, agents in busy if n < len(checkpoints) - 1 else ():
                if lo <= when < hi:
                    skip_items |= items
                    skip_agents |= agents
            problem_now = view.diff(model, copy, frozenset(), frozenset(skip_items),
                                    frozenset(skip_agents))
            if problem_now:
                raise _Mismatch(f"at {float(when):g} (simulator step {world.k}): {problem_now}",
                                world._category("effect"))
    except _Mismatch as m:
        out.steps = world.k
        return failed(out, m.message, m.category)
    out.steps = world.k
    out.served = [e.value for e in world.events if e.kind == "delivery"]
    if out.outlasted:
        return out
    model_served = sorted(names.orders[o] for o, expr in view.served.items()
                          if model.get_value(expr).bool_constant_value())
    if sorted(out.served) != model_served:
        return failed(out, f"served {sorted(out.served)}, model served {model_served}", "orders")
    out.final = copy
    return out


__all__ = ["GroundEffect", "Happening", "ModelState", "apply_happening", "happenings", "replay_temporal"]

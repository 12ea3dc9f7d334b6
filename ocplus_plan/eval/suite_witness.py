"""Which track an instance of a set enters, and the witness that an unsolved one is solvable.

An instance enters a *scored* track only when it is known to be solvable: a planner of the
reference portfolio solved it (status ``solved``), or, when none did within its CPU limit,
a **goal-agenda witness** exists (status ``open``): the instance's goal orders are served
one at a time, oldest first, each by a plan of :data:`WITNESS_PLANNER` for that one order
from the simulator state the previous plans leave (:func:`~ocplus_plan.planning.fidelity.
advance`), and the concatenation (temporal segments shifted to start after the previous
one ends) is then checked as one plan of the *whole* instance by UP's validator and VAL.
A validated concatenation is a plan, so the instance is solvable; its value is an upper
bound (the best known until a planner does better). An instance that a complete search
proved unsolvable (:data:`PROVERS` reporting ``unsolvable``) goes to the labelled
unsolvability track; one with neither a plan nor a proof is ``unknown`` and dropped from
every track (the manifest lists it).
"""

from __future__ import annotations

from typing import Any

from ..sim.state import State

#: the planner each order of a goal-agenda witness is solved with, per encoding
WITNESS_PLANNER: dict[str, str] = {"classical": "fast-downward", "temporal": "kairos"}
#: planners whose ``unsolvable`` is a proof (a complete search that exhausted the space)
PROVERS = frozenset({"fast-downward", "fast-downward-bjolp", "fast-downward-opt",
                     "fast-downward-wastar", "symk"})
#: the compiler's name for the end of a serving chain
SENTINEL = "o_none"
#: time between two segments of a temporal witness (VAL's tolerance is 0.001)
GAP = 0.01
#: the statuses of an instance's encoding, and whether each enters a scored track
STATUS_SCORED = {"solved": True, "open": True, "unsolvable": False, "unknown": False}


def agenda_witness(state: State, encoding: str, granularity: str, timeout: float,
                   wall_limit: float | None = None, max_orders: int | None = None,
                   ) -> tuple[Any, dict[str, Any]]:
    """(plan of the whole instance or None, what the manifest says about it).

    Each goal order gets ``timeout`` CPU seconds of :data:`WITNESS_PLANNER`; the witness
    fails (None) when one order is not solved, the simulator refuses a segment, or the
    validators reject the concatenation."""
    from ..planning import compile
    from ..planning.engines import solve
    from ..planning.fidelity import advance
    from ..planning.validate import plan_from_steps, plan_to_steps, validate_plan

    planner = WITNESS_PLANNER[encoding]
    whole = compile(state, encoding=encoding, granularity=granularity, max_orders=max_orders)
    temporal = encoding == "temporal"
    info: dict[str, Any] = {"method": "goal agenda: one goal order at a time, oldest first",
                            "planner": planner, "cpu_limit_per_order": timeout}
    chain = _next_same_recipe(state, whole.goal_orders)
    current, steps, offset = state, [], 0.0
    for number, order_id in enumerate(whole.goal_orders):
        order = next((o for o in current.orders if o.order_id == order_id), None)
        if order is None:
            return None, {**info, "failed": f"order {order_id} is no longer open"}
        part = compile(current, orders=[order], encoding=encoding, granularity=granularity)
        result = solve(part.problem, planner, timeout=timeout, wall_limit=wall_limit)
        if not result.solved:
            return None, {**info, "failed": f"order {number + 1}: {planner} {result.status}"}
        after = advance(part, result.plan, current)
        if after is None and not temporal:  # cooks in each other's way: plan in the model
            return pddl_agenda(whole, planner, timeout, wall_limit, info)
        if after is None:
            return None, {**info, "failed": f"order {number + 1}: the simulator refused "
                                            "the segment"}
        segment = plan_to_steps(result.plan)
        for s in segment:  # the segment's chain ends at its order; the whole one goes on
            s["args"] = [chain[order_id] if a == SENTINEL else a for a in s["args"]]
        if temporal:
            for s in segment:
                s["start"] = round(s["start"] + offset, 6)
            offset = max((s["start"] + (s["duration"] or 0.0) for s in segment),
                         default=offset) + GAP
        steps.extend(segment)
        current = after
    plan = plan_from_steps(whole.problem, steps, temporal)
    check = validate_plan(whole.problem, plan)
    if check.ok is not True:
        return None, {**info, "failed": f"the concatenation is not valid: {check.detail[:200]}"}
    return plan, {**info, "validated": check.detail}


def pddl_agenda(whole: Any, planner: str, timeout: float, wall_limit: float | None,
                info: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
    """The classical goal agenda in the model alone: segment ``i`` is planned from the
    model state the first ``i - 1`` segments reach (UP's sequential simulator) for the
    first ``i`` goals; used when the simulator refuses a segment (cooks in each other's
    way), so the witness proves the instance solvable and its replay says if it is
    faithful."""
    from unified_planning.shortcuts import SequentialSimulator

    from ..planning.engines import solve
    from ..planning.validate import plan_from_steps, plan_to_steps, validate_plan

    problem = whole.problem
    goals = list(problem.goals)
    info = {**info, "method": "goal agenda in the model: the first i goal orders from the "
                              "state the previous segments reach, i = 1, 2, ..."}
    steps: list[dict[str, Any]] = []
    with SequentialSimulator(problem, name="sequential_simulator") as sim:
        state = sim.get_initial_state()
        for i in range(len(goals)):
            part = problem.clone()
            part.clear_goals()
            for goal in goals[: i + 1]:
                part.add_goal(goal)
            for fluent in problem.initial_values:
                part.set_initial_value(fluent, state.get_value(fluent))
            result = solve(part, planner, timeout=timeout, wall_limit=wall_limit)
            if not result.solved:
                return None, {**info, "failed": f"goal {i + 1}: {planner} {result.status}"}
            segment = plan_to_steps(result.plan)
            for ai in plan_from_steps(problem, segment, False).actions:
                state = sim.apply(state, ai)
                if state is None:
                    return None, {**info, "failed": f"goal {i + 1}: a step does not apply"}
            steps.extend(segment)
    plan = plan_from_steps(problem, steps, False)
    check = validate_plan(problem, plan)
    if check.ok is not True:
        return None, {**info, "failed": f"the concatenation is not valid: {check.detail[:200]}"}
    return plan, {**info, "validated": check.detail}


def _next_same_recipe(state: State, goal_orders: tuple[int, ...]) -> dict[int, str]:
    """Order id -> the object name of the next open order of the same recipe in the whole
    instance's serving chain (``o_none`` at a chain's end), as the compiler declares it."""
    last = max((i for i, o in enumerate(state.orders) if o.order_id in goal_orders),
               default=-1)
    model = state.orders[: last + 1]
    out: dict[int, str] = {}
    for i, o in enumerate(model):
        later = [n for n in model[i + 1:] if tuple(n.recipe) == tuple(o.recipe)]
        out[o.order_id] = f"o{later[0].order_id}" if later else SENTINEL
    return out


def track_status(reference: dict[str, Any], witness: dict[str, Any] | None) -> str:
    """``solved``, ``open``, ``unsolvable`` or ``unknown`` (see the module docstring)."""
    if reference.get("planner") is not None and reference.get("engine") != "goal-agenda":
        return "solved"
    if witness is not None and "failed" not in witness:
        return "open"
    tried = reference.get("tried", {})
    if any(tried.get(p) == "unsolvable" for p in PROVERS):
        return "unsolvable"
    return "unknown"


__all__ = ["GAP", "PROVERS", "STATUS_SCORED", "WITNESS_PLANNER", "agenda_witness", "pddl_agenda",
           "track_status"]

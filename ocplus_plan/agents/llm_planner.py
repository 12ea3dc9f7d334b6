"""The planner mode of :class:`~.llm.LLMAgent`: a language model writes the whole plan.

When the executive asks for a plan, the state is compiled (:mod:`ocplus_plan.planning.compile`,
stations granularity), and the model gets the kitchen in words plus the PDDL domain and
problem; its reply is read line by line against the problem
(:func:`~ocplus_plan.planning.plan_text.plan_from_text`), validated by UP's validator and
VAL (:func:`~ocplus_plan.planning.validate.validate_plan`), and only then mapped back and
scheduled over the cooks, exactly like a registered planner's plan
(:func:`~.planner.plan_entries`, :func:`~ocplus_plan.execution.schedule.schedule`). A reply
that cannot be read is status ``unreadable``, a plan a validator rejects ``invalid``; the
executive keeps its cooks safe and asks again on its next trigger.
"""

from __future__ import annotations

import time
from typing import Any

from ..errors import CompileError, ConfigError, UnreadableText
from ..execution.plans import PlanFunction, PlanOutcome
from ..execution.schedule import schedule
from ..sim.observe_text import kitchen_text, rules_text
from ..sim.state import State
from .planner import PlannerAgent, plan_entries

PLANNER_TASK = (
    "You are the planner of a cooperative cooking game. Write a plan that serves every "
    "order in the goal.\nRules:\n{rules}\n\nThe kitchen now:\n{kitchen}\n\n"
    "The same state as a PDDL planning problem (the plan must be valid for it).\n"
    "Domain:\n{domain}\n\nProblem:\n{problem}\n\n{feedback}"
    "Reply with the plan only: one action per line, in order, written as {form}. "
    "Nothing else.")
_FORMS = {"classical": "(action-name arg1 arg2 ...)",
          "temporal": "START: (action-name arg1 arg2 ...) [DURATION]"}


def llm_plan_function(transcript: Any, encoding: str = "classical", use_val: bool = True,
                      max_orders: int | None = None) -> PlanFunction:
    """A :data:`PlanFunction` whose planner is the model behind ``transcript``
    (a :class:`~.llm.Transcript`)."""
    if encoding not in _FORMS:
        raise ConfigError(f"encoding must be one of {', '.join(_FORMS)}, got {encoding!r}")

    def plan(state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
        from ..planning.compile import compile as compile_state  # optional layer: lazy
        from ..planning.pddl import problem_texts
        from ..planning.plan_text import plan_from_text
        from ..planning.validate import validate_plan

        t0 = time.perf_counter()
        try:
            compiled = compile_state(state, None, encoding=encoding, granularity="stations",
                                     max_orders=max_orders, agents=agents)
        except CompileError as exc:
            return PlanOutcome("error", [], time.perf_counter() - t0, f"compile: {exc}")
        domain, problem = problem_texts(compiled)
        last = transcript.last_error
        feedback = f"Your last plan was refused: {last}\n\n" if last else ""
        prompt = PLANNER_TASK.format(rules=rules_text(state.rules), kitchen=kitchen_text(state),
                                     domain=domain, problem=problem, feedback=feedback,
                                     form=_FORMS[encoding])
        verdict: dict[str, Any] = {}

        def read(reply: str) -> Any:
            plan_, _ = plan_from_text(reply, compiled.problem, encoding == "temporal",
                                      transcript.max_reply_chars)
            check = validate_plan(compiled.problem, plan_, use_val=use_val)
            verdict["check"] = check
            if check.ok is False:
                raise UnreadableText(f"the plan is not valid for the problem: {check.detail}", 0)
            return plan_

        up_plan = transcript.ask(state.t, prompt, read)
        elapsed = time.perf_counter() - t0
        if up_plan is None:
            status = "invalid" if "check" in verdict else "unreadable"
            return PlanOutcome(status, [], elapsed, transcript.last_error)
        steps = schedule(plan_entries(compiled, up_plan, state), state, agents)
        return PlanOutcome("solved", steps, elapsed)

    plan.__name__ = "llm"
    return plan


def make_llm_planner_agent(transcript: Any, encoding: str = "classical",
                           policy: str = "on_event", use_val: bool = True,
                           max_orders: int | None = None, **executive_options: Any) -> PlannerAgent:
    """The :class:`PlannerAgent` that runs the model's plans."""
    fn = llm_plan_function(transcript, encoding, use_val, max_orders)
    return PlannerAgent(fn, encoding, "stations", policy, **executive_options)


__all__ = ["PLANNER_TASK", "llm_plan_function", "make_llm_planner_agent"]

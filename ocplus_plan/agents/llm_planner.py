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
    "order in the goal.\nRules:\n{rules}\n\nThe kitchen now:\n{kitchen}\n\n{english}"
    "The same state as a PDDL planning problem (the plan must be valid for it{cut}).\n"
    "{domain}Problem:\n{problem}\n\n{feedback}"
    "Reply with the plan only: one action per line, in order, written as {form}. "
    "Nothing else.")
#: what the prompt says of the domain: in words, as PDDL, or both (only the actions that
#: can apply in the kitchen, every time)
DOMAIN_FORMS = ("both", "english", "pddl")
_FORMS = {"classical": "(action-name arg1 arg2 ...)",
          "temporal": "START: (action-name arg1 arg2 ...) [DURATION]"}


def llm_plan_function(transcript: Any, encoding: str = "classical", use_val: bool = True,
                      max_orders: int | None = None, domain: str = "both") -> PlanFunction:
    """A :data:`PlanFunction` whose planner is the model behind ``transcript``
    (a :class:`~.llm.Transcript`); ``domain``: one of :data:`DOMAIN_FORMS`."""
    if encoding not in _FORMS:
        raise ConfigError(f"encoding must be one of {', '.join(_FORMS)}, got {encoding!r}")
    if domain not in DOMAIN_FORMS:
        raise ConfigError(f"domain must be one of {', '.join(DOMAIN_FORMS)}, got {domain!r}")

    def plan(state: State, agents: tuple[int, ...], reason: str = "") -> PlanOutcome:
        from ..planning.compile import compile as compile_state  # optional layer: lazy
        from ..planning.plan_text import plan_from_text
        from ..planning.validate import validate_plan

        t0 = time.perf_counter()
        try:
            compiled = compile_state(state, None, encoding=encoding, granularity="stations",
                                     max_orders=max_orders, agents=agents)
        except CompileError as exc:
            return PlanOutcome("error", [], time.perf_counter() - t0, f"compile: {exc}")
        last = transcript.last_error
        feedback = f"Your last plan was refused: {last}\n\n" if last else ""
        prompt = planner_prompt(state, compiled, feedback, encoding, domain)
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


def planner_prompt(state: State, compiled: Any, feedback: str = "",
                   encoding: str = "classical", domain: str = "both") -> str:
    """What the model reads: the rules and the kitchen in words, the actions it can use in
    words and/or as a PDDL domain (``domain``), cut to the actions that can apply
    (:func:`~ocplus_plan.planning.adapt.unusable_actions`: no washing without a sink, no
    steak actions without a steak), and the PDDL problem."""
    from ..planning.adapt import without_unusable_actions
    from ..planning.language import describe_domain
    from ..planning.pddl import pddl_texts

    cut, _ = without_unusable_actions(compiled.problem)
    domain_pddl, problem = pddl_texts(cut)
    kept = {a.name for a in cut.actions}
    k_max = max([3] + [int(n[len("deliver"):].split("_")[0]) for n in kept
                       if n.startswith("deliver")])
    english = describe_domain(encoding, compiled.granularity, k_max=k_max,
                              switches=compiled.switches, only=kept)
    english = english.split("Actions:\n", 1)[-1]
    return PLANNER_TASK.format(
        rules=rules_text(state.rules), kitchen=kitchen_text(state),
        english="" if domain == "pddl" else f"The actions a plan can use here:\n{english}\n",
        cut="" if domain == "english" else "; its domain holds only the actions that can "
        "apply in this kitchen",
        domain="" if domain == "english" else f"Domain:\n{domain_pddl}\n\n",
        problem=problem, feedback=feedback, form=_FORMS[encoding])


def make_llm_planner_agent(transcript: Any, encoding: str = "classical",
                           policy: str = "on_event", use_val: bool = True,
                           max_orders: int | None = None, domain: str = "both",
                           **executive_options: Any) -> PlannerAgent:
    """The :class:`PlannerAgent` that runs the model's plans (``domain``: how the prompt gives
    the domain, one of :data:`DOMAIN_FORMS`)."""
    fn = llm_plan_function(transcript, encoding, use_val, max_orders, domain)
    return PlannerAgent(fn, encoding, "stations", policy, **executive_options)


__all__ = ["DOMAIN_FORMS", "PLANNER_TASK", "llm_plan_function", "make_llm_planner_agent", "planner_prompt"]

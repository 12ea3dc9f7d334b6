"""The executive: turns plans into joint actions, monitors the simulator and replans.

- :mod:`.plans`: plan steps in simulator terms, planner outcomes, replanning policies.
- :mod:`.paths`: BFS distances and multi-agent space-time path reservations.
- :mod:`.executive`: plan steps -> per-agent task queues, monitoring, replan triggers.
- :mod:`.tasks`: a queued step and its checks (done already, ready to bump, pan ETAs).
- :mod:`.schedule`: a sequential plan scheduled over the cooks (:mod:`.scheduler`, the list
  scheduler; :mod:`.plan_variants`, the plan variants it scores).
- :mod:`.planning_step`: compile the state, solve it, map the plan back to steps.
- :mod:`.spec`: the planner spec ``planner:NAME:GRANULARITY:POLICY:OPTIONS``, parsed once.
- :mod:`.faults`: fault injection (forced burns, extra switches, blockers, message loss).

The planner-backed controller is ``ocplus_plan.agents.planner.PlannerAgent`` (``planner:NAME``
in the agent registry), a thin wrapper over :func:`.planning_step.compile_and_solve` and the
executive.
"""

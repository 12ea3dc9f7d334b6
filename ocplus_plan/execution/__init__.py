"""The executive: turns plans into joint actions, monitors the simulator and replans.

- :mod:`.plans`: plan steps in simulator terms, planner outcomes, replanning policies.
- :mod:`.paths`: BFS distances and multi-agent space-time path reservations.
- :mod:`.executive`: plan steps -> per-agent task queues, monitoring, replan triggers.
- :mod:`.faults`: fault injection (forced burns, extra switches, blockers, message loss).

The planner-backed controller that wires the planning layer to the executive is
``ocplus_plan.agents.planner.PlannerAgent`` (``planner:NAME`` in the agent registry).
"""

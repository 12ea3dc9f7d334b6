"""Planning layer: simulator states -> unified-planning problems -> planners -> plans.

Never imported by ``ocplus_plan.sim`` or ``ocplus_plan.env``; unified_planning is
imported by the submodules that need it (``model``, ``compile``, ``pddl``,
``engines``), not here.
"""

"""Speed mirrors of the simulator's rules.

The reference is :func:`ocplus_plan.sim.step.transition` (and :mod:`ocplus_plan.sim.observe`
for observations). Everything in this folder computes the same thing faster, over arrays of
many kitchens, and is held equal to the reference by the differential tests in
``tests/sim/fast/``: a rule change goes into the reference first, and those tests fail until
the mirror agrees bit for bit. Nothing outside ``fast/`` folders mirrors a rule.
"""

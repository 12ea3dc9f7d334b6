"""Speed mirrors of the RL features and shaping (:mod:`ocplus_plan.rl.features`,
:mod:`ocplus_plan.rl.shaping`) over the batched kitchens of :mod:`ocplus_plan.sim.fast`,
held equal to the reference by the differential tests in ``tests/rl/fast/``.
"""

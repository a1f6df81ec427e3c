"""The lazy SMT planner of Shoukry et al. (CDC 2016), one stage per module.

``loop``       Algorithm 1: horizons, DIS-PLAN and the theory in turn (:func:`plan_lazy`);
``displan``    DIS-PLAN (Section IV): region sequences as SAT over CaDiCaL;
``conplan``    CON-PLAN (Section V): the LP of a region sequence in HiGHS and its
               counterexamples;
``transit``    transit-time conflicts in front of CON-PLAN (beyond the paper);
``guide``      the reference plan DIS-PLAN's decisions follow (beyond the paper);

Nothing is imported here, so ``import plansynth.reach.lazy.displan`` loads only
DIS-PLAN and what it needs.
"""

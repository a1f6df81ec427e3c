"""The lazy SMT planner of Shoukry et al. (CDC 2016), one concept per module.

``loop``       Algorithm 1's loop: DIS-PLAN and the theory in turn over horizon
               windows, behind two narrow interfaces (:func:`~plansynth.reach.lazy.loop.lazy_loop`;
               missions run the same loop);
``planner``    the reach-avoid planner around it: abstraction, bounds, DIS-PLAN and
               CON-PLAN set up, the answer (:func:`~plansynth.reach.lazy.planner.plan_lazy`);
``options``    its options as one frozen value, and the named configurations;
``displan``    DIS-PLAN (Section IV): region sequences as SAT over CaDiCaL, with
               ``regiongraph`` (the graph it encodes), ``satsolver`` (the solver, its
               outcomes, the clause store, the slices a call runs in), ``horizons``
               (one instance for every horizon: activation literals, windows, guards)
               and ``hints`` (decision phases of a reference plan);
``segments``, ``segtheory``  exact segment transitions (points along segments, their LP);
``conplan``    CON-PLAN (Section V): the LP of a region sequence in HiGHS and its
               counterexamples;
``conflict``   what the theory answers the loop (a trajectory, or counterexamples);
``transit``    transit-time conflicts in front of CON-PLAN (beyond the paper);
``guide``      the reference plan DIS-PLAN's decisions follow (beyond the paper);
``minimal``    proving a found horizon minimal, and lowering it (beyond the paper);
``claims``     what ``infeasible`` and "minimal" mean, and relative to what;
``bounds``, ``axisreach``, ``relaxation``  horizon bounds, per-axis reachable sets and
               the MILP relaxation the claims use.

Nothing is imported here, so ``import plansynth.reach.lazy.displan`` loads only
DIS-PLAN and what it needs.
"""

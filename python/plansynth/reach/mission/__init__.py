"""LTL missions for reach-avoid planning.

Shoukry et al. (CDC 2016, Sections I and IV) name LTL missions as the direct extension
of the lazy SMT planner: DIS-PLAN encodes the mission with the linear bounded model
checking encoding of Biere, Heljanko, Junttila, Latvala and Schuppan (LMCS 2006), and
CON-PLAN is unchanged except for the loop of a lasso plan. The lazy loop itself is the
reach-avoid planner's (:func:`plansynth.reach.lazy.loop.lazy_loop`).

``ltl``        the formula language (parser, negation normal form, semantics);
``labels``     the abstraction refined by the label boundaries (each region inside or
               outside each label);
``bmc``        DIS-PLAN for a mission: the linear BMC encoding with loop selectors,
               incremental in the horizon in one CaDiCaL solver;
``plans``      what passes between the halves: a plan with its loop, and the theory's
               answers about the loop (refuted loop, no rest at the end);
``theory``     the mission's theory behind the loop: transit times, the loop alone,
               CON-PLAN, the LP with the loop closure;
``looplp``     that LP (CON-PLAN's rows and x_L = x_k) and its conflicts;
``horizon``    the product graph's lower bound on the horizon;
``proof``      the labels' geometry's proof of infeasibility (LTL tableau);
``planner``    the planner: ``lazy-smt`` on a problem with a mission;
``options``    the mission planners' options as frozen values;
``check``      the independent mission checker (no code shared with the planner);
``milp``       the baseline: the bounded mission as one big-M MILP (Wolff, Topcu and
               Murray, ICRA 2014) in HiGHS, planners ``milp-ltl`` and ``milp-ltl-oneshot``.
"""

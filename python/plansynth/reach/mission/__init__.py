"""LTL missions for reach-avoid planning (issue 14).

Shoukry et al. (CDC 2016, Sections I and IV) name LTL missions as the direct extension
of the lazy SMT planner: DIS-PLAN encodes the mission with the linear bounded model
checking encoding of Biere, Heljanko, Junttila, Latvala and Schuppan (LMCS 2006), and
CON-PLAN is unchanged except for the loop of a lasso plan.

``labels``     the abstraction refined by the label boundaries (each region inside or
               outside each label);
``bmc``        DIS-PLAN for a mission: the linear BMC encoding with loop selectors,
               incremental in the horizon in one CaDiCaL solver;
``planner``    the lazy loop for missions (``lazy-smt`` on a problem with a mission);
``check``      the independent mission checker (no code shared with the planner);
``milp``       the baseline: the bounded mission as one big-M MILP (Wolff, Topcu and
               Murray, ICRA 2014) in HiGHS, planner ``milp-ltl``.
"""

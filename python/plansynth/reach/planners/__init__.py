"""Reach-avoid planners, one module per planner family (STYLE.md, point 5).

``milp``       the region MILP, one per horizon (the cross-check oracle);
``milp_bigm``  the one-shot big-M MILP over the obstacles (LTL OPT stand-in);
``ompl``       OMPL's kinodynamic RRT, EST and KPIECE;
``gcs``        Drake's Graphs of Convex Sets.

The lazy SMT planner itself lives in :mod:`plansynth.reach.lazy`.
"""

"""The team planners as :class:`~plansynth.reach.planners.Planner` values: each its name,
its options value (:mod:`plansynth.reach.team.options`), the solver packages whose
versions it reports and the ``"module:function"`` that plans (loaded on its first solve).

``lazy-smt-team`` is the joint lazy SMT planner (:mod:`plansynth.reach.team.lazy`),
``milp-team`` the joint big-M MILP (:mod:`plansynth.reach.team.milp`), ``prioritized``
prioritized planning (:mod:`plansynth.reach.team.prioritized`). They plan
:class:`~plansynth.reach.team.problem.TeamProblem` values; :func:`plansynth.reach.solve`
sends a team to :func:`~plansynth.reach.team.solve.solve_team`.

>>> LAZY_SMT_TEAM.configure(horizon_search="linear").horizon_search
'linear'
"""

from __future__ import annotations

from plansynth.reach.planners import OptionsPlanner
from plansynth.reach.team.options import PrioritizedOptions, TeamLazyOptions, TeamMilpOptions

__all__ = ["LAZY_SMT_TEAM", "MILP_TEAM", "PRIORITIZED"]

#: ``lazy-smt-team``: the joint lazy SMT planner (CaDiCaL and HiGHS)
LAZY_SMT_TEAM = OptionsPlanner(
    "lazy-smt-team", TeamLazyOptions(), "plansynth.reach.team.seeding:run", ("python-sat", "highspy")
)
#: ``milp-team``: the joint big-M MILP, one per horizon (HiGHS)
MILP_TEAM = OptionsPlanner("milp-team", TeamMilpOptions(), "plansynth.reach.team.milp:run", ("highspy",))
#: ``prioritized``: the robots one after the other, the earlier ones as moving obstacles
PRIORITIZED = OptionsPlanner(
    "prioritized", PrioritizedOptions(), "plansynth.reach.team.prioritized:run", ("python-sat", "highspy")
)

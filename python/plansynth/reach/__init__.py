"""Reach-avoid planning with linear dynamics (Shoukry et al., "Scalable Motion
Planning Using Lazy SMT-Based Solving", CDC 2016).

>>> from plansynth.reach import solve, maze
>>> r = solve(maze(1))
>>> r.status.value, r.horizon, r.validated
('found', 57, True)

* problems: :class:`ReachProblem` (:func:`load_reach_problem`, spec reach-problem.md);
* the abstraction: :func:`abstract` (Section III);
* planners: :func:`solve` with ``planner="lazy-smt"`` (Algorithm 1: DIS-PLAN over SAT,
  CON-PLAN over LP) or ``"milp"`` (one MILP per horizon, the cross-check oracle);
* answers: :class:`ReachResult` with :class:`ReachStatus`, checked by the independent
  :func:`validate`.
"""

from plansynth.reach.abstraction import Abstraction, Region, abstract
from plansynth.reach.families import maze, random_workspace
from plansynth.reach.lazy.loop import TheoryChecker, plan_lazy
from plansynth.reach.planners.milp import plan_milp
from plansynth.reach.problem import Box, LinearDynamics, Polygon, ReachProblem, load_reach_problem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.solve import Planner, planners, register_planner, solve
from plansynth.reach.trajectory import Trajectory, load_trajectory
from plansynth.reach.validate import ValidationReport, validate

__all__ = [
    "Abstraction",
    "Box",
    "LinearDynamics",
    "Planner",
    "Polygon",
    "ReachProblem",
    "ReachResult",
    "ReachStatus",
    "Region",
    "TheoryChecker",
    "Trajectory",
    "ValidationReport",
    "abstract",
    "load_reach_problem",
    "load_trajectory",
    "maze",
    "plan_lazy",
    "plan_milp",
    "planners",
    "random_workspace",
    "register_planner",
    "solve",
    "validate",
]

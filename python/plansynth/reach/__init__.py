"""Reach-avoid planning with linear dynamics (Shoukry et al., "Scalable Motion
Planning Using Lazy SMT-Based Solving", CDC 2016).

>>> from plansynth.reach import load, solve
>>> r = solve(load("examples/reach/maze-1.yaml"))
>>> r.status.value, r.horizon, r.validated
('found', 62, True)

The same kinds of names as :mod:`plansynth.grid`:

* problems: :class:`ReachProblem` (:func:`load`, spec reach-problem.md);
* the abstraction: :func:`abstract` (Section III);
* planners: :func:`solve` with a planner chosen by name (:func:`planners`):
  ``"lazy-smt"`` (Algorithm 1: DIS-PLAN over SAT, CON-PLAN over LP; its options one
  :class:`LazyOptions` value), ``"milp"`` (one MILP per horizon, the cross-check oracle)
  and the baselines; :func:`configure` builds a planner's options value;
* answers: :class:`ReachResult` with :class:`ReachStatus` (``write()`` writes the
  spec's result JSON), every trajectory checked by the independent :func:`validate`.

``plansynth.reach.solve`` is the function here; the module of that name is
:mod:`plansynth.reach.solve` for ``from plansynth.reach.solve import ...``.
"""

from plansynth.reach.abstraction import Abstraction, Region, abstract
from plansynth.reach.families import maze, random_workspace
from plansynth.reach.lazy.loop import TheoryChecker, plan_lazy
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.planners.milp import plan_milp
from plansynth.reach.dynamics import LinearDynamics
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.solve import Planner, configure, get_planner, planners, register_planner, solve
from plansynth.reach.trajectory import Trajectory, load_trajectory
from plansynth.reach.validate import ValidationReport, validate

load = load_reach_problem

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
    "LazyOptions",
    "abstract",
    "configure",
    "get_planner",
    "load",
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

"""The nominal planner followed by a check: the baseline of robust planning.

``nominal-check`` plans the problem as if there were no disturbance (the lazy SMT
planner, :func:`plansynth.reach.lazy.planner.plan_lazy`, with its options) and leaves
the verdict to the robust check that :func:`plansynth.reach.solve` runs on every plan of
a problem with a disturbance (:mod:`plansynth.reach.robust.check`), with the gain K of
the same feedback design. A nominal plan rides the obstacles' edges and the bounds
wherever the time-optimal plan wants to, so it usually fails that check: the answer is
then ``unknown`` with the check's report, never ``found``. It is the "plan, then hope"
that a tightened plan replaces.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robot import configuration_space

__all__ = ["run"]


def run(problem: ReachProblem, budget: Budget, options: LazyOptions, progress: Any = None) -> Any:
    """Plan ``problem`` without its disturbance (a sized robot in its configuration
    space), with the lazy SMT planner."""
    from plansynth.reach.lazy.planner import plan_lazy

    if problem.mission is not None:
        raise InvalidOption("nominal-check", "planner", "plans reach-avoid problems, not missions")
    nominal = configuration_space(replace(problem, disturbance=None))
    result = plan_lazy(nominal, budget, options, progress)
    return replace(result, solver="nominal-check")

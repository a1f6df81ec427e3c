"""The regions a reach planner plans in: the abstraction a result's ``regions`` index,
which the pictures (``reach solve --plot``, ``reach plot``) and the viewer draw."""

from __future__ import annotations

from typing import Any

from plansynth.reach.problem import ReachProblem

__all__ = ["planner_abstraction"]


def planner_abstraction(problem: ReachProblem) -> Any:
    """The regions the planner plans in, the abstraction a result's ``regions`` index:
    the label-refined one for a mission, else that of the configuration space; under a
    disturbance, the tightened problem's (plansynth.reach.robust)."""
    if problem.disturbance is not None:
        from plansynth.reach.robust.picture import robust_abstraction

        robust = robust_abstraction(problem)
        if robust is not None:
            return robust
    if problem.mission is not None:
        from plansynth.reach.mission.labels import label_abstraction

        return label_abstraction(problem).abstraction
    from plansynth.reach.abstraction import abstract
    from plansynth.reach.robot import configuration_space

    return abstract(configuration_space(problem))

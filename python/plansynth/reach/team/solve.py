"""Solving a team: which planner a name means, and the validation of every answer by
the independent team validator (:func:`~plansynth.reach.team.validate.validate_team`).

The team planners are registered with the others (:data:`plansynth.reach.planners.PLANNERS`):
``lazy-smt-team`` (the joint lazy SMT planner, :mod:`plansynth.reach.team.lazy`),
``milp-team`` (the joint big-M MILP, :mod:`plansynth.reach.team.milp`) and
``prioritized`` (:mod:`plansynth.reach.team.prioritized`). :func:`plansynth.reach.solve`
plans a :class:`~plansynth.reach.team.problem.TeamProblem` with them: on a team, the name
``lazy-smt`` (every command's default) means ``lazy-smt-team`` (:func:`team_planner`), a
planner of one robot is an :class:`~plansynth.errors.InvalidOption` naming the team
planners, and a team planner given a reach-avoid problem plans it as a team of one
(:func:`team_of_one`). A plan the validator rejects is never ``found``
(:func:`validate_team_result`): the status becomes ``unknown`` and the message says why.

>>> from plansynth.reach import solve
>>> from plansynth.reach.team.families import smc_crossing
>>> r = solve(smc_crossing())
>>> r.status.value, r.validated, r.solver, r.validation.ok
('found', True, 'lazy-smt-team', True)
"""

from __future__ import annotations

import logging
import time
from dataclasses import replace
from typing import Any

from plansynth.errors import InvalidOption
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus
from plansynth.reach.team.problem import TeamProblem, TeamRobot
from plansynth.reach.team.result import TeamResult
from plansynth.reach.team.validate import validate_team

__all__ = ["TEAM_PLANNERS", "team_planner", "team_of_one", "validate_team_result", "is_team"]

log = logging.getLogger("plansynth.reach")

#: the planners of teams, and what ``lazy-smt`` means on a team
TEAM_PLANNERS = ("lazy-smt-team", "milp-team", "prioritized")
_ALIASES = {"lazy-smt": "lazy-smt-team"}


def is_team(problem: Any) -> bool:
    """Is ``problem`` a team problem?"""
    return isinstance(problem, TeamProblem)


def team_planner(name: str) -> str:
    """The team planner ``name`` means on a team problem (``lazy-smt``: ``lazy-smt-team``);
    a planner of one robot is an :class:`~plansynth.errors.InvalidOption`.

    >>> team_planner("lazy-smt"), team_planner("prioritized")
    ('lazy-smt-team', 'prioritized')
    >>> team_planner("rrt")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidOption: rrt: option 'planner': plans one robot; a team is planned by lazy-smt-team, milp-team, prioritized
    """
    name = _ALIASES.get(name, name)
    if name not in TEAM_PLANNERS:
        raise InvalidOption(name, "planner", f"plans one robot; a team is planned by {', '.join(TEAM_PLANNERS)}")
    return name


def team_of_one(problem: ReachProblem) -> TeamProblem:
    """A reach-avoid problem as a team of one robot (same world, robot, goal, mission)."""
    robot = TeamRobot(
        "robot",
        problem.dynamics,
        problem.start,
        problem.input_bound,
        goal=problem.goal,
        state_bounds=problem.state_bounds,
        robot_shape=problem.robot_shape,
        mission=problem.mission,
    )
    return TeamProblem(
        workspace=problem.workspace,
        obstacles=problem.obstacles,
        robots=(robot,),
        labels=problem.labels,
        max_horizon=problem.max_horizon,
        name=problem.name,
        source=problem.source,
    )


def validate_team_result(problem: TeamProblem, result: TeamResult, *, tol: float = 1e-6) -> TeamResult:
    """The team validator on a ``found`` result; a rejected plan becomes ``unknown``."""
    if result.status is not ReachStatus.FOUND:
        return result
    if result.trajectories is None:
        log.error("planner %s reported found without trajectories", result.solver)
        return replace(result, status=ReachStatus.UNKNOWN, validated=False, message="found without trajectories")
    t0 = time.perf_counter()
    report = validate_team(problem, result.trajectories, tol=tol, require_segment_safe=result.guarantee == "segments")
    seconds = time.perf_counter() - t0
    timings = {**result.timings, "validate": seconds, "total": result.seconds + seconds}
    if report.ok:
        return replace(
            result, validated=True, validation=report, segment_safe=report.segment_safe, timings=timings,
            seconds=timings["total"],
        )  # fmt: skip
    log.error("planner %s returned team trajectories that fail validation: %s", result.solver, report.summary())
    first = "; ".join(str(v) for v in report.violations[:3])
    return replace(
        result,
        status=ReachStatus.UNKNOWN,
        validated=False,
        validation=report,
        segment_safe=report.segment_safe,
        timings=timings,
        seconds=timings["total"],
        message=f"the {result.solver} plan failed validation and is not reported as found: {report.summary()}: {first}",
    )

"""``solve()``: planners chosen by name, every answer validated.

Planners live one per module behind the small :class:`~plansynth.reach.planners.Planner`
protocol (STYLE.md, point 5), in :mod:`plansynth.reach.planners`: ``lazy-smt``
(:mod:`plansynth.reach.lazy`, the paper's Algorithm 1; with an LTL mission, the same
loop over the mission's BMC encoding) and its named configurations, ``milp`` (the
one-shot region MILP) and the baselines ``milp-bigm``, ``rrt``, ``est``, ``kpiece``,
``gcs``; ``milp-ltl`` and ``milp-ltl-oneshot`` for missions. Each planner's options are
one frozen value, built once (:meth:`~plansynth.reach.planners.Planner.configure`, for
the kind of problem: with a mission or without); an option the planner does not take is
an :class:`~plansynth.errors.InvalidOption`. There is no fallback from one planner to
another: an unknown name is an error (:class:`~plansynth.errors.UnknownSolver`, listing
the names) and the result records the planner that ran (``solver``, ``solver_version``,
``options``).

A team of robots (:class:`~plansynth.reach.team.problem.TeamProblem`) goes to
:func:`plansynth.reach.team.solve.solve_team` (``lazy-smt`` means ``lazy-smt-team``
there; the team validator checks its answers).

Every trajectory a planner returns is checked here, and only here, by the independent
validator (:func:`plansynth.reach.validate.validate`, which knows neither the
decomposition nor the planners) before it is reported; segment safety is required when
the planner claims it. A plan for a mission is also checked by the independent mission
checker (:func:`plansynth.reach.mission.check.check_mission`). A trajectory that fails
is never reported as ``found``: the status becomes ``unknown``, the message says why,
and the failure is logged as an error.

>>> from plansynth.reach.families import maze
>>> r = solve(maze(1))
>>> r.status.value, r.validated, r.segment_safe, r.solver, r.solver_version.split()[0]
('found', True, True, 'lazy-smt', 'python-sat')
"""

from __future__ import annotations

import logging
import time
from dataclasses import asdict, is_dataclass, replace
from typing import Any

import numpy as np

from plansynth.budget import Budget
from plansynth.reach.planners import Planner, get_planner, planners, register_planner
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.validate import validate

__all__ = ["Planner", "solve", "register_planner", "planners", "get_planner", "validate_result", "configure"]

log = logging.getLogger("plansynth.reach")

#: the planners of teams (:mod:`plansynth.reach.team.solve`): a reach-avoid problem given
#: to one is planned as a team of one
_TEAM_ONLY = ("lazy-smt-team", "milp-team", "prioritized")


def configure(planner: str, base: Any = None, *, mission: bool | None = None, **values: Any) -> Any:
    """The options value of the planner called ``planner``: ``base`` (default: the
    planner's, for a problem with a mission when ``mission``) with ``values`` set; an
    option it does not take is an :class:`~plansynth.errors.InvalidOption`.

    >>> configure("milp", max_horizon=60)
    MilpOptions(max_horizon=60, start_horizon=None, segment_safe=True)
    >>> configure("lazy-smt", mission=True, semantics="lasso").semantics
    'lasso'
    """
    return get_planner(planner).configure(base, mission=mission, **values)


def validate_result(problem: ReachProblem, result: ReachResult, *, tol: float = 1e-6) -> ReachResult:
    """Run the validator on a ``found`` result and record the verdict, then, for a
    problem with a mission, the mission checker, and for a problem with a disturbance the
    robust check (:mod:`plansynth.reach.robust.check`); a failed trajectory turns the
    status into ``unknown``."""
    if result.status is not ReachStatus.FOUND:
        return result
    if problem.disturbance is not None:
        # the plan as it stands (a mission's: against its tightened labels), then the worst
        # case under every disturbance sequence
        from plansynth.reach.robust.planning import checked, nominal_problem

        return checked(problem, validate_result(nominal_problem(problem), result, tol=tol), tol=tol)
    if problem.mission is not None:
        return _validate_mission(problem, result, tol=tol)
    return _validate_trajectory(problem, result, tol=tol)


def _validate_trajectory(problem: ReachProblem, result: ReachResult, *, tol: float) -> ReachResult:
    """The validator on a ``found`` result's trajectory (a curve: :func:`_validate_curve`)."""
    if result.trajectory is None:
        log.error("planner %s reported found without a trajectory", result.solver)
        return replace(
            result,
            status=ReachStatus.UNKNOWN,
            validated=False,
            message=f"{result.solver} reported found without a trajectory",
        )
    t0 = time.perf_counter()
    if result.guarantee == "curve":
        return _validate_curve(problem, result, tol=tol)
    report = validate(problem, result.trajectory, require_segment_safe=result.guarantee == "segments", tol=tol)
    seconds = time.perf_counter() - t0
    timings = {**result.timings, "validate": seconds}
    total = result.seconds + seconds
    timings["total"] = total
    if report.ok:
        return replace(
            result, validated=True, validation=report, segment_safe=report.segment_safe, timings=timings, seconds=total
        )
    log.error("planner %s returned a trajectory that fails validation: %s", result.solver, report.summary())
    return replace(
        result,
        status=ReachStatus.UNKNOWN,
        validated=False,
        validation=report,
        segment_safe=report.segment_safe,
        timings=timings,
        seconds=total,
        message=f"the {result.solver} trajectory failed validation and is not reported as found: {report.summary()}",
    )


def _validate_mission(problem: ReachProblem, result: ReachResult, *, tol: float) -> ReachResult:
    """The validator on the problem with the workspace as its goal (a mission has no goal
    constraint) and its obstacles grown by the mission's obstacle margin (the robot's
    size checked by the validator itself), then the independent mission checker on the
    trajectory and its loop, in the problem's reading; a failure of either turns the
    result into ``unknown``."""
    from plansynth.reach.mission.check import check_mission
    from plansynth.reach.mission.labels import margin_problem

    checked = _validate_trajectory(margin_problem(problem).reach_view(), result, tol=tol)
    if checked.status is not ReachStatus.FOUND:
        return checked
    t0 = time.perf_counter()
    report = check_mission(problem, checked.trajectory, (checked.mission or {}).get("loop_start"), tol=tol)
    seconds = time.perf_counter() - t0
    timings = {**checked.timings, "mission_check": seconds, "total": checked.seconds + seconds}
    mission = {**(checked.mission or {}), **report.to_json_dict()}
    if report.ok:
        return replace(checked, mission=mission, timings=timings, seconds=timings["total"])
    log.error("planner %s returned a plan that fails the mission checker: %s", checked.solver, report.summary())
    return replace(
        checked,
        status=ReachStatus.UNKNOWN,
        validated=False,
        mission=mission,
        timings=timings,
        seconds=timings["total"],
        message=f"the {checked.solver} plan fails the mission checker and is not reported as found: {report.summary()}",
    )


def _validate_curve(problem: ReachProblem, result: ReachResult, *, tol: float) -> ReachResult:
    """A continuous-time curve (guarantee ``"curve"``, the gcs planner): its samples at dt
    and its dense sampling both pass the validator in ``dynamics="curve"`` mode (the
    dense one segment-safe and with the derivative check), or it is not ``found``."""
    t0 = time.perf_counter()
    report = validate(problem, result.trajectory, tol=tol, dynamics="curve")
    dense = None
    if result.curve is not None:
        dense = validate(
            problem,
            result.curve,
            require_segment_safe=True,
            tol=tol,
            dynamics="curve",
            times=None if result.curve_times is None else np.array(result.curve_times),
        )
    seconds = time.perf_counter() - t0
    timings = {**result.timings, "validate": seconds}
    total = result.seconds + seconds
    timings["total"] = total
    ok = report.ok and dense is not None and dense.ok
    if ok:
        return replace(
            result,
            validated=True,
            validation=report,
            curve_validation=dense,
            segment_safe=report.segment_safe,
            timings=timings,
            seconds=total,
        )
    why = (
        report.summary()
        if not report.ok
        else ("no dense curve to check" if dense is None else f"dense curve: {dense.summary()}")
    )
    log.error("planner %s returned a curve that fails validation: %s", result.solver, why)
    return replace(
        result,
        status=ReachStatus.UNKNOWN,
        validated=False,
        validation=report,
        curve_validation=dense,
        segment_safe=report.segment_safe,
        timings=timings,
        seconds=total,
        message=f"the {result.solver} curve failed validation and is not reported as found: {why}",
    )


def solve(
    problem: ReachProblem,
    planner: str = "lazy-smt",
    budget: Budget = Budget(),
    options: Any = None,
    *,
    progress: Any = None,
    abstraction: Any = None,
    **values: Any,
) -> ReachResult:
    """Plan with the planner called ``planner`` within ``budget``; validate the answer.

    ``options``: the planner's options value (:func:`configure`; default: the
    planner's for the kind of problem), with ``values`` set on it (lazy-smt:
    ``max_horizon``, ``counterexample``, ``segment_safe``, ``generalize``, ...; with a
    mission: ``semantics``, ``loop_first``, ...; milp: ``max_horizon``, ``segment_safe``,
    ``start_horizon``; rrt: ``seed``, ...). ``progress(L, iterations)`` is called by the
    planners that report progress. ``abstraction``: a decomposition computed before, for
    the planners that plan over one (lazy-smt, milp, gcs; not for a mission).
    """
    if getattr(problem, "robots", None) is not None or planner in _TEAM_ONLY:  # a team of robots
        if getattr(problem, "disturbance", None) is not None:  # (raises: the team planners plan no disturbance)
            _robust_problem(problem, planner, get_planner(planner))
        return _solve_team(problem, planner, budget, options, progress, values)
    run = get_planner(planner)
    if problem.disturbance is not None and not getattr(run, "disturbances", ""):
        _robust_problem(problem, planner, run)  # (raises: this planner does not plan under disturbances)
    if not hasattr(run, "configure"):  # a plugin registered as a plain function
        extra = {k: v for k, v in (("progress", progress), ("abstraction", abstraction)) if v is not None}
        return validate_result(problem, replace(run(problem, budget, **values, **extra), solver=planner))
    opts = run.configure(options, mission=problem.mission is not None, **values)
    robot = problem.robot_shape
    planned = problem
    tight = None
    if problem.disturbance is not None:
        # under a disturbance: plan the problem tightened by the tube of the feedback
        # design (plansynth.reach.robust), or the nominal one (the nominal-check baseline)
        t0 = time.perf_counter()
        tight, planned = _robust_problem(problem, planner, run)
        tightening = time.perf_counter() - t0
        if planned is None:
            from plansynth.reach.robust.planning import no_plan

            return replace(no_plan(tight, planner, tightening), solver_version=run.version(), options=_record(opts, {}))
    elif problem.mission is None and robot is not None and not robot.is_point:
        # a sized robot: every planner plans for its reference point in the configuration
        # space (obstacles grown, workspace shrunk: plansynth.reach.robot); the validator
        # checks the answer against the original problem, clearance included
        from plansynth.reach.robot import configuration_space

        planned = configuration_space(problem)
    result = run.solve(planned, budget, opts, progress=progress, abstraction=abstraction)
    result = replace(result, solver=planner, solver_version=run.version(), options=_record(opts, result.options))
    if tight is not None:
        from plansynth.reach.robust.planning import annotated

        result = annotated(result, tight, tightening)
    elif robot is not None and not robot.is_point:  # (a mission plans in the configuration space itself)
        from plansynth.reach.robot import robot_note

        note = robot_note(robot)
        result = replace(
            result,
            message=f"{result.message}; {note}" if result.message else note,
            options={**result.options, "robot": {"radius": robot.radius, "half_extent": robot.half_extent}},
        )
    return validate_result(problem, result)


def _solve_team(problem: Any, planner: str, budget: Budget, options: Any, progress: Any, values: dict) -> Any:
    """A team (:mod:`plansynth.reach.team.solve`): the team planner the name means, its
    answer checked by the team validator; a reach-avoid problem as a team of one."""
    from plansynth.reach.team.solve import is_team, team_of_one, team_planner, validate_team_result

    team = problem if is_team(problem) else team_of_one(problem)
    name = team_planner(planner)
    run = get_planner(name)
    opts = run.configure(options, **values)
    result = run.solve(team, budget, opts, progress=progress)
    result = replace(result, solver=name, solver_version=run.version(), options=_record(opts, result.options))
    if any(r.disturbance is not None for r in team.robots):
        # under disturbances: the tightened team's record, then the plan checked as it
        # stands and in the worst case (plansynth.reach.team.robust_check)
        from plansynth.reach.team.robust_check import annotated_team, checked_team

        return checked_team(team, validate_team_result(team, annotated_team(team, result)))
    return validate_team_result(team, result)


def _robust_problem(problem: ReachProblem, planner: str, run: Any) -> tuple[Any, ReachProblem | None]:
    """The tightening of a problem with a disturbance and the problem ``planner`` plans
    (None: nothing to plan, the tightening says why); a planner that does not plan
    under disturbances is an :class:`~plansynth.errors.InvalidOption`."""
    from plansynth.errors import InvalidOption
    from plansynth.reach.planners import robust_planners
    from plansynth.reach.robust.planning import planned

    how = getattr(run, "disturbances", "")
    if not how:
        raise InvalidOption(
            planner,
            "planner",
            f"does not plan under disturbances (robot.disturbance); planners that do: {', '.join(robust_planners())}",
        )
    tight = planned(problem)
    if how == "nominal":
        return tight, problem
    return tight, tight.problem


def _record(options: Any, recorded: dict[str, Any]) -> dict[str, Any]:
    """The options a result records: every field of the options value, with what the
    planner recorded of its run on top (``max_horizon`` resolved, the budget, ...)."""
    return {**(asdict(options) if is_dataclass(options) else {}), **(recorded or {})}

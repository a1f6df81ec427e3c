"""What :func:`plansynth.reach.solve` does with a problem that has a disturbance: the
problem the planner plans (:func:`planned`), the answer recorded with its feedback and
what it guarantees (:func:`annotated`), and the independent robust check of a found plan
(:func:`checked`).

The result of a robust solve carries ``robust`` (the result file's key of that name):
the feedback law and its gain K, what a found plan guarantees (:data:`~plansynth.reach.robust.tighten.GUARANTEE`),
the margins used (the largest, at the tube's cap), what ``infeasible`` and ``unknown``
are relative to (:data:`~plansynth.reach.robust.tighten.RELATIVE`), and the worst-case
check's report.
"""

from __future__ import annotations

import logging
import time
from dataclasses import replace
from typing import Any

import numpy as np

from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.robust.check import RobustReport, check_robust
from plansynth.reach.robust.tighten import RELATIVE, Tightened, robust_design, tightened

__all__ = ["planned", "annotated", "checked", "no_plan", "nominal_problem", "with_check"]

log = logging.getLogger("plansynth.reach")


def planned(problem: ReachProblem) -> Tightened:
    """The tightened problem of ``problem`` (a mission's labels tightened as well)."""
    design = robust_design(problem)
    if problem.mission is not None:
        from plansynth.reach.robust.missions import tightened_mission

        return tightened_mission(problem, design)
    return tightened(problem, design)


def no_plan(tight: Tightened, planner: str, seconds: float = 0.0) -> ReachResult:
    """The answer when the tightening leaves nothing to plan (``seconds``: the time the
    design and the tightening took)."""
    status = ReachStatus.INFEASIBLE if tight.status == "infeasible" else ReachStatus.UNKNOWN
    return ReachResult(
        status=status,
        solver=planner,
        seconds=seconds,
        timings={"tighten": seconds, "total": seconds},
        message=tight.reason,
        robust=tight.design.record(),
    )


def annotated(result: ReachResult, tight: Tightened, seconds: float = 0.0) -> ReachResult:
    """``result`` with the design recorded and its claims worded relative to it;
    ``seconds`` (the time the design and the tightening took) counted in its time."""
    record = tight.design.record()
    message = result.message
    if tight.note:
        message = f"{message}; {tight.note}" if message else tight.note
    if result.status is not ReachStatus.FOUND:
        message = f"{message}; {RELATIVE}" if message else RELATIVE
    elif result.counters.get("minimal"):
        message += "; the horizon is minimal for the problem tightened by this feedback design's tube"
    total = result.seconds + seconds
    timings = {**result.timings, "tighten": seconds, "total": total}
    return replace(result, robust=record, message=message, seconds=total, timings=timings)


def nominal_problem(problem: ReachProblem) -> ReachProblem:
    """The problem a robust plan satisfies as it stands (checked by the plain validator
    and, for a mission, the mission checker, before the robust check): the problem
    without its disturbance, or for a mission the tightened mission (its plan's labels are ``a__in`` and
    ``a__out``, and it does not cross them, not the labels' own boundaries)."""
    plain = replace(problem, disturbance=None)
    if problem.mission is None:
        return plain
    tight = planned(problem)
    return plain if tight.problem is None else tight.problem


def checked(problem: ReachProblem, result: ReachResult, *, tol: float = 1e-6) -> ReachResult:
    """The worst-case check of a ``found`` result that passed the plain validator; a
    plan that fails it is not reported as found."""
    if result.status is not ReachStatus.FOUND or result.trajectory is None or result.robust is None:
        return result
    t0 = time.perf_counter()
    K = np.asarray(result.robust["feedback"]["gain"], float)
    loop = (result.mission or {}).get("loop_start")
    semantics = (result.mission or {}).get("semantics")
    loop = loop if loop is not None else (result.trajectory.horizon if semantics == "finite" else None)
    report = check_robust(
        problem, result.trajectory, K, tol=tol, loop_start=loop, segments=result.guarantee == "segments"
    )
    if problem.mission is not None:
        from plansynth.reach.robust.mission_check import mission_holds

        holds, why = mission_holds(problem, result.trajectory, K, loop, tol)
        if not holds:
            report = report.with_violation("mission", None, why)
    return with_check(result, report, time.perf_counter() - t0)


def with_check(result: Any, report: RobustReport, seconds: float, check: str = "the robust check") -> Any:
    """``result`` (one robot's or a team's) with the worst-case check's ``report``
    recorded in ``robust.check`` and its ``seconds`` counted; a plan that fails it is
    ``unknown``, not found, and the message says so."""
    timings = {**result.timings, "robust_check": seconds, "total": result.seconds + seconds}
    robust = {**result.robust, "check": report.to_json_dict()}
    if report.ok:
        return replace(result, robust=robust, timings=timings, seconds=timings["total"])
    log.error("planner %s returned a plan that fails %s: %s", result.solver, check, report.summary())
    return replace(
        result,
        status=ReachStatus.UNKNOWN,
        robust=robust,
        timings=timings,
        seconds=timings["total"],
        message=f"the {result.solver} plan fails {check} and is not reported as found: {report.summary()}",
    )

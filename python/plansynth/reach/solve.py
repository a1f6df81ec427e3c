"""``solve()``: reach-avoid planners chosen by name, every answer validated.

Planners live one per module behind the small :class:`Planner` protocol (STYLE.md,
point 5): ``lazy-smt`` (:mod:`plansynth.reach.lazy.loop`, the paper's Algorithm 1) and its
named configurations, ``milp`` (:mod:`plansynth.reach.planners.milp`, the one-shot region MILP)
and the baselines ``milp-bigm``, ``rrt``, ``est``, ``kpiece``. One table names them all;
each module is imported on first use (:func:`get_planner`), so every name works whatever
was imported before. Plugins register with :func:`register_planner`. There is no
fallback from one planner to another: an unknown name is an error
(:class:`~plansynth.errors.UnknownSolver`, listing the names) and the result names the
planner that ran.

Every trajectory a planner returns is checked by the independent validator
(:func:`plansynth.reach.validate.validate`, which knows neither the decomposition nor
the planners) before it is reported; segment safety is required when the planner
claims it. A trajectory that fails is never reported as ``found``: the status becomes
``unknown``, the message says why, and the failure is logged as an error.

>>> from plansynth.reach.families import maze
>>> r = solve(maze(1))
>>> r.status.value, r.validated, r.segment_safe, r.planner
('found', True, True, 'lazy-smt')
"""

from __future__ import annotations

import logging
import time

import numpy as np
from dataclasses import replace
from typing import Any, Protocol

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable, UnknownSolver
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.validate import validate

__all__ = ["Planner", "solve", "register_planner", "planners", "get_planner", "validate_result"]

log = logging.getLogger("plansynth.reach")


class Planner(Protocol):
    """A reach-avoid planner: problem and budget in, unvalidated result out."""

    def __call__(self, problem: ReachProblem, budget: Budget = ..., **options: Any) -> ReachResult:
        ...


def _configured(*, paper: bool = False, **fixed: Any) -> Planner:
    """``plan_lazy`` with some options fixed (named configurations for comparisons);
    ``paper=True`` fixes the paper's options (:data:`plansynth.reach.lazy.loop.PAPER`) first.
    :mod:`plansynth.reach.lazy.loop` is imported on the first call, not here."""

    def planner(problem: ReachProblem, budget: Budget = Budget(), **options: Any) -> ReachResult:
        from plansynth.reach.lazy.loop import PAPER, plan_lazy

        return plan_lazy(problem, budget, **{**options, **(PAPER if paper else {}), **fixed})

    planner.__doc__ = f"plan_lazy with {'PAPER, ' if paper else ''}{fixed}"
    return planner


#: Every planner :func:`solve` knows, in the order :func:`planners` lists them: a name
#: maps to ``"module:attribute"`` (a planner loaded on first use, so that the registry is
#: complete whatever was imported before, and a planner's libraries are imported only
#: when it is asked for) or to a planner itself. A new built-in planner is one line here;
#: plugins use :func:`register_planner`.
_PLANNERS: dict[str, str | Planner] = {
    "lazy-smt": "plansynth.reach.lazy.loop:plan_lazy",
    "milp": "plansynth.reach.planners.milp:plan_milp",
    # the paper's loop and counterexamples (PAPER), with ZEROPREFIX and with the trivial
    # counterexample: the comparison of Section V
    "lazy-smt-paper": _configured(paper=True),
    "lazy-smt-paper-trivial": _configured(paper=True, counterexample="trivial"),
    # our loop with the paper's ZEROPREFIX counterexample (Farkas-shrunk) instead of the default
    "lazy-smt-zeroprefix": _configured(counterexample="zeroprefix"),
    # baselines (see Benchmarks in the README)
    "milp-bigm": "plansynth.reach.planners.milp_bigm:plan_milp_bigm",
    "rrt": "plansynth.reach.planners.ompl:plan_rrt_rrt",
    "est": "plansynth.reach.planners.ompl:plan_rrt_est",
    "kpiece": "plansynth.reach.planners.ompl:plan_rrt_kpiece",
    "gcs": "plansynth.reach.planners.gcs:plan_gcs",  # Drake's Graphs of Convex Sets
    # LTL missions (issue 14): the bounded mission as one big-M MILP per horizon
    "milp-ltl": "plansynth.reach.mission.milp:plan_milp_ltl",
}


def register_planner(name: str, planner: Planner, *, replace_existing: bool = False) -> None:
    """Make ``planner`` available to :func:`solve` as ``name``."""
    if name in _PLANNERS and not replace_existing:
        raise ValueError(f"a planner named {name!r} is already registered")
    _PLANNERS[name] = planner


def planners() -> tuple[str, ...]:
    """The names :func:`solve` accepts (nothing is imported to list them).

    >>> planners()
    ('lazy-smt', 'milp', 'lazy-smt-paper', 'lazy-smt-paper-trivial', 'lazy-smt-zeroprefix', 'milp-bigm', 'rrt', 'est', 'kpiece', 'gcs', 'milp-ltl')
    """
    return tuple(_PLANNERS)


def get_planner(name: str) -> Planner:
    """The planner called ``name``, importing its module on first use.

    An unknown name raises :class:`~plansynth.errors.UnknownSolver` (a ``ValueError``
    and a ``SolverUnavailable``) that lists every known name.

    >>> get_planner("milp").__name__
    'plan_milp'
    >>> get_planner("rrtx")
    Traceback (most recent call last):
    ...
    plansynth.errors.UnknownSolver: solver 'rrtx' is unavailable: unknown planner; choose one of: lazy-smt, milp, lazy-smt-paper, lazy-smt-paper-trivial, lazy-smt-zeroprefix, milp-bigm, rrt, est, kpiece, gcs, milp-ltl
    """
    entry = _PLANNERS.get(name)
    if entry is None:
        raise UnknownSolver("planner", name, planners())
    if isinstance(entry, str):
        import importlib

        module, attribute = entry.split(":")
        try:
            entry = getattr(importlib.import_module(module), attribute)
        except ModuleNotFoundError as exc:  # the planner exists but a library it needs does not
            raise SolverUnavailable(name, f"it needs the Python module {exc.name!r}; install it") from exc
        _PLANNERS[name] = entry
    return entry


def validate_result(problem: ReachProblem, result: ReachResult, *, tol: float = 1e-6) -> ReachResult:
    """Run the validator on a ``found`` result and record the verdict; a failed
    trajectory turns the status into ``unknown``."""
    if result.status is not ReachStatus.FOUND:
        return result
    if result.trajectory is None:
        log.error("planner %s reported found without a trajectory", result.planner)
        return replace(result, status=ReachStatus.UNKNOWN, validated=False,
                       message=f"{result.planner} reported found without a trajectory")
    t0 = time.perf_counter()
    if result.guarantee == "curve":
        return _validate_curve(problem, result, tol=tol)
    report = validate(problem, result.trajectory, require_segment_safe=result.guarantee == "segments", tol=tol)
    seconds = time.perf_counter() - t0
    timings = {**result.timings, "validate": seconds}
    total = result.seconds + seconds
    timings["total"] = total
    if report.ok:
        return replace(result, validated=True, validation=report, segment_safe=report.segment_safe,
                       timings=timings, seconds=total)
    log.error("planner %s returned a trajectory that fails validation: %s", result.planner, report.summary())
    return replace(
        result, status=ReachStatus.UNKNOWN, validated=False, validation=report, segment_safe=report.segment_safe,
        timings=timings, seconds=total,
        message=f"the {result.planner} trajectory failed validation and is not reported as found: {report.summary()}",
    )


def _validate_curve(problem: ReachProblem, result: ReachResult, *, tol: float) -> ReachResult:
    """A continuous-time curve (guarantee ``"curve"``, the gcs planner): its samples at dt
    and its dense sampling both pass the validator in ``dynamics="curve"`` mode (the
    dense one segment-safe and with the derivative check), or it is not ``found``."""
    t0 = time.perf_counter()
    report = validate(problem, result.trajectory, tol=tol, dynamics="curve")
    dense = None
    if result.curve is not None:
        dense = validate(problem, result.curve, require_segment_safe=True, tol=tol, dynamics="curve",
                         times=None if result.curve_times is None else np.array(result.curve_times))
    seconds = time.perf_counter() - t0
    timings = {**result.timings, "validate": seconds}
    total = result.seconds + seconds
    timings["total"] = total
    ok = report.ok and dense is not None and dense.ok
    if ok:
        return replace(result, validated=True, validation=report, curve_validation=dense,
                       segment_safe=report.segment_safe, timings=timings, seconds=total)
    why = report.summary() if not report.ok else ("no dense curve to check" if dense is None else f"dense curve: {dense.summary()}")
    log.error("planner %s returned a curve that fails validation: %s", result.planner, why)
    return replace(result, status=ReachStatus.UNKNOWN, validated=False, validation=report, curve_validation=dense,
                   segment_safe=report.segment_safe, timings=timings, seconds=total,
                   message=f"the {result.planner} curve failed validation and is not reported as found: {why}")


def solve(
    problem: ReachProblem,
    planner: str = "lazy-smt",
    budget: Budget = Budget(),
    **options: Any,
) -> ReachResult:
    """Plan with the planner called ``planner`` within ``budget``; validate the answer.

    ``options`` go to the planner (lazy-smt: ``max_horizon``, ``counterexample``,
    ``segment_safe``, ``generalize``, ``progress``, ...; milp: ``max_horizon``,
    ``segment_safe``, ``start_horizon``, ``progress``).
    """
    run = get_planner(planner)
    if problem.mission is not None:  # LTL missions (issue 14): lazy-smt and milp-ltl plan them
        from plansynth.reach.mission.planner import solve_mission

        return solve_mission(problem, planner, budget, **options)
    robot = problem.robot_shape
    if robot is not None and not robot.is_point:
        # a sized robot: every planner plans for its reference point in the configuration
        # space (obstacles grown, workspace shrunk: plansynth.reach.robot); the validator
        # checks the answer against the original problem, clearance included
        from plansynth.reach.robot import configuration_space, robot_note

        result = run(configuration_space(problem), budget, **options)
        note = robot_note(robot)
        result = replace(result, message=f"{result.message}; {note}" if result.message else note,
                         options={**result.options, "robot": {"radius": robot.radius, "half_extent": robot.half_extent}})
        return validate_result(problem, result)
    result = run(problem, budget, **options)
    return validate_result(problem, result)

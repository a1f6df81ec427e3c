"""``solve()``: reach-avoid planners chosen by name, every answer validated.

Planners live one per module behind the small :class:`Planner` protocol (STYLE.md,
point 5): ``lazy-smt`` (:mod:`plansynth.reach.lazy`, the paper's Algorithm 1) and
``milp`` (:mod:`plansynth.reach.milp`, the one-shot region MILP). Others register with
:func:`register_planner`. There is no fallback from one planner to another: an unknown
name is an error and the result names the planner that ran.

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
from dataclasses import replace
from typing import Any, Protocol

from plansynth.budget import Budget
from plansynth.reach.lazy import PAPER, plan_lazy
from plansynth.reach.milp import plan_milp
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.validate import validate

__all__ = ["Planner", "solve", "register_planner", "planners", "validate_result"]

log = logging.getLogger("plansynth.reach")


class Planner(Protocol):
    """A reach-avoid planner: problem and budget in, unvalidated result out."""

    def __call__(self, problem: ReachProblem, budget: Budget = ..., **options: Any) -> ReachResult:
        ...


def _configured(**fixed: Any) -> Planner:
    """``plan_lazy`` with some options fixed (named configurations for comparisons)."""

    def planner(problem: ReachProblem, budget: Budget = Budget(), **options: Any) -> ReachResult:
        return plan_lazy(problem, budget, **{**options, **fixed})

    planner.__doc__ = f"plan_lazy with {fixed}"
    return planner


def _milp_ltl(problem: ReachProblem, budget: Budget = Budget(), **options: Any) -> ReachResult:
    """The mission MILP baseline (:mod:`plansynth.reach.mission.milp`), for problems with a mission."""
    from plansynth.reach.mission.milp import plan_milp_ltl

    return plan_milp_ltl(problem, budget, **options)


_PLANNERS: dict[str, Planner] = {
    "lazy-smt": plan_lazy,
    "milp": plan_milp,
    # the paper's loop and counterexamples (PAPER), with ZEROPREFIX and with the trivial
    # counterexample: the comparison of Section V
    "lazy-smt-paper": _configured(**PAPER),
    "lazy-smt-paper-trivial": _configured(**{**PAPER, "counterexample": "trivial"}),
    # our loop with the paper's ZEROPREFIX counterexample (Farkas-shrunk) instead of the default
    "lazy-smt-zeroprefix": _configured(counterexample="zeroprefix"),
    # LTL missions (issue 14): the bounded mission as one big-M MILP per horizon
    "milp-ltl": _milp_ltl,
}


def register_planner(name: str, planner: Planner, *, replace_existing: bool = False) -> None:
    """Make ``planner`` available to :func:`solve` as ``name``."""
    if name in _PLANNERS and not replace_existing:
        raise ValueError(f"a planner named {name!r} is already registered")
    _PLANNERS[name] = planner


def planners() -> tuple[str, ...]:
    """The names :func:`solve` accepts.

    >>> planners()[:5]
    ('lazy-smt', 'milp', 'lazy-smt-paper', 'lazy-smt-paper-trivial', 'lazy-smt-zeroprefix')
    """
    return tuple(_PLANNERS)


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
    if planner not in _PLANNERS:
        raise ValueError(f"unknown planner {planner!r} (known: {', '.join(_PLANNERS)})")
    if problem.mission is not None:  # LTL missions (issue 14): lazy-smt and milp-ltl plan them
        from plansynth.reach.mission.planner import solve_mission

        return solve_mission(problem, planner, budget, **options)
    result = _PLANNERS[planner](problem, budget, **options)
    return validate_result(problem, result)

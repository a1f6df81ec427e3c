"""Fast path planning (FPP) as a baseline reach-avoid planner (``fpp``).

Marcucci, Nobel, Tedrake and Boyd, "Fast path planning through large collections of
safe boxes", IEEE Transactions on Robotics 2024, through its authors' library
(``fastpathplanning`` on PyPI, :func:`fastpathplanning.plan`): the fastest published
planner through large collections of boxes. Its three phases (Sections III-V of the
paper): *offline*, the boxes' intersection graph, its line graph and a representative
point in every intersection (one SOCP; ``fastpathplanning.SafeSet``); *online*, the
shortest polygonal path through the boxes, refined by box insertions (a few SOCPs), then
a smooth piecewise Bezier curve along that box sequence with fixed total duration T,
whose transition times are improved by retiming (alternating QPs and SOCPs, cvxpy and
Clarabel).

**Set up as its examples set it up** (``examples/maze.ipynb`` of the library): cost
weights ``alpha = [0, 0, 1]`` (the jerk's squared L2 norm), the start and a terminal
point (the goal's centre), and the start at rest (``der_init = {1: 0}``, our problem's
start; a robot that does not start at rest is not planned). The boxes are the ones
``gcs`` is given, the maximal free boxes grown from the obstacle grid
(:func:`~plansynth.reach.planners.convex_sets.maximal_free_boxes`): every obstacle must
be a box.

**Duration.** FPP has no dynamics: it plans a smooth curve of a duration T fixed in
advance, with no velocity or acceleration bound. With one cost term (``alpha`` nonzero
at a single order j), the optimal curve for duration sT is the one for T traversed s
times slower (the cost scales by s^(1-2j), the box and boundary constraints not at all),
so the duration is chosen after planning, not by re-planning: the shortest uniform
re-timing at which the curve's control points, and by the convex-hull property the whole
curve, keep |v| and |a| within the problem's bounds (velocity: the velocity state
bounds, or the input bound of a single integrator; acceleration: the input bound of a
double integrator). Velocity scales by 1/s and acceleration by 1/s^2, so that s is
exact, no bisection needed. The bounds the curve met at FPP's own duration are reported
(``counters["fpp_speed_ratio"]``, ``["fpp_accel_ratio"]``: the largest |v| and |a| over
their bounds, from the control points; above 1, FPP's curve breaks them).

**What is returned** is a continuous-time curve, as ``gcs`` returns
(:mod:`~plansynth.reach.planners.curves`): sampled at dt (states (position, velocity),
inputs the acceleration) and densely, checked by the validator's ``dynamics="curve"``
mode (collision of the samples and of the segments between them, |v| and |a|, the
derivative consistency of the dense samples). The guarantee (:data:`GUARANTEE`) is not
the lazy planner's: no trajectory of the discrete dynamics x' = A x + B u. Every piece's
control points lie in one box, so the whole curve is free; FPP cannot prove
infeasibility, and a run without a curve is ``unknown``.

**Budget.** FPP's solver calls (cvxpy, Clarabel) cannot be interrupted, so FPP runs in
a child process (:func:`plansynth.isolate.run_isolated`) killed when the budget runs
out: the answer is then ``unknown``, and nothing is left running. The result's
``seconds`` are FPP's own (its offline and online phases, measured in the child, as a
user of the library times them) plus the sets and the sampling here;
``timings["isolation"]`` holds the rest of the wall-clock time (the child's start,
importing cvxpy and the library, sending the curve back).
"""

from __future__ import annotations

import contextlib
import io
import math
import time
from typing import Any

import numpy as np

from plansynth.budget import Budget, BudgetExhausted
from plansynth.errors import SolverUnavailable
from plansynth.reach.geometry import Box, halfspaces
from plansynth.reach.planners.convex_sets import maximal_free_boxes
from plansynth.reach.planners.curves import (
    CurveRun,
    PiecewiseBezier,
    derivative_bounds,
    integrator_order,
    position_box,
    sampled_curve,
)
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult
from plansynth.registry import extra_remedy

__all__ = ["plan_fpp", "run", "GUARANTEE", "fpp_version"]

#: Seconds of FPP's nominal duration per metre of the workspace's longest side (its maze
#: example: T = 10 x side); only a scale: the duration is chosen after planning.
NOMINAL_SECONDS_PER_METRE = 10.0
#: The child process gets the budget left plus this (it is killed after that).
GRACE = 0.5

GUARANTEE = (
    "continuous-time curve (FPP): piecewise Bezier curve with every piece's control points in one free box, so "
    "the whole curve avoids the obstacles (convex-hull property); FPP plans no dynamics and no velocity or "
    "acceleration bound: its curve is re-timed uniformly to the shortest duration at which |v| and |a| stay "
    "within the problem's bounds; NOT a trajectory of the exact discrete dynamics x' = A x + B u with "
    "piecewise-constant inputs (the samples at dt are states of the continuous curve: the validator checks "
    "their positions, segments, |v| and |a|, and the dense curve, and reports the dynamics residual without "
    "requiring it)"
)


def fpp_version() -> str:
    try:
        from importlib.metadata import version

        return version("fastpathplanning")
    except Exception:  # pragma: no cover - metadata missing
        return "unknown"


def _require_fpp() -> None:
    """FPP runs in a child process: say here, in this one, when it is not installed."""
    import importlib.util

    try:
        found = importlib.util.find_spec("fastpathplanning") is not None
    except ValueError:  # a module set to None in sys.modules: as if not installed
        found = False
    if not found:
        raise SolverUnavailable("fpp", extra_remedy("fastpathplanning", "baselines"))


def _fpp_in_child(
    lo: np.ndarray, hi: np.ndarray, p_init: np.ndarray, p_term: np.ndarray, T: float, alpha: tuple[float, ...]
) -> dict[str, Any]:
    """FPP's offline and online phases (run in the child process): the curve's control
    points and transition times, and the phases' seconds."""
    import fastpathplanning as fpp

    out = io.StringIO()  # FPP prints its progress whatever ``verbose`` says
    with contextlib.redirect_stdout(out):
        t0 = time.perf_counter()
        S = fpp.SafeSet(lo, hi, verbose=False)
        t1 = time.perf_counter()
        d = len(p_init)
        path = fpp.plan(S, p_init, p_term, T, list(alpha), der_init={1: np.zeros(d)}, verbose=False)
        t2 = time.perf_counter()
    if path is None:  # pragma: no cover - fpp returns a curve or raises
        return {"offline": t1 - t0, "online": t2 - t1, "points": None}
    return {
        "offline": t1 - t0,
        "online": t2 - t1,
        "points": [np.asarray(b.points, float) for b in path.beziers],
        "breaks": np.array([path.beziers[0].a] + [b.b for b in path.beziers], float),
    }


def _terminal_point(problem: ReachProblem, boxes: list[Box]) -> np.ndarray | None:
    """A point of the goal in some box: the goal's centre when a box holds it, else the
    centre of the largest intersection of the goal with a box."""
    goal = problem.goal
    if isinstance(goal, Box):
        glo, ghi = np.array(goal.lo), np.array(goal.hi)
    else:
        v = np.asarray(goal.vertices, float)  # type: ignore[union-attr]
        glo, ghi = v.min(axis=0), v.max(axis=0)
    centre = (glo + ghi) / 2
    H, h = halfspaces(goal)  # type: ignore[arg-type]
    if any(b.contains(centre) for b in boxes) and np.all(H @ centre <= h + 1e-9):
        return centre
    best, size = None, 0.0
    for b in boxes:
        lo, hi = np.maximum(glo, b.lo), np.minimum(ghi, b.hi)
        c = (lo + hi) / 2
        if np.all(hi >= lo) and np.all(H @ c <= h + 1e-9) and (best is None or np.prod(hi - lo) > size):
            best, size = c, float(np.prod(hi - lo))
    return best


def plan_fpp(
    problem: ReachProblem,
    budget: Budget = Budget(seconds=60.0),
    *,
    derivative: int = 3,
    segment_safe: bool = True,
    max_horizon: int | None = None,
    progress: Any = None,
) -> ReachResult:
    """Plan with FPP (see the module doc) within ``budget`` (its seconds; iterations are
    not used), minimising the squared L2 norm of the ``derivative``-th derivative
    (FPP's ``alpha`` with that one weight; its examples: 3, the jerk). The curve is *not* yet validated (:func:`plansynth.reach.solve` does it).
    ``segment_safe``, ``max_horizon`` and ``progress`` do not apply: the whole curve is
    kept in the boxes, and FPP has no horizon."""
    from plansynth.isolate import Crash, Finished, run_isolated

    if derivative < 1:
        raise ValueError(f"derivative must be at least 1, got {derivative}")
    alpha = (0.0,) * (derivative - 1) + (1.0,)
    k = integrator_order(problem, "fpp")
    if not all(isinstance(o, Box) for o in problem.obstacles):
        raise SolverUnavailable("fpp", "FPP plans through boxes: every obstacle must be a box (use gcs or lazy-smt)")
    if not problem.starts_at_rest:
        raise SolverUnavailable("fpp", "the fpp baseline starts at rest; this problem's start moves (use lazy-smt)")
    _require_fpp()
    t0 = time.perf_counter()
    rec = CurveRun("fpp", t0, options={"alpha": list(alpha), "fastpathplanning": fpp_version(), "sets": "boxes"})
    counters, timings, unknown = rec.counters, rec.timings, rec.unknown

    clock = budget.clock()
    ts = time.perf_counter()
    try:
        with clock.phase("the boxes"):
            boxes = maximal_free_boxes(problem)
    except BudgetExhausted as exc:
        timings["sets"] = time.perf_counter() - ts
        return unknown(str(exc))
    pbox = position_box(problem)
    boxes = [
        Box(tuple(np.maximum(b.lo, pbox.lo)), tuple(np.minimum(b.hi, pbox.hi)))
        for b in boxes
        if np.all(np.minimum(b.hi, pbox.hi) > np.maximum(b.lo, pbox.lo))
    ]
    timings["sets"] = time.perf_counter() - ts
    counters["boxes"] = len(boxes)
    p_init = np.asarray(problem.start_position, float)
    p_term = _terminal_point(problem, boxes)
    if p_term is None or not any(b.contains(p_init) for b in boxes):
        return unknown("the start or the goal lies in no free box")
    T0 = NOMINAL_SECONDS_PER_METRE * max(h - lo for lo, h in zip(problem.workspace.lo, problem.workspace.hi))
    lo = np.array([b.lo for b in boxes], float)
    hi = np.array([b.hi for b in boxes], float)
    left = clock.remaining()
    tc = time.perf_counter()
    out = run_isolated(
        _fpp_in_child,
        lo,
        hi,
        p_init,
        p_term,
        T0,
        alpha,
        timeout=None if math.isinf(left) else max(0.05, left) + GRACE,
        memory_mb=budget.memory_mb,
    )
    wall = time.perf_counter() - tc
    if not isinstance(out, Finished):
        # the child's start-up is not known apart from FPP's work here: the run's seconds
        # are all of it (a run killed at the budget took the budget, not 0 s)
        timings["child"] = wall
        if isinstance(out, Crash):
            last = out.describe()
            return unknown(f"FPP found no curve ({last})")
        return unknown(f"budget ran out in FPP (killed after {wall:.1f} s)")
    value = out.value
    timings["offline"], timings["online"] = value["offline"], value["online"]
    timings["isolation"] = max(0.0, wall - value["offline"] - value["online"])
    if value["points"] is None:
        return unknown("FPP found no curve; FPP cannot prove infeasibility")
    if budget.seconds is not None and time.perf_counter() - t0 - timings["isolation"] > budget.seconds:
        return unknown(f"FPP ran past its budget of {budget.seconds:g} s")

    tr = time.perf_counter()
    curve = PiecewiseBezier(tuple(value["points"]), np.asarray(value["breaks"], float) - value["breaks"][0])
    # FPP's own curve against the problem's bounds, and the uniform re-timing that keeps them
    v = curve.derivative()
    a = v.derivative()
    speed = _ratio(v, derivative_bounds(problem, 1) if k == 2 else _input_box(problem))
    accel = _ratio(a, _input_box(problem)) if k == 2 else 0.0
    stretch = max(speed, math.sqrt(accel), 1e-12)
    curve = curve.stretched(stretch)
    sampled = sampled_curve(problem, curve, k)
    N, extra, dense_times = sampled[3], sampled[4], sampled[2]
    counters.update(
        {
            "pieces": len(curve.points),
            "fpp_duration": float(T0),
            "fpp_speed_ratio": float(speed),
            "fpp_accel_ratio": float(accel),
            "retimed_duration": float(curve.duration),
            "curve_seconds": float(N * problem.dynamics.dt),  # type: ignore[operator]
            "stretch": float(extra),
            "curve_samples": len(dense_times),
        }
    )
    timings["sample"] = time.perf_counter() - tr
    return rec.found(sampled, GUARANTEE)


def _input_box(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
    b = problem.input_bound * np.ones(problem.dim)
    return -b, b


def _ratio(curve: PiecewiseBezier, bounds: tuple[np.ndarray, np.ndarray] | None) -> float:
    """The largest factor by which the curve's control points exceed ``bounds`` (per
    axis, each side; 0 without bounds)."""
    if bounds is None:
        return 0.0
    lo, hi = (np.asarray(x, float) for x in bounds)
    cmin, cmax = curve.extremes()
    with np.errstate(divide="ignore", invalid="ignore"):
        up = np.where(hi > 0, np.maximum(cmax, 0) / hi, np.where(cmax > 0, np.inf, 0.0))
        down = np.where(lo < 0, np.minimum(cmin, 0) / lo, np.where(cmin < 0, np.inf, 0.0))
    return float(np.max(np.concatenate([up, down])))


def run(problem: ReachProblem, budget: Budget, options: Any, progress: Any = None) -> ReachResult:
    """``fpp`` as a planner of :func:`plansynth.reach.solve`: :func:`plan_fpp` with the
    fields of its options value."""
    return plan_fpp(
        problem,
        budget,
        derivative=options.derivative,
        segment_safe=options.segment_safe,
        max_horizon=options.max_horizon,
        progress=progress,
    )

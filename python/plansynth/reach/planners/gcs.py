"""Graphs of Convex Sets (GCS) as a baseline reach-avoid planner (``gcs``).

The planner a robotics user would reach for today to plan through convex free space:
Marcucci, Petersen, von Wrangel and Tedrake, "Motion planning around obstacles with
convex optimization", Science Robotics 2023 (Section "Results": trajectory design with
Bezier curves in a graph of convex sets), as implemented by Drake's
``pydrake.planning.GcsTrajectoryOptimization``.

**The convex sets** (``sets``). GCS is meant for sets that *overlap*: a curve passes
from one set to the next inside their intersection. ``sets="auto"`` (the default) gives
it the sets its users build (:mod:`plansynth.reach.planners.convex_sets`): the maximal
free boxes grown from the obstacle grid when every obstacle is a box (``"boxes"``), and
Drake's IRIS regions where obstacles are polygons (``"iris"``), with an edge between two
sets whose intersection has nonempty interior, both ways. ``sets="decomposition"``
gives it *our* free-space regions instead, the disjoint ones the lazy SMT planner walks
(:func:`plansynth.reach.abstraction.abstract`, with its adjacency as the graph's
edges), which touch only along faces: a weaker baseline (every junction of the curve
on a shared face; maze-2: 0.44 s against 0.21 s over the boxes), kept to compare
planners over the same decomposition.

What is posed (one Bezier curve of ``order`` per visited region, a duration h per
region, the sum of durations minimised: ``AddTimeCost``):

``variant="like-for-like"`` (default), the peer of the lazy planner's semantics:
  the workspace position and the convex regions as the sets (control points inside a
  region keep the whole piece inside it: convex-hull property of Bezier curves), the
  start position as the source with zero velocity (``AddZeroDerivativeConstraints``:
  the start is at rest), the goal shape as the target set, the problem's velocity
  bounds (the state bounds of the velocity components) as ``AddVelocityBounds``,
  velocity continuity (``AddContinuityConstraints(1)``: exact in the rounding step, its
  own convex surrogate in the relaxation) and ``|a| <= input_bound``
  (``AddNonlinearDerivativeBounds``, order 2). Drake solves the convex relaxation
  (Clarabel), rounds it to paths and solves each path's nonconvex restriction (IPOPT).
  Path continuity ``AddPathContinuityConstraints(1)`` (dr/ds continuous) is *not*
  added: together with true velocity continuity it forces, at every junction, equal
  piece durations or a stop, which made the curves 20% longer (maze-1: 38.9 s instead
  of 32.5 s) and IPOPT 5-10x slower, or stopped it at its iteration limit (maze-3/4).
``variant="surrogate"``: like-for-like without the exact continuity constraint, only
  its convex surrogate (continuity of the path derivative dr/ds, which is velocity
  continuity only where neighbouring pieces have equal durations). Much faster and
  much more often solved by IPOPT, but its velocity jumps where a piece's duration
  changes (maze-1: from 0.05 to 2 m/s entering the wall's gap), so the validator's
  derivative check rejects it: it shows what the like-for-like variant costs.
``variant="convex"``: the plain convex form, continuity of the curve only, velocity
  bounds only: fast, but its velocity jumps at region changes and its acceleration is
  unbounded, so it is not a peer of the discrete dynamics (the validator rejects it for
  the double integrator: the "derivative" check).

Time scaling: Drake's surrogates assume segments of about one time unit (the
characteristic time h0 = 1 of ``AddNonlinearDerivativeBounds``; with time in seconds
the like-for-like variant is infeasible on every maze). The planner therefore solves
in units of ``time_unit`` seconds (default 10 s: velocity bounds scaled by T,
acceleration bounds by T^2) and maps the curve back to seconds.

The answer: the curve is re-timed to ``N dt`` with ``N = ceil(duration / dt)`` (a
uniform stretch by a factor >= 1, which keeps every bound and the start at rest) and
sampled at ``t_k = k dt``; the state of the sample is (position, velocity), its input
the curve's acceleration at t_k. A denser sampling (``CURVE_SUBSTEPS`` per dt, plus
every piece's end points) is returned as ``ReachResult.curve``. This is **not** a
trajectory of the discrete dynamics ``x' = A x + B u`` with piecewise-constant inputs:
the guarantee is ``"curve"`` (:data:`GUARANTEE`), and the validator runs in its
``dynamics="curve"`` mode: positions, segments between samples, velocities and inputs
are checked on both samplings, the derivative consistency of the dense one, and the
dynamics residual is reported, not required.

Supported robots: the named single- and double-integrator models (integrator chains of
order 1 and 2); other dynamics raise :class:`~plansynth.errors.SolverUnavailable`.
GCS cannot prove infeasibility (the relaxation and the rounding are heuristics): a run
without a curve is ``unknown``.
"""

from __future__ import annotations

import logging
import time
from typing import Any

import numpy as np

from plansynth.budget import Budget, BudgetExhausted
from plansynth.errors import SolverUnavailable
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.geometry import halfspaces
from plansynth.reach.planners.convex_sets import ConvexSets, overlapping_sets
from plansynth.reach.planners.curves import (
    CURVE_SUBSTEPS,
    CurveRun,
    PiecewiseBezier,
    derivative_bounds,
    integrator_order,
    position_box,
    sampled_curve,
)
from plansynth.reach.planners.options import GCS_SETS as SETS
from plansynth.reach.planners.options import GCS_VARIANTS as VARIANTS
from plansynth.reach.planners.options import GcsOptions
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult
from plansynth.registry import extra_remedy

__all__ = ["plan_gcs", "VARIANTS", "SETS", "GUARANTEE", "DEFAULT_TIME_UNIT", "CURVE_SUBSTEPS", "drake_version"]

DEFAULT_TIME_UNIT = 10.0
IPOPT_MAX_ITER = 100_000  # with a time budget: its share of the time ends IPOPT first
SOLVER_SHARE = 0.4  # of the time left: the relaxation's, and all restrictions' together
#: Drake's preprocessing (one small convex program per edge, to drop edges no path can
#: use) cannot be interrupted: on the 50 x 50 GCS maze (3,300 edges) it ran for minutes
#: past a 20 s budget. Beyond this many regions it is off.
PREPROCESS_MAX_REGIONS = 200
#: rounded paths tried by default: Drake's 5 up to PREPROCESS_MAX_REGIONS regions, 1
#: beyond. Every restriction's share of the budget is fixed before Drake starts (it
#: cannot be interrupted between them), and on the GCS paper's 20 x 20 and 50 x 50
#: mazes a 150-piece path's IPOPT restriction needs about 40 s: with five shares of
#: 120 s it stopped at its wall-time limit (reported as an iteration limit) after
#: 10 s, with one it finds the curve.
LARGE_MAX_ROUNDED_PATHS = 1
DEFAULT_MAX_ROUNDED_PATHS = 5

#: What a ``gcs`` result guarantees, and how that differs from the discrete planners.
GUARANTEE = (
    "continuous-time curve (GCS): piecewise Bezier curve with every piece's control points in one convex "
    "free-space region, so the whole curve avoids the obstacles (convex-hull property), |v| within the velocity "
    "bounds on the whole curve and, in the like-for-like variant, |a| <= input_bound on the whole curve and "
    "velocity continuous; NOT a trajectory of the exact discrete dynamics x' = A x + B u with piecewise-constant "
    "inputs (the samples at dt are states of the continuous curve: the validator checks their positions, "
    "segments, |v| and |a|, and the dense curve, and reports the dynamics residual without requiring it)"
)

log = logging.getLogger("plansynth.reach.planners.gcs")


def drake_version() -> str:
    try:
        from importlib.metadata import version

        return version("drake")
    except Exception:  # pragma: no cover - metadata missing
        return "unknown"


def _import_drake() -> dict[str, Any]:
    try:
        from pydrake.geometry.optimization import GraphOfConvexSetsOptions, HPolyhedron, Point
        from pydrake.planning import GcsTrajectoryOptimization
        from pydrake.solvers import ClarabelSolver, IpoptSolver, SolverOptions
    except ImportError as exc:  # drake comes with the baselines extra
        raise SolverUnavailable("gcs", extra_remedy("pydrake", "baselines")) from exc
    return {
        "Gcs": GcsTrajectoryOptimization,
        "Options": GraphOfConvexSetsOptions,
        "HPolyhedron": HPolyhedron,
        "Point": Point,
        "Clarabel": ClarabelSolver,
        "Ipopt": IpoptSolver,
        "SolverOptions": SolverOptions,
    }


def rounded_paths(n_regions: int, requested: int | None = None) -> int:
    """How many paths Drake rounds the relaxation to: ``requested``, else
    :data:`DEFAULT_MAX_ROUNDED_PATHS` up to :data:`PREPROCESS_MAX_REGIONS` regions and
    :data:`LARGE_MAX_ROUNDED_PATHS` beyond (see there)."""
    if requested is not None:
        if requested < 1:
            raise ValueError(f"max_rounded_paths must be at least 1, got {requested}")
        return int(requested)
    return DEFAULT_MAX_ROUNDED_PATHS if n_regions <= PREPROCESS_MAX_REGIONS else LARGE_MAX_ROUNDED_PATHS


def _sets(problem: ReachProblem, sets: str, abstraction: Abstraction | None) -> ConvexSets:
    """The convex sets and their edges: overlapping ones, or the decomposition's regions
    with its adjacency (``sets="decomposition"``)."""
    if sets != "decomposition":
        return overlapping_sets(problem, sets)
    a = abstract(problem) if abstraction is None else abstraction
    return ConvexSets(
        "decomposition",
        tuple(r.H for r in a.regions),
        tuple(r.h for r in a.regions),
        tuple((i, j) for i, nb in enumerate(a.adjacency) for j in nb if i < j),
    )


def plan_gcs(
    problem: ReachProblem,
    budget: Budget = Budget(seconds=60.0),
    *,
    variant: str = "like-for-like",
    order: int = 5,
    time_unit: float = DEFAULT_TIME_UNIT,
    max_rounded_paths: int | None = None,
    sets: str = "auto",
    abstraction: Abstraction | None = None,
    segment_safe: bool = True,
    max_horizon: int | None = None,
    progress: Any = None,
) -> ReachResult:
    """Plan with Drake's GCS trajectory optimisation (see the module doc) within ``budget``.

    ``sets``: ``"auto"``, ``"boxes"``, ``"iris"`` (overlapping sets,
    :func:`~plansynth.reach.planners.convex_sets.overlapping_sets`) or
    ``"decomposition"`` (the lazy planner's disjoint regions; ``abstraction``, when
    given, is that decomposition).

    ``budget.seconds`` becomes the time limit of Drake's solvers (Clarabel's
    ``time_limit``, IPOPT's ``max_wall_time``) and is checked once more when Drake
    returns: past it the status is ``unknown`` (GCS cannot be interrupted between its
    solver calls, so it may overrun by one solver call). The relaxation gets 40% of
    the time left after the sets are built (within the budget too), each
    rounded path's restriction an equal share of another 40%; the graph's
    construction is not interruptible, nor is Drake's preprocessing, which is therefore
    off beyond :data:`PREPROCESS_MAX_REGIONS` regions, where ``max_rounded_paths``
    also defaults to :data:`LARGE_MAX_ROUNDED_PATHS` (else Drake's 5), so that one
    restriction gets the whole share. ``budget.iterations`` is not
    used. The trajectory is *not* yet validated (:func:`plansynth.reach.solve` does it).
    ``segment_safe``, ``max_horizon`` and ``progress`` (the options every planner is
    given) do not apply: the whole curve is kept in the regions, and GCS has no horizon.
    """
    if variant not in VARIANTS:
        raise ValueError(f"unknown gcs variant {variant!r} (known: {', '.join(VARIANTS)})")
    if sets not in SETS:
        raise ValueError(f"unknown gcs sets {sets!r} (known: {', '.join(SETS)})")
    if not time_unit > 0:
        raise ValueError(f"time_unit must be positive, got {time_unit}")
    k = integrator_order(problem, "gcs")
    D = _import_drake()
    t0 = time.perf_counter()
    T = float(time_unit)
    d = problem.dim
    dt = float(problem.dynamics.dt)  # type: ignore[arg-type]
    options = {
        "variant": variant,
        "order": order,
        "time_unit": T,
        "sets": sets,
        "drake": drake_version(),
        "relaxation_solver": "Clarabel",
        "restriction_solver": "IPOPT" if variant != "convex" and k == 2 else "Clarabel",
    }
    rec = CurveRun("gcs", t0, options=options)
    counters, timings, unknown = rec.counters, rec.timings, rec.unknown

    ta = time.perf_counter()
    try:
        with budget.clock().phase("the convex sets"):
            graph = _sets(problem, sets, abstraction)
    except BudgetExhausted as exc:
        timings["sets"] = time.perf_counter() - ta
        return unknown(str(exc))
    timings["sets"] = time.perf_counter() - ta
    options["sets"] = graph.kind
    counters["regions"] = len(graph.H)
    counters["set_edges"] = len(graph.edges)
    max_rounded_paths = rounded_paths(len(graph.H), max_rounded_paths)
    options["max_rounded_paths"] = max_rounded_paths
    pbox = position_box(problem)
    Hb, hb = halfspaces(pbox)
    hpolys = [D["HPolyhedron"](np.vstack([H, Hb]), np.concatenate([h, hb])) for H, h in zip(graph.H, graph.h)]
    edges = [e for i, j in graph.edges for e in ((i, j), (j, i))]
    Hg, hg = halfspaces(problem.goal)
    goal_set = D["HPolyhedron"](np.vstack([Hg, Hb]), np.concatenate([hg, hb]))

    tb = time.perf_counter()
    gcs = D["Gcs"](d)
    main = gcs.AddRegions(hpolys, edges, order=order, h_min=1e-6, h_max=20.0, name="free")
    source = gcs.AddRegions([D["Point"](problem.start_position)], order=0, name="start")
    target = gcs.AddRegions([goal_set], order=0, name="goal")
    # the source and target connect to the regions that contain the start / meet the goal
    src_edges = gcs.AddEdges(source, main)
    gcs.AddEdges(main, target)
    gcs.AddTimeCost()
    if k == 1:
        # single integrator: the input is the velocity
        ub = problem.input_bound * T * np.ones(d)
        gcs.AddVelocityBounds(-ub, ub)
    else:
        vb = derivative_bounds(problem, 1)
        if vb is not None:
            gcs.AddVelocityBounds(vb[0] * T, vb[1] * T)
        if variant in ("like-for-like", "surrogate"):
            if not problem.starts_at_rest:
                raise SolverUnavailable(
                    "gcs",
                    f"the {variant} GCS variant starts at rest; this problem's start "
                    "has a nonzero velocity (use variant=convex or lazy-smt)",
                )
            src_edges.AddZeroDerivativeConstraints(1)
            if variant == "like-for-like":
                # true velocity continuity (nonconvex: exact in the restriction, its
                # convex surrogate in the relaxation); NOT together with the path
                # continuity dr/ds below, which would force equal piece durations or
                # rest at every junction (curves 20% longer, IPOPT 5-10x slower)
                gcs.AddContinuityConstraints(1)
            else:
                gcs.AddPathContinuityConstraints(1)
            ab = problem.input_bound * T * T * np.ones(d)
            gcs.AddNonlinearDerivativeBounds(-ab, ab, 2)
    timings["build"] = time.perf_counter() - tb

    opts = D["Options"]()
    opts.convex_relaxation = True
    opts.preprocessing = len(graph.H) <= PREPROCESS_MAX_REGIONS
    counters["preprocessing"] = bool(opts.preprocessing)
    opts.max_rounded_paths = int(max_rounded_paths)
    opts.solver = D["Clarabel"]()
    nonconvex = variant != "convex" and k == 2
    opts.restriction_solver = D["Ipopt"]() if nonconvex else D["Clarabel"]()
    so = D["SolverOptions"]()
    rso = D["SolverOptions"]()
    if budget.seconds is not None:
        # the relaxation gets 40% of what is left, each of the (up to
        # max_rounded_paths) restrictions an equal share of another 40%, the rest is
        # for Drake's rounding between them: each limit is per solver call, so giving
        # every call all that is left let a 50 x 50 maze overrun its budget several
        # times over (with halves it still overran 120 s by 12 s once)
        left = max(0.05, float(budget.seconds) - (time.perf_counter() - t0))
        share = max(0.05, SOLVER_SHARE * left / max(1, int(max_rounded_paths)))
        so.SetOption(D["Clarabel"].id(), "time_limit", SOLVER_SHARE * left)
        if nonconvex:
            rso.SetOption(D["Ipopt"].id(), "max_wall_time", share)
            # the wall time, not IPOPT's 3,000 iterations, ends a long restriction (the
            # 20 x 20 GCS maze's 150-region path stopped at the iteration limit in 27 s)
            rso.SetOption(D["Ipopt"].id(), "max_iter", IPOPT_MAX_ITER)
        else:
            rso.SetOption(D["Clarabel"].id(), "time_limit", share)
    opts.solver_options = so
    opts.restriction_solver_options = rso
    ts = time.perf_counter()
    prev = logging.getLogger("drake").level
    logging.getLogger("drake").setLevel(logging.WARNING)
    try:
        traj, res = gcs.SolvePath(source, target, opts)
    finally:
        logging.getLogger("drake").setLevel(prev)
    timings["solve"] = time.perf_counter() - ts
    counters["solution_result"] = str(res.get_solution_result()).split(".")[-1]
    if budget.seconds is not None and time.perf_counter() - t0 > budget.seconds:
        return unknown(f"GCS ran past its budget of {budget.seconds:g} s ({counters['solution_result']})")
    if not res.is_success():
        return unknown(f"GCS found no curve ({counters['solution_result']}); GCS cannot prove infeasibility")

    tr = time.perf_counter()
    pieces = [traj.segment(i) for i in range(traj.get_number_of_segments())]
    # the source and target pieces are constant (order 0, duration h_min): drop them
    pieces = [p for p in pieces if p.order() > 0 and p.end_time() - p.start_time() > 1e-12]
    t_start, t_end = pieces[0].start_time(), pieces[-1].end_time()
    duration = (t_end - t_start) * T
    # the pieces in seconds (Drake's time in units of T), from t = 0
    bezier = PiecewiseBezier(
        tuple(np.asarray(p.control_points(), float).T for p in pieces),
        np.array([(p.start_time() - t_start) * T for p in pieces] + [duration]),
    )
    sampled = sampled_curve(problem, bezier, k)
    N, stretch, dense_times = sampled[3], sampled[4], sampled[2]
    visited = []
    for p in pieces:
        mid = p.value(0.5 * (p.start_time() + p.end_time())).ravel()
        inside = graph.containing(mid)
        visited.append(inside[0] if inside else -1)
    timings["sample"] = time.perf_counter() - tr
    counters.update(
        {
            "pieces": len(pieces),
            "curve_seconds": float(N * dt),
            "gcs_duration": float(duration),
            "stretch": float(stretch),
            "curve_samples": len(dense_times),
            "set_sequence": [int(r) for r in visited],
        }
    )
    return rec.found(sampled, GUARANTEE, tuple(int(r) for r in visited) if graph.kind == "decomposition" else None)


def run(
    problem: ReachProblem,
    budget: Budget,
    options: GcsOptions,
    progress: Any = None,
    abstraction: Abstraction | None = None,
) -> ReachResult:
    """``gcs`` as a planner of :func:`plansynth.reach.solve`: :func:`plan_gcs` with the
    fields of its options value."""
    return plan_gcs(
        problem,
        budget,
        variant=options.variant,
        order=options.order,
        time_unit=options.time_unit,
        max_rounded_paths=options.max_rounded_paths,
        sets=options.sets,
        abstraction=abstraction,
        segment_safe=options.segment_safe,
        max_horizon=options.max_horizon,
        progress=progress,
    )

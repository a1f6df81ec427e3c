"""Kinodynamic sampling baselines from OMPL's control planners (RRT, EST, KPIECE1).

The paper compares its lazy SMT planner with an RRT that plans directly with the
discrete-time dynamics (Shoukry et al., CDC 2016, Section VI, Table I, column "RRT").
This module is that peer, built on OMPL (Sucan, Moll and Kavraki, 2012):

- the state space is ``R^n`` (the dynamics' state), bounded by ``state_bounds`` (or the
  workspace for the position components and ``+-DEFAULT_STATE_SPAN`` elsewhere);
- the control space is ``[-input_bound, input_bound]^m`` (the paper's ``||u||_inf``);
- the state propagator applies the *exact* discrete dynamics ``x' = A x + B u`` once,
  and the propagation step is set so that one control step is one discrete step
  (minimum and maximum control duration 1): every edge of the tree is one time step;
- a state is valid when it satisfies the state bounds, its position lies in the
  workspace and outside every obstacle's interior (Definition 2.3); by default an edge
  whose straight segment enters an obstacle is rejected as well, so that the RRT gives
  the same segment guarantee as the lazy SMT planner (``segment_safe=False``: samples
  only, the paper's semantics);
- the goal is the region of states whose position lies in the goal shape;
- OMPL's random number generator is seeded, so a run is reproducible up to timing.

The found path is turned into a :class:`~plansynth.reach.trajectory.Trajectory` of
discrete steps by replaying its controls through the dynamics; :func:`plansynth.reach.solve`
reports it as found only if the independent validator (:mod:`plansynth.reach.validate`) accepts it.
Sampling planners cannot prove infeasibility: a run that ends without an exact
solution is ``unknown``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.reach.geometry import Box, Polygon, shape_to_shapely
from plansynth.reach.planners.options import OmplOptions
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.registry import extra_remedy

__all__ = ["PLANNERS", "plan_rrt", "ompl_version", "DEFAULT_STATE_SPAN", "run_rrt", "run_est", "run_kpiece"]

#: Bound used for non-position state components when the problem gives no state bounds.
DEFAULT_STATE_SPAN = 10.0

_SEEDED: int | None = None

#: OMPL control planners offered here (our name -> OMPL class name).
PLANNERS: dict[str, str] = {"rrt": "RRT", "est": "EST", "kpiece": "KPIECE1"}


def ompl_version() -> str:
    try:
        from importlib.metadata import version

        return version("ompl")
    except Exception:  # pragma: no cover - metadata missing
        return "unknown"


def _import_ompl() -> tuple[Any, Any, Any]:
    try:
        import ompl.base as ob
        import ompl.control as oc
        import ompl.util as ou
    except ImportError as exc:  # ompl comes with the baselines extra
        raise SolverUnavailable("ompl", extra_remedy("ompl", "baselines")) from exc
    return ob, oc, ou


def _state_bounds(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
    n = problem.dynamics.n_states
    if problem.state_bounds is not None:
        return np.array(problem.state_bounds.lo, dtype=float), np.array(problem.state_bounds.hi, dtype=float)
    lo = np.full(n, -DEFAULT_STATE_SPAN)
    hi = np.full(n, DEFAULT_STATE_SPAN)
    for axis, i in enumerate(problem.dynamics.position):
        lo[i] = problem.workspace.lo[axis]
        hi[i] = problem.workspace.hi[axis]
    return lo, hi


def _free_test(problem: ReachProblem) -> Callable[[np.ndarray], bool]:
    """``free(p)``: p in the workspace and outside every obstacle's interior."""
    ws_lo = np.array(problem.workspace.lo)
    ws_hi = np.array(problem.workspace.hi)
    boxes = [o for o in problem.obstacles if isinstance(o, Box)]
    box_lo = np.array([b.lo for b in boxes]) if boxes else None
    box_hi = np.array([b.hi for b in boxes]) if boxes else None
    polys = [o for o in problem.obstacles if isinstance(o, Polygon)]
    poly_union = None
    if polys:
        import shapely

        poly_union = shapely.union_all([shape_to_shapely(p) for p in polys])
        shapely.prepare(poly_union)

    def free(p: np.ndarray) -> bool:
        if np.any(p < ws_lo) or np.any(p > ws_hi):
            return False
        if box_lo is not None and np.any(np.all((box_lo < p) & (p < box_hi), axis=1)):
            return False
        if poly_union is not None:
            import shapely

            if poly_union.contains(shapely.Point(float(p[0]), float(p[1]))):
                return False
        return True

    return free


def _segment_test(problem: ReachProblem) -> Callable[[np.ndarray, np.ndarray], bool]:
    """``blocked(p, q)``: the segment p -> q enters some obstacle's interior."""
    boxes = [o for o in problem.obstacles if isinstance(o, Box)]
    box_lo = np.array([b.lo for b in boxes], dtype=float) if boxes else None
    box_hi = np.array([b.hi for b in boxes], dtype=float) if boxes else None
    polys = [o for o in problem.obstacles if isinstance(o, Polygon)]
    union = None
    if polys:
        import shapely

        union = shapely.union_all([shape_to_shapely(p) for p in polys])

    def blocked(p: np.ndarray, q: np.ndarray) -> bool:
        if box_lo is not None:
            d = q - p
            with np.errstate(divide="ignore", invalid="ignore"):
                t1 = (box_lo - p) / d
                t2 = (box_hi - p) / d
            lo_t = np.where(d == 0, np.where((box_lo < p) & (p < box_hi), -np.inf, np.inf), np.minimum(t1, t2))
            hi_t = np.where(d == 0, np.where((box_lo < p) & (p < box_hi), np.inf, -np.inf), np.maximum(t1, t2))
            tmin = lo_t.max(axis=1)
            tmax = hi_t.min(axis=1)
            if np.any((tmin < tmax) & (tmin < 1.0) & (tmax > 0.0)):
                return True
        if union is not None:
            import shapely

            seg = shapely.LineString([(float(p[0]), float(p[1])), (float(q[0]), float(q[1]))])
            if seg.length == 0:
                return bool(union.contains(shapely.Point(float(p[0]), float(p[1]))))
            if union.relate_pattern(seg, "T********"):
                return True
        return False

    return blocked


def _goal_distance(problem: ReachProblem) -> Callable[[np.ndarray], float]:
    goal = problem.goal
    if isinstance(goal, Box):
        lo, hi = np.array(goal.lo), np.array(goal.hi)

        def dist(p: np.ndarray) -> float:
            return float(np.linalg.norm(np.maximum(0.0, np.maximum(lo - p, p - hi))))

        return dist
    import shapely

    g = shape_to_shapely(goal)
    shapely.prepare(g)

    def dist_poly(p: np.ndarray) -> float:
        return float(g.distance(shapely.Point(float(p[0]), float(p[1]))))

    return dist_poly


def plan_rrt(
    problem: ReachProblem,
    budget: Budget = Budget(seconds=60.0),
    seed: int = 0,
    planner: str = "rrt",
    *,
    goal_bias: float | None = None,
    segment_safe: bool = True,
) -> Any:
    """Plan with OMPL's kinodynamic ``planner`` ("rrt", "est" or "kpiece") within ``budget``.

    Returns a :class:`~plansynth.reach.result.ReachResult`, ``found`` with the trajectory
    (not yet validated: :func:`plansynth.reach.solve` does that); sampling never proves infeasibility, so
    otherwise the status is ``unknown``. ``budget.seconds`` bounds the planning time
    (default 60 s when absent); ``budget.iterations`` is not used by OMPL's planners.
    With ``segment_safe`` (the default, as the lazy SMT planner) an edge whose segment
    enters an obstacle is rejected during propagation; without it only the sampled
    positions are checked (the paper's semantics, which lets a step hop over a thin wall).
    """
    from plansynth.reach.result import ReachResult, ReachStatus

    if planner not in PLANNERS:
        raise SolverUnavailable(planner, f"unknown OMPL planner; choose one of {', '.join(PLANNERS)}")
    t0 = time.perf_counter()  # the budget covers importing OMPL and setting up too
    ob, oc, ou = _import_ompl()
    seconds = 60.0 if budget.seconds is None else float(budget.seconds)
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A = np.array(dyn.A)
    B = np.array(dyn.B)
    pos = list(dyn.position)
    lo, hi = _state_bounds(problem)

    ou.setLogLevel(ou.LOG_WARN)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i in range(n):
        bounds.setLow(i, float(lo[i]))
        bounds.setHigh(i, float(hi[i]))
    space.setBounds(bounds)
    cspace = oc.RealVectorControlSpace(space, m)
    cbounds = ob.RealVectorBounds(m)
    cbounds.setLow(-problem.input_bound)
    cbounds.setHigh(problem.input_bound)
    cspace.setBounds(cbounds)
    ss = oc.SimpleSetup(cspace)
    si = ss.getSpaceInformation()

    counters = {"propagations": 0, "validity_checks": 0}

    def propagate(state: Any, control: Any, duration: float, result: Any) -> None:
        # One call = one discrete step: the propagation step size is one step and
        # control durations are fixed to 1, so ``duration`` carries no information.
        counters["propagations"] += 1
        x = np.fromiter((state[i] for i in range(n)), dtype=float, count=n)
        u = np.fromiter((control[j] for j in range(m)), dtype=float, count=m)
        y = A @ x + B @ u
        if segment_safe and blocked(x[pos], y[pos]):
            y = lo - 1.0  # outside the state bounds: the validity checker rejects the edge
        for i in range(n):
            result[i] = float(y[i])

    free = _free_test(problem)
    blocked = _segment_test(problem)

    def valid(state: Any) -> bool:
        counters["validity_checks"] += 1
        x = np.fromiter((state[i] for i in range(n)), dtype=float, count=n)
        if np.any(x < lo) or np.any(x > hi):
            return False
        return free(x[pos])

    goal_dist = _goal_distance(problem)

    class _PositionGoal(ob.GoalRegion):
        def __init__(self, si_: Any) -> None:
            super().__init__(si_)
            # OMPL accepts a state when distanceGoal < threshold; inside the goal it is 0.
            self.setThreshold(1e-9)

        def distanceGoal(self, state: Any) -> float:  # noqa: N802 - OMPL's name
            p = np.fromiter((state[i] for i in pos), dtype=float, count=len(pos))
            return goal_dist(p)

    ss.setStatePropagator(propagate)
    ss.setStateValidityChecker(valid)
    step = float(dyn.dt) if dyn.dt else 1.0
    si.setPropagationStepSize(step)
    si.setMinMaxControlDuration(1, 1)
    goal = _PositionGoal(si)
    ss.setGoal(goal)
    start = space.allocState()
    for i in range(n):
        start[i] = float(problem.start[i])
    ss.setStartState(start)
    global _SEEDED
    seeded = _SEEDED is None
    if _SEEDED is None:
        # OMPL seeds its generators once per process; later calls are ignored (with an
        # error message), so a reproducible run needs a fresh process (as the bench runs).
        ou.RNG.setSeed(int(seed) + 1)  # +1: OMPL reads seed 0 as "unset"
        _SEEDED = int(seed)
    planner_obj = getattr(oc, PLANNERS[planner])(si)
    if goal_bias is not None and hasattr(planner_obj, "setGoalBias"):
        planner_obj.setGoalBias(goal_bias)
    ss.setPlanner(planner_obj)
    setup_s = time.perf_counter() - t0
    remaining = max(0.01, seconds - setup_s)
    t_plan = time.perf_counter()
    status = ss.solve(remaining)
    plan_s = time.perf_counter() - t_plan
    exact = bool(ss.haveExactSolutionPath())
    try:
        pdata = ob.PlannerData(si) if hasattr(ob, "PlannerData") else oc.PlannerData(si)
        ss.getPlannerData(pdata)
        counters["tree_states"] = int(pdata.numVertices())
    except Exception:  # planner data is a counter only
        pass
    options = {
        "planner": PLANNERS[planner],
        "seed": seed,
        "seed_applied": seeded,
        "segment_safe": segment_safe,
        "step": step,
        "goal_bias": goal_bias,
        "ompl": ompl_version(),
    }
    timings = {"plan": plan_s, "setup": setup_s}
    name = planner
    if not exact:
        timings["total"] = time.perf_counter() - t0
        return ReachResult(
            status=ReachStatus.UNKNOWN,
            solver=name,
            seconds=timings["total"],
            trajectory=None,
            regions=None,
            segment_safe=None,
            horizon=None,
            counters=counters,
            timings=timings,
            options=options,
            guarantee="segments" if segment_safe else "samples",
            validated=None,
            validation=None,
            message=(
                f"budget ran out in OMPL {PLANNERS[planner]} planning: no exact solution "
                f"({_status_text(status)}) after {plan_s:.2f} s"
            ),
        )
    path = ss.getSolutionPath()
    inputs: list[np.ndarray] = []
    for k in range(path.getControlCount()):
        c = path.getControl(k)
        u = np.array([c[j] for j in range(m)], dtype=float)
        repeats = max(1, int(round(path.getControlDuration(k) / step)))
        inputs.extend([u] * repeats)
    states = [np.array(problem.start, dtype=float)]
    for u in inputs:
        states.append(A @ states[-1] + B @ u)
    traj = Trajectory(states=np.array(states), inputs=np.array(inputs).reshape(len(inputs), m))
    timings["total"] = time.perf_counter() - t0
    return ReachResult(  # validated by plansynth.reach.solve, like every planner's
        status=ReachStatus.FOUND,
        solver=name,
        seconds=timings["total"],
        trajectory=traj,
        regions=None,
        segment_safe=None,
        horizon=traj.horizon,
        counters=counters,
        timings=timings,
        options=options,
        guarantee="segments" if segment_safe else "samples",
        message="",
    )


def _status_text(status: Any) -> str:
    try:
        return str(status.asString())
    except Exception:
        return str(status)


def _run(name: str) -> Callable[..., Any]:
    def run(problem: ReachProblem, budget: Budget, options: OmplOptions, progress: Any = None) -> Any:
        return plan_rrt(
            problem, budget, options.seed, name, goal_bias=options.goal_bias, segment_safe=options.segment_safe
        )

    run.__name__ = f"run_{name}"
    run.__doc__ = f"OMPL {PLANNERS[name]} as a :func:`plansynth.reach.solve` planner (see :func:`plan_rrt`)."
    return run


#: ``rrt``, ``est`` and ``kpiece`` as planners of :func:`plansynth.reach.solve` read their
#: options value (:class:`~plansynth.reach.planners.options.OmplOptions`); the registry's
#: entries (:mod:`plansynth.reach.planners.baselines`) name these functions.
run_rrt = _run("rrt")
run_est = _run("est")
run_kpiece = _run("kpiece")

"""One-shot big-M MILP over the horizon: the paper's "LTL OPT" stand-in.

Shoukry et al. (CDC 2016, Section VI, Table I, column "LTL OPT") compare their lazy
SMT planner with a monolithic mixed-integer encoding of the whole reach-avoid problem
(in the style of Karaman and Frazzoli's MILP formulation of LTL planning). This module
is that peer, solved with HiGHS:

- continuous variables ``x_0..x_N`` and ``u_0..u_{N-1}``; ``x_0 = start``,
  ``x_{t+1} = A x_t + B u_t`` (equalities), ``|u_t|_inf <= input_bound``, state bounds,
  every position inside the workspace;
- obstacle avoidance by big-M disjunction: every obstacle is split into convex pieces
  ``{p : H p <= h}`` (boxes and convex polygons as they are, non-convex polygons by a
  constrained Delaunay triangulation); for each step t and piece, binaries ``z_{t,j}``
  with ``sum_j z_{t,j} >= 1`` select a face j whose half-plane the position leaves:
  ``H_j p_t >= h_j + margin - M_j (1 - z_{t,j})``, with ``M_j`` the largest violation
  over the workspace box (a tight, per-face constant) and a small ``margin`` (1e-4)
  that keeps positions off the pieces' shared edges;
- the final position lies in the goal: ``H_g p_N <= h_g``.

By default whole segments are kept off the obstacles (both end points of segment t
outside the same face), the guarantee the lazy SMT planner gives; ``segment_safe=False``
constrains only the positions x_t (the paper's sampled semantics). The horizon is not known in advance, so the
solver tries a growing sequence of horizons ``N`` (each a full MILP), starting from a
lower bound on the number of steps; ``infeasible`` is never claimed (a proof would need
every N up to ``max_horizon``); the objective is feasibility (0), or the L1 norm of the
inputs with ``objective="l1"``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from plansynth.budget import Budget, BudgetExhausted, checkpoint
from plansynth.reach.geometry import (
    Box,
    convex_pieces,  # (moved there: the lazy planner uses it too)
    halfspaces,
)
from plansynth.reach.highs import new_highs
from plansynth.reach.planners.options import BigMOptions
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["plan_milp_bigm", "convex_pieces", "horizon_schedule", "highs_version", "run", "BigMOptions"]


def highs_version() -> str:
    try:
        from importlib.metadata import version

        return version("highspy")
    except Exception:  # pragma: no cover
        return "unknown"


def horizon_schedule(problem: ReachProblem, growth: float = 1.5) -> list[int]:
    """Horizons to try: from a lower bound on the steps needed up to ``max_horizon``.

    The lower bound is the largest per-axis distance from the start position to the goal
    divided by the largest distance one step can cover (from the position rows of A, B
    and the state bounds when given; else 1).
    """
    start = problem.start_position
    if isinstance(problem.goal, Box):
        glo, ghi = np.array(problem.goal.lo), np.array(problem.goal.hi)
    else:
        v = np.array(problem.goal.vertices)
        glo, ghi = v.min(axis=0), v.max(axis=0)
    gap = float(np.max(np.maximum(0.0, np.maximum(glo - start, start - ghi))))
    per_step = _max_step_length(problem)
    n0 = max(1, math.ceil(gap / per_step - 1e-9)) if per_step > 0 else 1
    out = []
    n = n0
    while n < problem.max_horizon:
        out.append(n)
        n = max(n + 1, int(math.ceil(n * growth)))
    out.append(problem.max_horizon)
    return out


def _max_step_length(problem: ReachProblem) -> float:
    dyn = problem.dynamics
    if problem.state_bounds is None:
        return math.inf
    lo, hi = np.array(problem.state_bounds.lo), np.array(problem.state_bounds.hi)
    best = 0.0
    A, B = np.array(dyn.A), np.array(dyn.B)
    for i in dyn.position:
        row = A[i].copy()
        row[i] -= 1.0  # displacement of the coordinate in one step
        span = np.abs(row) * np.maximum(np.abs(lo), np.abs(hi))
        # position components are unbounded in the displacement sense only via other states
        span[list(dyn.position)] = 0.0 if np.allclose(row[list(dyn.position)], 0) else np.inf
        best = max(best, float(span.sum() + np.abs(B[i]).sum() * problem.input_bound))
    return best


@dataclass
class _Rows:
    lower: list[float]
    upper: list[float]
    starts: list[int]
    index: list[int]
    value: list[float]

    def add(self, lo: float, hi: float, coefs: dict[int, float]) -> None:
        self.lower.append(lo)
        self.upper.append(hi)
        self.starts.append(len(self.index))
        for k, v in coefs.items():
            if v != 0.0:
                self.index.append(k)
                self.value.append(v)


#: Positions keep this distance outside the obstacle pieces. It must exceed the MILP's
#: feasibility tolerance, and it excludes the shared edges of the pieces of a
#: non-convex obstacle (interior points of the obstacle that lie in no open piece).
MARGIN = 1e-4


def _solve_horizon(
    problem: ReachProblem,
    N: int,
    seconds: float,
    objective: str,
    margin: float = MARGIN,
    segment_safe: bool = True,
    pieces: list[tuple[np.ndarray, np.ndarray]] | None = None,
) -> tuple[str, Trajectory | None, dict[str, Any]]:
    import highspy

    deadline = time.perf_counter() + seconds  # building the model spends the budget too
    inf = highspy.kHighsInf
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.array(dyn.A), np.array(dyn.B)
    pos = list(dyn.position)
    d = len(pos)

    # columns: x_t (t=0..N), u_t (t=0..N-1), then binaries
    def xi(t: int, i: int) -> int:
        return t * n + i

    def ui(t: int, j: int) -> int:
        return (N + 1) * n + t * m + j

    n_cont = (N + 1) * n + N * m
    lb = np.full(n_cont, -inf)
    ub = np.full(n_cont, inf)
    lb[[xi(0, i) for i in range(n)]] = problem.start
    ub[[xi(0, i) for i in range(n)]] = problem.start
    for t in range(N):
        for j in range(m):
            lb[ui(t, j)] = -problem.input_bound
            ub[ui(t, j)] = problem.input_bound
    for t in range(N + 1):
        if problem.state_bounds is not None:
            for i in range(n):
                lb[xi(t, i)] = max(lb[xi(t, i)], problem.state_bounds.lo[i]) if t else lb[xi(t, i)]
                ub[xi(t, i)] = min(ub[xi(t, i)], problem.state_bounds.hi[i]) if t else ub[xi(t, i)]
        if t:
            for a, i in enumerate(pos):
                lb[xi(t, i)] = max(lb[xi(t, i)], problem.workspace.lo[a])
                ub[xi(t, i)] = min(ub[xi(t, i)], problem.workspace.hi[a])
    if problem.tube is not None:  # a tightened problem (plansynth.reach.robust): bounds tightened step by step
        x_lo, x_hi, u_lo, u_hi = problem.tube.bounds(*problem.state_box, problem.input_bound, N)
        lb[n : (N + 1) * n], ub[n : (N + 1) * n] = x_lo[1:].ravel(), x_hi[1:].ravel()
        lb[(N + 1) * n : n_cont], ub[(N + 1) * n : n_cont] = u_lo.ravel(), u_hi.ravel()
    rows = _Rows([], [], [], [], [])
    for t in range(N):
        for i in range(n):
            coefs = {xi(t + 1, i): 1.0}
            for k in range(n):
                if A[i, k]:
                    coefs[xi(t, k)] = coefs.get(xi(t, k), 0.0) - A[i, k]
            for j in range(m):
                if B[i, j]:
                    coefs[ui(t, j)] = coefs.get(ui(t, j), 0.0) - B[i, j]
            rows.add(0.0, 0.0, coefs)
    # goal
    Hg, hg = halfspaces(problem.goal)
    if problem.tube is not None:  # the final tube in the goal
        hg = hg - problem.tube.position_margins(Hg, problem.dynamics.position, N)[N]
    for r in range(Hg.shape[0]):
        rows.add(-inf, float(hg[r]), {xi(N, pos[a]): float(Hg[r, a]) for a in range(d)})
    # obstacles, big-M
    ws_lo, ws_hi = np.array(problem.workspace.lo), np.array(problem.workspace.hi)
    corners = np.array(np.meshgrid(*[[ws_lo[a], ws_hi[a]] for a in range(d)])).reshape(d, -1).T
    if pieces is None:
        pieces = [p for o in problem.obstacles for p in convex_pieces(o)]
    n_bin = 0
    bin_cols: list[int] = []
    # samples: one disjunction per position p_t (t >= 1); segments: one per segment
    # (p_t, p_{t+1}), whose chosen face must have both end points outside it, so the
    # whole segment avoids the (convex) piece.
    spans = [(t, t + 1) for t in range(N)] if segment_safe else [(t, t) for t in range(1, N + 1)]
    for a_t, b_t in spans:
        for H, h in pieces:
            choose: dict[int, float] = {}
            for r in range(H.shape[0]):
                checkpoint()  # a convex piece may have thousands of faces
                col = n_cont + n_bin
                n_bin += 1
                bin_cols.append(col)
                choose[col] = 1.0
                # H_r p >= h_r + margin - M (1 - z)  <=>  H_r p - M z >= h_r + margin - M
                M = max(0.0, float(np.max(h[r] + margin - corners @ H[r]))) + 1.0
                for t in sorted({a_t, b_t}):
                    coefs = {xi(t, pos[a]): float(H[r, a]) for a in range(d)}
                    coefs[col] = -M
                    rows.add(float(h[r]) + margin - M, inf, coefs)
            rows.add(1.0, inf, choose)
    h = new_highs()
    total = n_cont + n_bin
    all_lb = np.concatenate([lb, np.zeros(n_bin)])
    all_ub = np.concatenate([ub, np.ones(n_bin)])
    h.addVars(total, all_lb, all_ub)
    if n_bin:
        h.changeColsIntegrality(n_bin, np.array(bin_cols, dtype=np.int32), np.ones(n_bin, dtype=np.uint8))
    if objective == "l1" and N > 0:
        # |u| via auxiliary s >= u, s >= -u
        s0 = total
        h.addVars(N * m, np.zeros(N * m), np.full(N * m, inf))
        for t in range(N):
            for j in range(m):
                s = s0 + t * m + j
                rows.add(0.0, inf, {s: 1.0, ui(t, j): -1.0})
                rows.add(0.0, inf, {s: 1.0, ui(t, j): 1.0})
        h.changeColsCost(N * m, np.arange(s0, s0 + N * m, dtype=np.int32), np.ones(N * m))
    nrows = len(rows.lower)
    h.addRows(
        nrows,
        np.array(rows.lower),
        np.array(rows.upper),
        len(rows.index),
        np.array(rows.starts, dtype=np.int32),
        np.array(rows.index, dtype=np.int32),
        np.array(rows.value),
    )
    checkpoint()
    h.setOptionValue("time_limit", max(0.01, float(deadline - time.perf_counter())))
    h.run()
    status = h.getModelStatus()
    info = h.getInfo()
    stats = {
        "binaries": n_bin,
        "rows": nrows,
        "columns": total,
        "mip_nodes": int(getattr(info, "mip_node_count", 0) or 0),
    }
    S = highspy.HighsModelStatus
    has_sol = getattr(info, "primal_solution_status", 0) == 2
    if status == S.kOptimal or (has_sol and status in (S.kTimeLimit, S.kSolutionLimit, S.kInterrupt)):
        col = np.array(h.getSolution().col_value)
        X = col[: (N + 1) * n].reshape(N + 1, n)
        U = col[(N + 1) * n : n_cont].reshape(N, m)
        # Replay the inputs through the dynamics so that the states are exactly consistent.
        states = [np.array(problem.start, dtype=float)]
        for t in range(N):
            states.append(A @ states[-1] + B @ U[t])
        del X
        return "found", Trajectory(states=np.array(states), inputs=U.reshape(N, m)), stats
    if status == S.kInfeasible:
        return "infeasible", None, stats
    return "unknown", None, stats


def plan_milp_bigm(
    problem: ReachProblem,
    budget: Budget = Budget(seconds=60.0),
    *,
    horizon: int | None = None,
    objective: str = "feasibility",
    growth: float = 1.5,
    segment_safe: bool = True,
) -> Any:
    """Solve ``problem`` by one big-M MILP per horizon (HiGHS) within ``budget``.

    With ``horizon`` given, only that horizon is tried. The trajectory is not validated
    here (:func:`plansynth.reach.solve` validates every planner's). With
    ``segment_safe`` (default, as the lazy SMT planner) whole segments avoid the
    obstacles; otherwise only the sampled positions (the paper's semantics).
    """
    from plansynth.reach.result import ReachResult, ReachStatus

    if objective not in ("feasibility", "l1"):
        raise ValueError(f"objective must be 'feasibility' or 'l1', got {objective!r}")
    t0 = time.perf_counter()
    clock = budget.clock()
    horizons = [horizon] if horizon is not None else horizon_schedule(problem, growth)
    counters: dict[str, Any] = {"milp_calls": 0, "binaries": 0, "mip_nodes": 0, "horizons_infeasible": 0}
    timings: dict[str, float] = {"milp": 0.0}
    options = {
        "objective": objective,
        "growth": growth,
        "horizon": horizon,
        "segment_safe": segment_safe,
        "highs": highs_version(),
    }
    message = ""
    last = "unknown"
    pieces: list[tuple[np.ndarray, np.ndarray]] | None = None
    for N in horizons:
        if clock.exhausted():
            message = f"budget ran out before the MILP at horizon {N}"
            last = "unknown"
            break
        clock.tick()
        ts = time.perf_counter()
        remaining = clock.remaining()
        try:
            with clock.phase("building the MILP"):
                if pieces is None:  # the obstacles' convex pieces, once for every horizon
                    pieces = []
                    for o in problem.obstacles:
                        checkpoint()
                        pieces += convex_pieces(o)
                outcome, traj, stats = _solve_horizon(
                    problem,
                    N,
                    1e6 if math.isinf(remaining) else remaining,
                    objective,
                    segment_safe=segment_safe,
                    pieces=pieces,
                )
        except BudgetExhausted as exc:
            timings["milp"] += time.perf_counter() - ts
            message = f"{exc} at horizon {N}"
            last = "unknown"
            break
        timings["milp"] += time.perf_counter() - ts
        counters["milp_calls"] += 1
        counters["binaries"] = stats["binaries"]
        counters["mip_nodes"] += stats["mip_nodes"]
        counters["last_horizon"] = N
        last = outcome
        if outcome == "found" and traj is not None:  # validated by plansynth.reach.solve, like every planner's
            timings["total"] = time.perf_counter() - t0
            return ReachResult(
                status=ReachStatus.FOUND,
                solver="milp-bigm",
                seconds=timings["total"],
                trajectory=traj,
                regions=None,
                segment_safe=None,
                horizon=N,
                counters=counters,
                timings=timings,
                options=options,
                guarantee="segments" if segment_safe else "samples",
                message=f"found at horizon {N}",
            )
        if outcome == "infeasible":
            counters["horizons_infeasible"] += 1
            continue
        message = f"budget ran out in the MILP solver (HiGHS time limit) at horizon {N}"
        break
    else:
        if last == "infeasible":
            message = "no trajectory at any horizon tried (not a proof for the horizons in between)"
    timings["total"] = time.perf_counter() - t0
    return ReachResult(
        status=ReachStatus.UNKNOWN,
        solver="milp-bigm",
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
        message=message,
    )


def run(problem: ReachProblem, budget: Budget, options: BigMOptions, progress: Any = None) -> Any:
    """``milp-bigm`` as a planner of :func:`plansynth.reach.solve` (no progress: one
    MILP per horizon of :func:`horizon_schedule`)."""
    return plan_milp_bigm(
        problem,
        budget,
        horizon=options.horizon,
        objective=options.objective,
        growth=options.growth,
        segment_safe=options.segment_safe,
    )

"""The one-shot MILP over the same region graph: the cross-check oracle of the lazy
planner (and a baseline in the spirit of the paper's "LTL OPT" column, Section VI).

For a horizon N, one mixed-integer program with HiGHS decides region sequence and
trajectory together:

* binaries ``z[t, i]`` ("p_t in region i"), ``sum_i z[t, i] = 1``, start regions at
  t = 0, goal regions at t = N, and transitions ``z[t, i] <= sum_{j in N[i] + i}
  z[t+1, j]`` -- the constraints of DIS-PLAN (Section IV);
* the dynamics, input, state and workspace bounds of CON-PLAN (Section V);
* big-M region membership ``H_i p_t <= h_i + M_i (1 - z[t, i])`` with a per-row
  ``M_i`` (the row's largest violation over the workspace box, so the relaxation is as
  tight as a big-M can be), and with segment safety also ``H_i p_{t+1} <= ...``;
* ``H_goal p_N <= h_goal``.

Horizons are tried upwards from the region-graph distance (BFS), so the first horizon
with a solution is the shortest one -- the same quantity the lazy planner computes,
which makes the two comparable horizon by horizon. No solution at every horizon up to
``max_horizon`` is ``unknown`` (no plan through the abstraction, not a proof);
``infeasible`` needs the proved bound, as in the lazy planner. MIP tolerances let a big-M row slip by
``M * 1e-6``, so the trajectory is not taken from the MILP: its region sequence is
re-solved as an LP (the CON-PLAN feasibility LP) and only that trajectory is reported.

>>> from plansynth.reach.families import maze
>>> r = plan_milp(maze(1), options=MilpOptions(max_horizon=57, start_horizon=57))
>>> r.status.value, r.horizon
('found', 57)
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import highspy
import numpy as np

from plansynth.budget import Budget, BudgetExhausted, Clock, checkpoint
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.geometry import halfspaces
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.bounds import proved_horizon_bound, step_adjacency
from plansynth.reach.lazy.claims import DECOMPOSITION_ONLY, EXACT_SAMPLES
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.planners.options import MilpOptions
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = ["plan_milp", "solve_horizon", "MilpOptions"]

ProgressFn = Callable[[int, int], None]


def _big_m(H: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Per row, the largest ``H_row p - h_row`` over the box [lo, hi] (at least 0)."""
    return np.maximum(0.0, np.maximum(H * lo, H * hi).sum(axis=1) - h)


def solve_horizon(
    problem: ReachProblem,
    abstraction: Abstraction,
    N: int,
    *,
    segment_safe: bool = True,
    seconds: float = math.inf,
    adjacency: tuple[tuple[int, ...], ...] | None = None,
) -> tuple[str, tuple[int, ...] | None, dict]:
    """One MILP at horizon ``N``: ``("found", regions, stats)``, ``("infeasible", None,
    stats)`` or ``("unknown", None, stats)`` (time limit). ``seconds`` counts from the
    call: building the model spends it too (and checks it, see :mod:`plansynth.budget`).
    ``adjacency``: the transitions allowed (default: the decomposition's adjacency)."""
    deadline = time.perf_counter() + seconds
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = np.array(dyn.position)
    d = len(pos)
    R = len(abstraction.regions)
    graph = RegionGraph.from_abstraction(abstraction)
    if adjacency is not None:
        graph = RegionGraph(graph.n_regions, adjacency, graph.start_regions, graph.goal_regions)
    ws_lo, ws_hi = np.array(problem.workspace.lo), np.array(problem.workspace.hi)
    T = N + 1
    n_x, n_u, n_z = T * n, N * m, T * R
    n_col = n_x + n_u + n_z

    def x(t: int) -> int:
        return t * n

    def z(t: int, i: int) -> int:
        return n_x + n_u + t * R + i

    blocks = Rows(on_add=checkpoint)
    add = blocks.add

    # dynamics x_{t+1} - A x_t - B u_t = 0
    ai, aj = np.nonzero(A)
    bi, bj = np.nonzero(B)
    for t in range(N):
        add(
            np.concatenate([np.arange(n), ai, bi]),
            np.concatenate([x(t + 1) + np.arange(n), x(t) + aj, n_x + t * m + bj]),
            np.concatenate([np.ones(n), -A[ai, aj], -B[bi, bj]]),
            np.zeros(n),
            np.zeros(n),
        )
    # one region per step
    for t in range(T):
        add(np.zeros(R, dtype=np.int64), z(t, 0) + np.arange(R), np.ones(R), np.ones(1), np.ones(1))
    # transitions z[t,i] - sum_{j in N[i] + i} z[t+1,j] <= 0
    for t in range(N):
        for i in range(R):
            nb = (i, *graph.adjacency[i])
            add(
                np.zeros(1 + len(nb), dtype=np.int64),
                np.array([z(t, i)] + [z(t + 1, j) for j in nb]),
                np.array([1.0] + [-1.0] * len(nb)),
                np.full(1, -np.inf),
                np.zeros(1),
            )
    # big-M membership (and segments)
    for i, reg in enumerate(abstraction.regions):
        H, h = np.asarray(reg.H, float), np.asarray(reg.h, float)
        M = _big_m(H, h, ws_lo, ws_hi)
        k = H.shape[0]
        rr = np.concatenate([np.repeat(np.arange(k), d), np.arange(k)])
        for t in range(T):
            for state_t in (t, t + 1) if (segment_safe and t < N) else (t,):
                cc = np.concatenate([np.tile(x(state_t) + pos, k), np.full(k, z(t, i))])
                add(rr, cc, np.concatenate([H.ravel(), M]), np.full(k, -np.inf), h + M)
    # goal
    Hg, hg = (np.asarray(a, float) for a in halfspaces(problem.goal))
    kg = Hg.shape[0]
    if problem.tube is not None:  # a tightened problem (plansynth.reach.robust): the final tube in the goal
        hg = hg - problem.tube.position_margins(Hg, problem.dynamics.position, N)[N]
    add(np.repeat(np.arange(kg), d), np.tile(x(N) + pos, kg), Hg.ravel(), np.full(kg, -np.inf), hg)

    col_lo = np.full(n_col, -np.inf)
    col_hi = np.full(n_col, np.inf)
    s_lo, s_hi = problem.state_box
    col_lo[:n_x] = np.tile(s_lo, T)
    col_hi[:n_x] = np.tile(s_hi, T)
    col_lo[:n] = col_hi[:n] = problem.start
    col_lo[n_x : n_x + n_u] = -problem.input_bound
    col_hi[n_x : n_x + n_u] = problem.input_bound
    if problem.tube is not None:  # the bounds tightened step by step (plansynth.reach.tube)
        x_lo, x_hi, u_lo, u_hi = problem.tube.bounds(s_lo, s_hi, problem.input_bound, N)
        col_lo[n:n_x], col_hi[n:n_x] = x_lo[1:].ravel(), x_hi[1:].ravel()
        col_lo[n_x : n_x + n_u], col_hi[n_x : n_x + n_u] = u_lo.ravel(), u_hi.ravel()
    col_lo[n_x + n_u :] = 0.0
    col_hi[n_x + n_u :] = 1.0
    for i in range(R):
        if i not in abstraction.start_regions:
            col_hi[z(0, i)] = 0.0
        if i not in abstraction.goal_regions:
            col_hi[z(N, i)] = 0.0

    r0 = blocks.n_row
    lp = csc_lp(
        n_col,
        r0,
        *blocks.coo(),
        np.zeros(n_col),
        col_lo,
        col_hi,
        *blocks.bounds(),
        integrality=[highspy.HighsVarType.kContinuous] * (n_x + n_u) + [highspy.HighsVarType.kInteger] * n_z,
    )

    h = new_highs()
    h.passModel(lp)
    if math.isfinite(seconds):
        left = deadline - time.perf_counter()
        if left <= 0:
            return "unknown", None, {"binaries": n_z, "rows": r0, "mip_nodes": 0}
        h.setOptionValue("time_limit", max(1e-3, float(left)))
    h.run()
    status = h.getModelStatus()
    info = h.getInfo()
    stats = {"binaries": n_z, "rows": r0, "mip_nodes": int(info.mip_node_count)}
    S = highspy.HighsModelStatus
    if status == S.kOptimal:
        col = np.asarray(h.getSolution().col_value)
        zz = col[n_x + n_u :].reshape(T, R)
        return "found", tuple(int(i) for i in np.argmax(zz, axis=1)), stats
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return "infeasible", None, stats
    return "unknown", None, stats


def plan_milp(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: MilpOptions | None = None,
    progress: ProgressFn | None = None,
    *,
    abstraction: Abstraction | None = None,
) -> ReachResult:
    """MILPs at horizons ``options.start_horizon`` (default: the region-graph distance)
    up to ``options.max_horizon`` within ``budget``; the trajectory is not yet validated
    here. ``progress(N, iterations)`` is called before each horizon.

    Claims as the lazy planner's (:mod:`plansynth.reach.lazy.claims`):
    samples only, the transitions are every pair of regions one step can connect
    (:func:`~plansynth.reach.lazy.bounds.step_adjacency`), so with regions covering the
    free space no solution up to ``max_horizon`` is ``infeasible`` and the first horizon
    found is minimal for the problem. Segment-safe, the MILP decides plans whose
    consecutive samples share a region, so having no solution at every horizon from
    the BFS bound up to ``max_horizon`` is ``unknown`` with
    ``counters["abstraction_refuted"]`` (``infeasible`` only when
    :func:`~plansynth.reach.lazy.bounds.proved_horizon_bound` exceeds ``max_horizon``),
    and the horizon found is minimal through the decomposition
    (``counters["minimal_relative_to"]``) unless it is at most that bound."""
    opts = MilpOptions() if options is None else options
    segment_safe, start_horizon = opts.segment_safe, opts.start_horizon
    t_start = time.perf_counter()
    clock: Clock = budget.clock()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    timings = {"abstraction": 0.0, "milp": 0.0, "lp": 0.0}
    if abstraction is None:
        t0 = time.perf_counter()
        try:
            with clock.phase("the convex decomposition (abstraction)"):
                abstraction = abstract(problem)
        except BudgetExhausted as exc:
            timings["abstraction"] = time.perf_counter() - t0
            timings["total"] = time.perf_counter() - t_start
            return ReachResult(
                status=ReachStatus.UNKNOWN,
                solver="milp",
                seconds=timings["total"],
                timings=timings,
                options={"segment_safe": segment_safe},
                message=str(exc),
                guarantee="segments" if segment_safe else "samples",
            )
        timings["abstraction"] = time.perf_counter() - t0
    graph = RegionGraph.from_abstraction(abstraction)
    step = None if segment_safe else step_adjacency(problem, abstraction)  # samples only: exact (see lazy/claims.py)
    if step is not None:
        graph = RegionGraph(graph.n_regions, step, graph.start_regions, graph.goal_regions)
    exact = step is not None and abstraction.exact
    bfs = graph.horizon_lower_bound()
    first = int(bfs) if math.isfinite(bfs) else L_max + 1
    if start_horizon is not None:
        first = max(first, int(start_horizon))
    options = {
        "segment_safe": segment_safe,
        "max_horizon": L_max,
        "start_horizon": first,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
    counters: dict = {
        "regions": graph.n_regions,
        "milp_calls": 0,
        "mip_nodes": 0,
        "binaries": 0,
        "bfs_bound": None if math.isinf(bfs) else int(bfs),
    }
    guarantee = "segments" if segment_safe else "samples"

    def finish(status: ReachStatus, horizon: int | None, message: str, trajectory=None, regions=None) -> ReachResult:
        timings["total"] = time.perf_counter() - t_start
        counters["iterations"] = clock.iterations
        return ReachResult(
            status=status,
            solver="milp",
            seconds=timings["total"],
            trajectory=trajectory,
            regions=regions,
            horizon=horizon,
            counters=counters,
            timings=timings,
            options=options,
            message=message,
            guarantee=guarantee,
        )

    proved = proved_horizon_bound(problem, abstraction, L_max, segment_safe=segment_safe)
    counters["proved_bound"] = None if math.isinf(proved) else int(proved)
    not_proof = (
        (
            f"not a proof of infeasibility (a step may cross several regions; proved lower bound on the "
            f"horizon: {int(proved)})"
        )
        if math.isfinite(proved)
        else ""
    )
    if proved > L_max:
        why = (
            "no trajectory reaches the goal through the free space"
            if math.isinf(proved)
            else f"every trajectory needs at least {int(proved)} steps (bounded displacement through the free space)"
        )
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why}")
    if first > L_max and exact and (start_horizon is None or first == int(bfs)):
        return finish(
            ReachStatus.INFEASIBLE,
            L_max,
            f"infeasible up to horizon {L_max}: no region path of at most {L_max} steps ({EXACT_SAMPLES})",
        )
    if first > L_max:
        if math.isinf(bfs):
            counters["abstraction_refuted"] = L_max
            return finish(
                ReachStatus.UNKNOWN,
                L_max,
                f"no plan through the abstraction: the goal regions are not "
                f"connected to the start regions; {not_proof}",
            )
        if start_horizon is None or first == int(bfs):
            counters["abstraction_refuted"] = L_max
            return finish(
                ReachStatus.UNKNOWN,
                L_max,
                f"no plan through the abstraction up to horizon {L_max}: the "
                f"region-graph distance is {first}; {not_proof}",
            )
        return finish(ReachStatus.UNKNOWN, None, f"start horizon {first} exceeds max_horizon {L_max}")
    polish = ConPlan(problem, abstraction, segment_safe=segment_safe, counterexample="trivial", clock=clock)
    N = first
    try:
        with clock.phase("building the MILP"):
            for N in clock.steps(range(first, L_max + 1), progress=progress, what="the MILP at horizon"):
                t0 = time.perf_counter()
                outcome, regions, stats = solve_horizon(
                    problem, abstraction, N, segment_safe=segment_safe, seconds=clock.remaining(), adjacency=step
                )
                timings["milp"] += time.perf_counter() - t0
                counters["milp_calls"] += 1
                counters["mip_nodes"] += stats["mip_nodes"]
                counters["binaries"] = stats["binaries"]
                if outcome == "unknown":
                    return finish(
                        ReachStatus.UNKNOWN, N, f"budget ran out in the MILP solver (HiGHS time limit) at horizon {N}"
                    )
                if outcome == "found":
                    assert regions is not None
                    t0 = time.perf_counter()
                    trajectory = polish.feasible(regions)
                    timings["lp"] += time.perf_counter() - t0
                    if trajectory is None:
                        return finish(
                            ReachStatus.UNKNOWN,
                            N,
                            f"the MILP's region sequence at horizon {N} has no trajectory "
                            "under exact LP tolerances (numerically borderline instance)",
                            regions=regions,
                        )
                    message = f"found at horizon {N}"
                    if start_horizon is None or first == int(bfs):  # every shorter horizon refuted
                        relative = "problem" if (exact or N <= proved) else "decomposition"
                        counters.update(minimal=True, minimal_relative_to=relative)
                        if relative == "decomposition":
                            message += (
                                f"; minimal only among plans through the decomposition ({DECOMPOSITION_ONLY}), "
                                f"not proved for the problem (proved lower bound: {int(proved)})"
                            )
                    return finish(ReachStatus.FOUND, N, message, trajectory, regions)
            if start_horizon is not None and first > (int(bfs) if math.isfinite(bfs) else 0):
                return finish(
                    ReachStatus.UNKNOWN, L_max, f"no solution at horizons {first}..{L_max} (shorter ones not tried)"
                )
            if exact:
                return finish(
                    ReachStatus.INFEASIBLE,
                    L_max,
                    f"infeasible up to horizon {L_max}: no MILP solution at any horizon ({EXACT_SAMPLES})",
                )
            counters["abstraction_refuted"] = L_max
            return finish(
                ReachStatus.UNKNOWN,
                L_max,
                f"no MILP solution through the abstraction at any horizon up to {L_max}; {not_proof}",
            )
    except BudgetExhausted as exc:  # (the LP solver's too: the trajectory of the MILP's regions)
        return finish(ReachStatus.UNKNOWN, N, str(exc) if exc.phase.startswith("before") else f"{exc} at horizon {N}")

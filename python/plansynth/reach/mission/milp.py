"""The baseline: the bounded mission as one big-M MILP per horizon in HiGHS (Wolff,
Topcu and Murray, "Optimization-based trajectory generation with linear temporal
logic specifications", ICRA 2014), planner ``milp-ltl``.

For a horizon L, one mixed-integer program decides regions, loop and trajectory:

* binaries ``z[t, i]`` (p_t in region i of the label-refined decomposition), one per
  step, start regions at t = 0, transitions between equal or adjacent regions, and
  big-M membership ``H_i p_t <= h_i + M (1 - z[t, i])`` (segments: p_{t+1} too);
* the dynamics, input, state and workspace bounds;
* binaries for the successor of the last position (Wolff et al.'s loop variables):
  ``stay`` (a finite plan) or ``loop_j`` with ``|x_L - x_{j-1}| <= M (1 - loop_j)``;
* the mission in negation normal form as continuous [0, 1] variables P[f, t] with the
  linear inequalities of its recursive definition (P[a & b, t] <= P[a, t], P[a U b, t]
  <= P[b, t] + P[a, t], ... ; at t = L + 1 the values of the loop's target position),
  and Wolff et al.'s eventuality constraint for U/F: an until-formula true at L must
  have its right side true at a loop position. P[mission, 0] = 1.

Horizons are tried upwards from 0, as in the lazy planner; the first with a solution
is the shortest. As there, ``infeasible`` needs the proof of
:func:`~plansynth.reach.mission.proof.label_proof`; no solution at any horizon (one
region per step) is ``unknown``, not a proof. The trajectory is not taken from the MILP (big-M rows slip by the MIP
tolerances): its regions and loop are re-solved as an exact LP
(:class:`~plansynth.reach.mission.planner.LoopLP`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget
from plansynth.reach.lazy.bounds import time_windows
from plansynth.reach.highs import new_highs
from plansynth.reach.mission.ltl import And, Const, Finally, Formula, Globally, Next, Not, Or, Prop, Release, Until, nnf, parse, subformulas
from plansynth.reach.mission.labels import LabelledAbstraction, label_abstraction, planning_problem
from plansynth.reach.planners import OptionsPlanner, keyword_runner
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = ["plan_milp_ltl", "solve_mission_horizon"]


#: HiGHS drops matrix entries at most this small (its ``small_matrix_value``) and
#: answers such a row with a warning, which highspy raises; they are left out here.
SMALL_MATRIX_VALUE = 1e-9


def _big_m(H: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.maximum(0.0, np.maximum(H * lo, H * hi).sum(axis=1) - h)


def solve_mission_horizon(
    problem: ReachProblem, labelled: LabelledAbstraction, formula: Formula, L: int, *,
    segment_safe: bool = True, semantics: str = "any", earliest=None, seconds: float = math.inf,
) -> tuple[str, tuple[int, ...] | None, int | None, dict]:
    """One MILP at horizon L: ``(status, regions, loop_start, stats)`` with status
    ``found`` / ``infeasible`` / ``unknown`` (time limit)."""
    ab = labelled.abstraction
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = list(dyn.position)
    R = ab.n_regions
    h = new_highs()
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", max(1e-3, float(seconds)))
    inf = highspy.kHighsInf
    # not problem.state_box: a big-M needs finite bounds, so unbounded states get +-1e4
    slo = np.full(n, -1e4)
    shi = np.full(n, 1e4)
    if problem.state_bounds is not None:
        slo, shi = np.array(problem.state_bounds.lo, float), np.array(problem.state_bounds.hi, float)
    ws_lo, ws_hi = np.array(problem.workspace.lo, float), np.array(problem.workspace.hi, float)
    slo[pos] = np.maximum(slo[pos], ws_lo)
    shi[pos] = np.minimum(shi[pos], ws_hi)
    X = [[h.addVariable(lb=float(slo[i]), ub=float(shi[i])) for i in range(n)] for _ in range(L + 1)]
    U = [[h.addVariable(lb=-problem.input_bound, ub=problem.input_bound) for _ in range(m)] for _ in range(L)]
    Z = [[h.addBinary() for _ in range(R)] for _ in range(L + 1)]
    for i in range(n):
        h.addConstr(X[0][i] == float(problem.start[i]))
    for t in range(L):
        for i in range(n):
            h.addConstr(X[t + 1][i] - sum(float(A[i, j]) * X[t][j] for j in range(n) if A[i, j] != 0)
                        - sum(float(B[i, j]) * U[t][j] for j in range(m) if B[i, j] != 0) == 0.0)
    ear = earliest if earliest is not None else [0] * R
    for t in range(L + 1):
        h.addConstr(sum(Z[t]) == 1.0)
        for i in range(R):
            if (t == 0 and i not in ab.start_regions) or t < ear[i]:
                h.addConstr(Z[t][i] == 0.0)
        if t < L:
            for i in range(R):
                h.addConstr(Z[t][i] - sum(Z[t + 1][j] for j in (i, *ab.adjacency[i])) <= 0.0)
    for i, reg in enumerate(ab.regions):
        H, hh = np.asarray(reg.H, float), np.asarray(reg.h, float)
        M = _big_m(H, hh, ws_lo, ws_hi)
        for t in range(L + 1):
            for s in ((t, t + 1) if (segment_safe and t < L) else (t,)):
                for row, rhs, mm in zip(H, hh, M):
                    if mm <= SMALL_MATRIX_VALUE:
                        continue  # the row holds everywhere in the workspace (up to HiGHS's tolerance)
                    h.addConstr(sum(float(row[k]) * X[s][pos[k]] for k in range(len(pos))
                                    if abs(row[k]) > SMALL_MATRIX_VALUE)
                                + float(mm) * Z[t][i] <= float(rhs + mm))
    # the successor of the last position: stay (finite) or loop_j (x_L = x_{j-1})
    sels: list[tuple[Any, int, bool]] = []
    if semantics in ("any", "finite"):
        sels.append((h.addBinary(), L, False))
    if semantics in ("any", "lasso"):
        sels += [(h.addBinary(), j, True) for j in range(1, L + 1)]
    h.addConstr(sum(s for s, _, _ in sels) == 1.0)
    for s, j, is_loop in sels:
        if not is_loop:
            continue
        for i in range(n):
            Mx = float(shi[i] - slo[i])
            h.addConstr(X[L][i] - X[j - 1][i] + Mx * s <= Mx)
            h.addConstr(X[j - 1][i] - X[L][i] + Mx * s <= Mx)
        for i in range(R):
            h.addConstr(Z[L][i] - Z[j - 1][i] + s <= 1.0)
    # the mission
    f = nnf(formula)
    subs = [g for g in subformulas(f) if not isinstance(g, Const)]
    P = {(g, t): h.addVariable(lb=0.0, ub=1.0) for g in subs for t in range(L + 2)}

    def val(g: Formula, t: int):
        if isinstance(g, Const):
            return 1.0 if g.value else 0.0
        return P[g, t]

    for t in range(L + 1):
        for g in subs:
            v = P[g, t]
            if isinstance(g, Prop):
                h.addConstr(v - sum(Z[t][r] for r in range(R) if g.name in labelled.labels_of[r]) <= 0.0)
            elif isinstance(g, Not):
                h.addConstr(v - sum(Z[t][r] for r in range(R) if g.arg.name not in labelled.labels_of[r]) <= 0.0)
            elif isinstance(g, And):
                h.addConstr(v - val(g.left, t) <= 0.0)
                h.addConstr(v - val(g.right, t) <= 0.0)
            elif isinstance(g, Or):
                h.addConstr(v - val(g.left, t) - val(g.right, t) <= 0.0)
            elif isinstance(g, Next):
                h.addConstr(v - val(g.arg, t + 1) <= 0.0)
            elif isinstance(g, (Finally, Until)):
                a = Const(True) if isinstance(g, Finally) else g.left
                b = g.arg if isinstance(g, Finally) else g.right
                h.addConstr(v - val(b, t) - val(a, t) <= 0.0)
                h.addConstr(v - val(b, t) - P[g, t + 1] <= 0.0)
            elif isinstance(g, (Globally, Release)):
                a = Const(False) if isinstance(g, Globally) else g.left
                b = g.arg if isinstance(g, Globally) else g.right
                h.addConstr(v - val(b, t) <= 0.0)
                h.addConstr(v - val(a, t) - P[g, t + 1] <= 0.0)
    # position L + 1 takes the values of the selected successor (one-sided, as P <= ...)
    for s, j, _ in sels:
        for g in subs:
            h.addConstr(P[g, L + 1] - P[g, j] + s <= 1.0)
    # eventualities: an until true at L has its right side true at a loop position
    inloop = [h.addVariable(lb=0.0, ub=1.0) for _ in range(L + 1)]
    for i in range(L + 1):
        h.addConstr(inloop[i] - (inloop[i - 1] if i > 0 else 0.0) - sum(s for s, j, _ in sels if j == i) <= 0.0)
    for g in subs:
        if isinstance(g, (Finally, Until)):
            b = g.arg if isinstance(g, Finally) else g.right
            w = [h.addVariable(lb=0.0, ub=1.0) for _ in range(L + 1)]
            for i in range(L + 1):
                h.addConstr(w[i] - inloop[i] <= 0.0)
                h.addConstr(w[i] - val(b, i) <= 0.0)
            h.addConstr(P[g, L] - sum(w) <= 0.0)
    if isinstance(f, Const) and not f.value:
        return "infeasible", None, None, {"binaries": 0, "mip_nodes": 0}
    if not isinstance(f, Const):
        h.addConstr(P[f, 0] >= 1.0)
    t0 = time.perf_counter()
    h.run()
    status = h.getModelStatus()
    S = highspy.HighsModelStatus
    stats = {"binaries": (L + 1) * R + len(sels), "mip_nodes": int(h.getInfo().mip_node_count),
             "solve_seconds": time.perf_counter() - t0}
    if status == S.kOptimal:
        col = np.asarray(h.getSolution().col_value)
        regions = tuple(int(np.argmax([col[z.index] for z in Z[t]])) for t in range(L + 1))
        chosen = max(sels, key=lambda sj: col[sj[0].index])
        return "found", regions, (chosen[1] - 1 if chosen[2] else None), stats
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return "infeasible", None, None, stats
    return "unknown", None, None, stats


def plan_milp_ltl(
    problem: ReachProblem,
    budget: Budget = Budget(),
    *,
    labelled: LabelledAbstraction | None = None,
    max_horizon: int | None = None,
    semantics: str = "any",
    segment_safe: bool = True,
    lower_bound: bool = True,
    progress: Callable[[int, int], None] | None = None,
) -> ReachResult:
    """MILPs at horizons 0..max_horizon within ``budget`` (not yet validated)."""
    from plansynth.reach.mission.planner import LoopLP

    if problem.mission is None:
        raise ValueError("milp-ltl plans missions; this problem has none")
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if max_horizon is None else int(max_horizon)
    timings = {"abstraction": 0.0, "bounds": 0.0, "milp": 0.0, "lp": 0.0}
    if labelled is None:
        t0 = time.perf_counter()
        labelled = label_abstraction(problem)
        timings["abstraction"] = time.perf_counter() - t0
    pp = planning_problem(problem)
    t0 = time.perf_counter()
    earliest = time_windows(pp, labelled.abstraction, L_max).earliest if lower_bound else None
    timings["bounds"] = time.perf_counter() - t0
    formula = parse(problem.mission)
    polish = LoopLP(pp, labelled.abstraction, segment_safe=segment_safe)
    options = {"semantics": semantics, "segment_safe": segment_safe, "max_horizon": L_max, "lower_bound": lower_bound,
               "budget": {"seconds": budget.seconds, "iterations": budget.iterations}}
    counters: dict[str, Any] = {"regions": labelled.n_regions, "milp_calls": 0, "mip_nodes": 0, "binaries": 0}

    def finish(status, horizon, message, traj=None, regions=None, loop_start=None) -> ReachResult:
        timings["total"] = time.perf_counter() - t_start
        counters["iterations"] = clock.iterations
        mission = {"formula": problem.mission, "semantics": None if regions is None else ("finite" if loop_start is None else "lasso"),
                   "loop_start": loop_start}
        return ReachResult(status=status, planner="milp-ltl", seconds=timings["total"], trajectory=traj, regions=regions,
                           horizon=horizon, counters=counters, timings=timings, options=options, message=message,
                           guarantee="segments" if segment_safe else "samples", mission=mission)

    from plansynth.reach.mission.planner import NOT_A_PROOF
    from plansynth.reach.mission.proof import label_proof

    t0 = time.perf_counter()
    proved, why = label_proof(problem, labelled)
    timings["proof"] = time.perf_counter() - t0
    counters["label_proof"] = proved
    if proved:
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    for L in range(0, L_max + 1):
        if progress is not None:
            progress(L, clock.iterations)
        if clock.exhausted():
            return finish(ReachStatus.UNKNOWN, L, f"budget ran out at horizon {L}")
        clock.tick()
        t0 = time.perf_counter()
        status, regions, loop_start, stats = solve_mission_horizon(
            pp, labelled, formula, L, segment_safe=segment_safe, semantics=semantics, earliest=earliest,
            seconds=clock.remaining())
        timings["milp"] += time.perf_counter() - t0
        timings["milp_solve"] = timings.get("milp_solve", 0.0) + stats.get("solve_seconds", 0.0)
        counters["milp_calls"] += 1
        counters["mip_nodes"] += stats.get("mip_nodes", 0)
        counters["binaries"] = stats.get("binaries", 0)
        if status == "unknown":
            return finish(ReachStatus.UNKNOWN, L, f"HiGHS stopped without an answer at horizon {L} (time limit)")
        if status == "found":
            t0 = time.perf_counter()
            traj = polish.solve(regions, loop_start)
            timings["lp"] += time.perf_counter() - t0
            if traj is None:
                return finish(ReachStatus.UNKNOWN, L, f"the MILP's regions at horizon {L} have no trajectory under exact "
                              "LP tolerances (numerically borderline)", regions=regions, loop_start=loop_start)
            return finish(ReachStatus.FOUND, L, f"found at horizon {L}", traj, regions, loop_start)
    counters["abstraction_refuted"] = L_max  # one region per step: no proof (see plan_mission)
    return finish(ReachStatus.UNKNOWN, L_max, f"no MILP solution through the label-refined abstraction at any "
                  f"horizon up to {L_max}; {NOT_A_PROOF} ({why})")


@dataclass(frozen=True)
class MilpLtlOptions:
    """The options of the mission MILP (see :func:`plan_milp_ltl`)."""

    max_horizon: int | None = None
    semantics: str = "any"
    segment_safe: bool = True
    lower_bound: bool = True


#: ``milp-ltl`` as a planner of :func:`plansynth.reach.solve` (missions only)
MILP_LTL = OptionsPlanner("milp-ltl", MilpLtlOptions(), keyword_runner(plan_milp_ltl, progress=True), "highspy")

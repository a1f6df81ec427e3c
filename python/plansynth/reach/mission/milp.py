"""The baseline: the bounded mission as one big-M MILP per horizon in HiGHS (Wolff,
Topcu and Murray, "Optimization-based trajectory generation with linear temporal
logic specifications", ICRA 2014), planner ``milp-ltl``.

For a horizon L, one mixed-integer program decides regions, loop and trajectory:

* binaries ``z[t, i]`` (p_t in region i of the label-refined decomposition), one per
  step, start regions at t = 0, transitions between equal or adjacent regions, and
  big-M membership ``H_i p_t <= h_i + M (1 - z[t, i])`` (segments: p_{t+1} too);
* the dynamics, input, state and workspace bounds;
* binaries for the successor of the last position (Wolff et al.'s loop variables):
  ``stay`` (a finite plan, which must end at rest: ``|(A - I) x_L + B u| <= M (1 - stay)``
  for an admissible u) or ``loop_j`` with ``|x_L - x_{j-1}| <= M (1 - loop_j)``;
* the mission in negation normal form as continuous [0, 1] variables P[f, t] with the
  linear inequalities of its recursive definition (P[a & b, t] <= P[a, t], P[a U b, t]
  <= P[b, t] + P[a, t], ... ; at t = L + 1 the values of the loop's target position),
  and Wolff et al.'s eventuality constraint for U/F: an until-formula true at L must
  have its right side true at a loop position. P[mission, 0] = 1.

The model of a horizon (:func:`mission_milp`) is assembled in array operations (row
blocks in COO form, :class:`~plansynth.reach.highs.Rows` and
:func:`~plansynth.reach.highs.csc_lp`, as for the reach MILP) and passed to HiGHS in one
``passModel``, so the baseline's time is HiGHS's branch and bound plus a build about as
long as the solve; tests/reach/test_mission_milp.py checks that it is the model a
term-by-term build gives (the same columns, rows, bounds and objective).

``milp-ltl-oneshot`` (``one_shot=True``) is Wolff et al.'s setting as published: one MILP
at the fixed horizon K = ``max_horizon``, whose plan has exactly K steps (any plan of the
bounded mission, not the shortest); a MILP without a solution there proves nothing about
shorter horizons (a shorter finite plan need not extend to K steps), so it is ``unknown``
unless the label proof below decides. Otherwise
horizons are tried upwards from the proved lower bound of
:func:`~plansynth.reach.mission.horizon.horizon_lower_bound` (``horizon_bound``; from 0
without it), as in the lazy planner; the first with a solution is the shortest. As there, ``infeasible`` needs the proof of
:func:`~plansynth.reach.mission.proof.label_proof`; no solution at any horizon (one
region per step) is ``unknown``, not a proof. The trajectory is not taken from the MILP (big-M rows slip by the MIP
tolerances): its regions and loop are re-solved as an exact LP
(:class:`~plansynth.reach.mission.looplp.LoopLP`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget, BudgetExhausted
from plansynth.errors import InvalidOption
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.bounds import time_windows
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.mission.horizon import timed_horizon_bound
from plansynth.reach.mission.labels import LabelledAbstraction, label_abstraction, planning_problem
from plansynth.reach.mission.looplp import LoopLP
from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    nnf,
    parse,
    subformulas,
)
from plansynth.reach.mission.options import MilpLtlOptions
from plansynth.reach.mission.proof import NOT_A_PROOF, timed_label_proof
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = ["MissionMilp", "mission_milp", "plan_milp_ltl", "solve_mission_horizon", "MilpLtlOptions"]


#: HiGHS drops matrix entries at most this small (its ``small_matrix_value``) and
#: answers such a row with a warning, which highspy raises; they are left out here.
SMALL_MATRIX_VALUE = 1e-9


def _big_m(H: np.ndarray, h: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.maximum(0.0, np.maximum(H * lo, H * hi).sum(axis=1) - h)


@dataclass(frozen=True)
class MissionMilp:
    """The mission MILP of one horizon as a HiGHS model: ``lp`` (with its integrality),
    the first column of the region binaries ``z[t, i]`` (column ``z0 + t R + i``) and the
    loop selectors ``(column, j, is_loop)`` (``stay`` has j = L)."""

    lp: highspy.HighsLp
    n_regions: int
    z0: int
    sels: tuple[tuple[int, int, bool], ...]


class _Model:
    """Columns and row blocks of a MILP in COO form (the assembly of
    :func:`~plansynth.reach.highs.csc_lp`): each ``rows`` call appends one block."""

    def __init__(self) -> None:
        self.lo: list[np.ndarray] = []
        self.hi: list[np.ndarray] = []
        self.n_col = 0
        self.rows = Rows()

    def cols(self, k: int, lo, hi) -> np.ndarray:
        first = self.n_col
        self.lo.append(np.broadcast_to(np.asarray(lo, float), (k,)))
        self.hi.append(np.broadcast_to(np.asarray(hi, float), (k,)))
        self.n_col += k
        return np.arange(first, first + k)

    def terms(self, terms: list[tuple[list[int], list[float], float]], sense: str) -> None:
        """Rows ``sum(c x) <sense> rhs`` for ``(cols, coefs, rhs)`` in ``terms``, sense
        one of ``<=``, ``==``, ``>=``."""
        if not terms:
            return
        r = np.repeat(np.arange(len(terms)), [len(c) for c, _, _ in terms])
        c = np.fromiter((j for cs, _, _ in terms for j in cs), np.int64, len(r))
        v = np.fromiter((x for _, vs, _ in terms for x in vs), float, len(r))
        rhs = np.array([b for _, _, b in terms], float)
        self.block(r, c, v, rhs, sense)

    def block(self, r, c, v, rhs, sense: str) -> None:
        inf = np.full(len(rhs), np.inf)
        lo, hi = {"<=": (-inf, rhs), "==": (rhs, rhs), ">=": (rhs, inf)}[sense]
        self.rows.add(r, c, v, lo, hi)

    def lp(self, integer: np.ndarray) -> highspy.HighsLp:
        R, C, V = self.rows.coo()
        # a column repeated in a row (P[a | a, t] <= P[a, t] + P[a, t]) is one entry
        key, inv = np.unique(R * self.n_col + C, return_inverse=True)
        V = np.bincount(inv.ravel(), weights=V, minlength=len(key))
        keep = V != 0.0
        R, C, V = (key // self.n_col)[keep], (key % self.n_col)[keep], V[keep]
        row_lo, row_hi = self.rows.bounds()
        integrality = np.full(self.n_col, highspy.HighsVarType.kContinuous)
        integrality[integer] = highspy.HighsVarType.kInteger
        return csc_lp(
            self.n_col,
            self.rows.n_row,
            R,
            C,
            V,
            np.zeros(self.n_col),
            np.concatenate(self.lo),
            np.concatenate(self.hi),
            row_lo,
            row_hi,
            integrality=list(integrality),
        )


def mission_milp(
    problem: ReachProblem,
    labelled: LabelledAbstraction,
    formula: Formula,
    L: int,
    *,
    segment_safe: bool = True,
    semantics: str = "any",
    earliest=None,
) -> MissionMilp | None:
    """The mission MILP at horizon L (the model the module docstring describes),
    assembled in array operations and passed to HiGHS whole; ``None`` when the mission
    is ``false`` (no model can hold it)."""
    f = nnf(formula)
    if isinstance(f, Const) and not f.value:
        return None
    ab = labelled.abstraction
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = np.array(dyn.position)
    R = ab.n_regions
    # not problem.state_box: a big-M needs finite bounds, so unbounded states get +-1e4
    slo = np.full(n, -1e4)
    shi = np.full(n, 1e4)
    if problem.state_bounds is not None:
        slo, shi = np.array(problem.state_bounds.lo, float), np.array(problem.state_bounds.hi, float)
    ws_lo, ws_hi = np.array(problem.workspace.lo, float), np.array(problem.workspace.hi, float)
    slo[pos] = np.maximum(slo[pos], ws_lo)
    shi[pos] = np.minimum(shi[pos], ws_hi)
    mdl = _Model()
    X = mdl.cols((L + 1) * n, np.tile(slo, L + 1), np.tile(shi, L + 1)).reshape(L + 1, n)
    U = mdl.cols(L * m, -problem.input_bound, problem.input_bound).reshape(L, m)
    Z = mdl.cols((L + 1) * R, 0.0, 1.0).reshape(L + 1, R)
    ones = lambda k: np.ones(k)  # noqa: E731
    # the start, the dynamics x_{t+1} - A x_t - B u_t = 0
    mdl.block(np.arange(n), X[0], ones(n), np.asarray(problem.start, float), "==")
    ai, aj = np.nonzero(A)
    bi, bj = np.nonzero(B)
    for t in range(L):
        mdl.block(
            np.concatenate([np.arange(n), ai, bi]),
            np.concatenate([X[t + 1], X[t][aj], U[t][bj]]),
            np.concatenate([ones(n), -A[ai, aj], -B[bi, bj]]),
            np.zeros(n),
            "==",
        )
    # one region per step, start regions, time windows, transitions to equal or adjacent regions
    ear = np.asarray(earliest if earliest is not None else [0] * R)
    nbrs = [np.array((i, *ab.adjacency[i])) for i in range(R)]
    tr_r = np.concatenate([np.full(len(nb), i) for i, nb in enumerate(nbrs)]) if R else np.zeros(0, int)
    tr_j = np.concatenate(nbrs) if R else np.zeros(0, int)
    starts = set(ab.start_regions)
    T = np.arange(L + 1)
    mdl.block(np.repeat(T, R), Z.ravel(), ones(Z.size), np.ones(L + 1), "==")
    off = (T[:, None] < ear[None, :]) | ((T[:, None] == 0) & ~np.isin(np.arange(R), list(starts))[None, :])
    mdl.block(np.arange(int(off.sum())), Z[off], ones(int(off.sum())), np.zeros(int(off.sum())), "==")
    # z[t, i] <= sum of z[t + 1, j] over j equal or adjacent to i: row t R + i
    Tl = np.arange(L)
    mdl.block(
        np.concatenate([Z[:L].ravel() - Z[0, 0], (Tl[:, None] * R + tr_r[None, :]).ravel()]),
        np.concatenate([Z[:L].ravel(), Z[1:][:, tr_j].ravel()]),
        np.concatenate([ones(L * R), -ones(L * len(tr_j))]),
        np.zeros(L * R),
        "<=",
    )
    # big-M membership H_i p_s + M z[t, i] <= h_i + M for s = t (and t + 1: segments)
    pairs = (
        [t for t in range(L + 1) for _ in ((t, t + 1) if (segment_safe and t < L) else (t,))],
        [s for t in range(L + 1) for s in ((t, t + 1) if (segment_safe and t < L) else (t,))],
    )
    for i, reg in enumerate(ab.regions):
        H, hh = np.asarray(reg.H, float), np.asarray(reg.h, float)
        M = _big_m(H, hh, ws_lo, ws_hi)
        live = M > SMALL_MATRIX_VALUE  # other rows hold everywhere in the workspace (up to HiGHS's tolerance)
        H, hh, M = H[live], hh[live], M[live]
        rk, kk = np.nonzero(np.abs(H) > SMALL_MATRIX_VALUE)
        k_rows = len(hh)
        # one block for every (t, s): row q k_rows + j is row j of the pair q
        q_t, q_s = np.array(pairs[0]), np.array(pairs[1])
        q = np.arange(len(q_t))
        mdl.block(
            np.concatenate([(q[:, None] * k_rows + rk).ravel(), (q[:, None] * k_rows + np.arange(k_rows)).ravel()]),
            np.concatenate([X[q_s][:, pos[kk]].ravel(), np.repeat(Z[q_t, i], k_rows)]),
            np.concatenate([np.tile(H[rk, kk], len(q)), np.tile(M, len(q))]),
            np.tile(hh + M, len(q)),
            "<=",
        )
    # the successor of the last position: stay (finite) or loop_j (x_L = x_{j-1})
    sel_j: list[tuple[int, bool]] = []
    if semantics in ("any", "finite"):
        sel_j.append((L, False))
    if semantics in ("any", "lasso"):
        sel_j += [(j, True) for j in range(1, L + 1)]
    S = mdl.cols(len(sel_j), 0.0, 1.0)
    sels = tuple((int(s), j, lp) for s, (j, lp) in zip(S, sel_j))
    mdl.block(np.zeros(len(S), int), S, ones(len(S)), np.ones(1), "==")
    Mx = shi - slo
    AI = A - np.eye(n)
    for s, j, is_loop in sels:
        if not is_loop:
            # stay: the robot rests at x_L, (A - I) x_L + B u = 0 for an admissible u (the
            # finite reading), each row within +-Mr (1 - stay) of 0
            u_rest = mdl.cols(m, -problem.input_bound, problem.input_bound)
            Mr = np.abs(AI) @ np.maximum(np.abs(slo), np.abs(shi)) + np.abs(B).sum(axis=1) * problem.input_bound
            ri, rj = np.nonzero(AI)
            qi, qj = np.nonzero(B)
            for sign in (1.0, -1.0):
                mdl.block(
                    np.concatenate([ri, qi, np.arange(n)]),
                    np.concatenate([X[L][rj], u_rest[qj], np.full(n, s)]),
                    np.concatenate([sign * AI[ri, rj], sign * B[qi, qj], Mr]),
                    Mr,
                    "<=",
                )
            continue
        rr = np.arange(n)
        for sign in (1.0, -1.0):
            mdl.block(
                np.concatenate([rr, rr, rr]),
                np.concatenate([X[L], X[j - 1], np.full(n, s)]),
                np.concatenate([np.full(n, sign), np.full(n, -sign), Mx]),
                Mx,
                "<=",
            )
        rr = np.arange(R)
        mdl.block(
            np.concatenate([rr, rr, rr]),
            np.concatenate([Z[L], Z[j - 1], np.full(R, s)]),
            np.concatenate([ones(R), -ones(R), ones(R)]),
            np.ones(R),
            "<=",
        )
    # the mission: P[g, t] in [0, 1] for t = 0..L + 1, rows (cols, coefs, rhs) of "<= rhs"
    subs = [g for g in subformulas(f) if not isinstance(g, Const)]
    P0 = mdl.cols(len(subs) * (L + 2), 0.0, 1.0)
    index = {g: k for k, g in enumerate(subs)}

    def P(g: Formula, t: int) -> int:
        return int(P0[index[g] * (L + 2) + t])

    rows: list[tuple[list[int], list[float], float]] = []

    def le(v: int, terms: list[Formula | int], t: int | None = None, rhs: float = 0.0) -> None:
        """v - sum(terms) <= rhs; a formula term is P[., t], a Const moves to the rhs."""
        cs, vs = [v], [1.0]
        for g in terms:
            if isinstance(g, Const):
                rhs += 1.0 if g.value else 0.0
            else:
                cs.append(int(g) if isinstance(g, (int, np.integer)) else P(g, t))
                vs.append(-1.0)
        rows.append((cs, vs, rhs))

    with_label = {g: [int(r) for r in range(R) if g.name in labelled.labels_of[r]] for g in subs if isinstance(g, Prop)}
    for t in range(L + 1):
        zt = [int(z) for z in Z[t]]
        for g in subs:
            v = P(g, t)
            if isinstance(g, Prop):
                le(v, [zt[r] for r in with_label[g]])
            elif isinstance(g, Not):
                le(v, [zt[r] for r in range(R) if g.arg.name not in labelled.labels_of[r]])
            elif isinstance(g, And):
                le(v, [g.left], t)
                le(v, [g.right], t)
            elif isinstance(g, Or):
                le(v, [g.left, g.right], t)
            elif isinstance(g, Next):
                le(v, [g.arg], t + 1)
            elif isinstance(g, (Finally, Until)):
                a = Const(True) if isinstance(g, Finally) else g.left
                b = g.arg if isinstance(g, Finally) else g.right
                le(v, [b, a], t)
                rows.append(_minus(v, b, t, P(g, t + 1), P))
            elif isinstance(g, (Globally, Release)):
                a = Const(False) if isinstance(g, Globally) else g.left
                b = g.arg if isinstance(g, Globally) else g.right
                le(v, [b], t)
                rows.append(_minus(v, a, t, P(g, t + 1), P))
    # position L + 1 takes the values of the selected successor (one-sided, as P <= ...)
    for s, j, _ in sels:
        for g in subs:
            rows.append(([P(g, L + 1), P(g, j), s], [1.0, -1.0, 1.0], 1.0))
    # eventualities: an until true at L has its right side true at a loop position
    inloop = [int(c) for c in mdl.cols(L + 1, 0.0, 1.0)]
    for i in range(L + 1):
        cs = [inloop[i]] + ([inloop[i - 1]] if i > 0 else []) + [s for s, j, _ in sels if j == i]
        rows.append((cs, [1.0] + [-1.0] * (len(cs) - 1), 0.0))
    for g in subs:
        if isinstance(g, (Finally, Until)):
            b = g.arg if isinstance(g, Finally) else g.right
            w = [int(c) for c in mdl.cols(L + 1, 0.0, 1.0)]
            for i in range(L + 1):
                rows.append(([w[i], inloop[i]], [1.0, -1.0], 0.0))
                le(w[i], [b], i)
            rows.append(([P(g, L)] + w, [1.0] + [-1.0] * len(w), 0.0))
    mdl.terms(rows, "<=")
    if not isinstance(f, Const):
        mdl.block(np.zeros(1, int), np.array([P(f, 0)]), np.ones(1), np.ones(1), ">=")
    integer = np.concatenate([Z.ravel(), S])
    return MissionMilp(mdl.lp(integer), R, (L + 1) * n + L * m, sels)


def _minus(v: int, a: Formula, t: int, nxt: int, P) -> tuple[list[int], list[float], float]:
    """The row v - a[t] - nxt <= 0 (a Const moves to the right-hand side)."""
    if isinstance(a, Const):
        return [v, nxt], [1.0, -1.0], 1.0 if a.value else 0.0
    return [v, P(a, t), nxt], [1.0, -1.0, -1.0], 0.0


def solve_mission_horizon(
    problem: ReachProblem,
    labelled: LabelledAbstraction,
    formula: Formula,
    L: int,
    *,
    segment_safe: bool = True,
    semantics: str = "any",
    earliest=None,
    seconds: float = math.inf,
) -> tuple[str, tuple[int, ...] | None, int | None, dict]:
    """One MILP at horizon L (:func:`mission_milp`): ``(status, regions, loop_start,
    stats)`` with status ``found`` / ``infeasible`` / ``unknown`` (time limit)."""
    t0 = time.perf_counter()
    model = mission_milp(
        problem, labelled, formula, L, segment_safe=segment_safe, semantics=semantics, earliest=earliest
    )
    if model is None:
        return "infeasible", None, None, {"binaries": 0, "mip_nodes": 0, "build_seconds": time.perf_counter() - t0}
    h = new_highs()
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", max(1e-3, float(seconds)))
    h.passModel(model.lp)
    build = time.perf_counter() - t0
    t0 = time.perf_counter()
    h.run()
    status = h.getModelStatus()
    S = highspy.HighsModelStatus
    R = model.n_regions
    stats = {
        "binaries": (L + 1) * R + len(model.sels),
        "mip_nodes": int(h.getInfo().mip_node_count),
        "solve_seconds": time.perf_counter() - t0,
        "build_seconds": build,
    }
    if status == S.kOptimal:
        col = np.asarray(h.getSolution().col_value)
        z = col[model.z0 : model.z0 + (L + 1) * R].reshape(L + 1, R)
        regions = tuple(int(r) for r in np.argmax(z, axis=1))
        chosen = max(model.sels, key=lambda sj: col[sj[0]])
        return "found", regions, (chosen[1] - 1 if chosen[2] else None), stats
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return "infeasible", None, None, stats
    return "unknown", None, None, stats


def plan_milp_ltl(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: MilpLtlOptions | None = None,
    progress: Callable[[int, int], None] | None = None,
    *,
    labelled: LabelledAbstraction | None = None,
) -> ReachResult:
    """MILPs at horizons 0..max_horizon within ``budget`` (not yet validated:
    :func:`plansynth.reach.solve` does that, with the mission checker); ``options``
    (:class:`~plansynth.reach.mission.options.MilpLtlOptions`): ``horizon_bound``: from
    the proved lower bound of :func:`~plansynth.reach.mission.horizon.horizon_lower_bound`
    on, as the lazy planner; ``one_shot``: one MILP at ``max_horizon`` only (Wolff et
    al.'s fixed horizon; see the module doc), planner ``milp-ltl-oneshot``."""
    opts = MilpLtlOptions() if options is None else options
    one_shot, segment_safe = opts.one_shot, opts.segment_safe
    name = "milp-ltl-oneshot" if one_shot else "milp-ltl"
    if problem.mission is None:
        raise InvalidOption(
            name, "planner", "plans LTL missions, and this problem has none (plan it with a reach-avoid planner)"
        )
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    timings = {"abstraction": 0.0, "bounds": 0.0, "milp": 0.0, "lp": 0.0}
    if labelled is None:
        t0 = time.perf_counter()
        labelled = label_abstraction(problem)
        timings["abstraction"] = time.perf_counter() - t0
    pp = planning_problem(problem)
    t0 = time.perf_counter()
    earliest = time_windows(pp, labelled.abstraction, L_max).earliest if opts.lower_bound else None
    timings["bounds"] = time.perf_counter() - t0
    formula = parse(problem.mission)
    polish = LoopLP(pp, labelled.abstraction, segment_safe=segment_safe)
    record = {
        **asdict(opts),
        "max_horizon": L_max,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
    counters: dict[str, Any] = {"regions": labelled.n_regions, "milp_calls": 0, "mip_nodes": 0, "binaries": 0}

    def finish(status, horizon, message, traj=None, regions=None, loop_start=None) -> ReachResult:
        timings["total"] = time.perf_counter() - t_start
        counters["iterations"] = clock.iterations
        mission = {
            "formula": problem.mission,
            "semantics": None if regions is None else ("finite" if loop_start is None else "lasso"),
            "loop_start": loop_start,
        }
        return ReachResult(
            status=status,
            solver=name,
            seconds=timings["total"],
            trajectory=traj,
            regions=regions,
            horizon=horizon,
            counters=counters,
            timings=timings,
            options=record,
            message=message,
            guarantee="segments" if segment_safe else "samples",
            mission=mission,
        )

    proved, why = timed_label_proof(problem, labelled, timings, counters)
    if proved:
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    L0 = 0
    if one_shot:
        L0 = L_max
    elif opts.horizon_bound:
        graph = RegionGraph.from_abstraction(labelled.abstraction)
        L0 = timed_horizon_bound(graph, labelled.labels_of, formula, earliest, L_max, timings, counters, clock)
    L = L0
    try:
        for L in clock.steps(range(L0, L_max + 1), progress=progress, what="the MILP at horizon"):
            t0 = time.perf_counter()
            status, regions, loop_start, stats = solve_mission_horizon(
                pp,
                labelled,
                formula,
                L,
                segment_safe=segment_safe,
                semantics=opts.semantics,
                earliest=earliest,
                seconds=clock.remaining(),
            )
            timings["milp"] += time.perf_counter() - t0
            timings["milp_solve"] = timings.get("milp_solve", 0.0) + stats.get("solve_seconds", 0.0)
            counters["milp_calls"] += 1
            counters["mip_nodes"] += stats.get("mip_nodes", 0)
            counters["binaries"] = stats.get("binaries", 0)
            if status == "unknown":
                return finish(ReachStatus.UNKNOWN, L, f"HiGHS stopped without an answer at horizon {L} (time limit)")
            if status == "found":
                t0 = time.perf_counter()
                traj = polish.solve(regions, loop_start) if loop_start is not None else polish.solve_finite(regions)
                timings["lp"] += time.perf_counter() - t0
                if traj is None:
                    return finish(
                        ReachStatus.UNKNOWN,
                        L,
                        f"the MILP's regions at horizon {L} have no trajectory under "
                        "exact LP tolerances (numerically borderline)",
                        regions=regions,
                        loop_start=loop_start,
                    )
                if one_shot:
                    return finish(
                        ReachStatus.FOUND,
                        L,
                        f"found at horizon {L} (one MILP at the max horizon: a plan of "
                        "exactly that many steps, not the shortest)",
                        traj,
                        regions,
                        loop_start,
                    )
                return finish(ReachStatus.FOUND, L, f"found at horizon {L}", traj, regions, loop_start)
    except BudgetExhausted as exc:  # (the polishing LP's time limit too)
        return finish(ReachStatus.UNKNOWN, L, str(exc) if exc.phase.startswith("before") else f"{exc} at horizon {L}")
    if one_shot:
        return finish(
            ReachStatus.UNKNOWN,
            L_max,
            f"no MILP solution at horizon {L_max} (one MILP at the max "
            f"horizon: shorter horizons not tried, no proof); {NOT_A_PROOF} ({why})",
        )
    counters["abstraction_refuted"] = L_max  # one region per step: no proof (see plansynth.reach.mission.planner)
    return finish(
        ReachStatus.UNKNOWN,
        L_max,
        f"no MILP solution through the label-refined abstraction at any horizon up to {L_max}; {NOT_A_PROOF} ({why})",
    )

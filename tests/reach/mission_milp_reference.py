"""The expression-API build of the milp-ltl model, as milp.py had it before its model
was assembled in array operations: one ``addVariable``/``addConstr`` per
column and row. Kept here as the reference the array build is compared against
(tests/reach/test_mission_milp.py): the same columns, rows, bounds and objective."""

from __future__ import annotations

from typing import Any

import highspy
import numpy as np

from plansynth.reach.highs import new_highs
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
    subformulas,
)
from plansynth.reach.mission.milp import SMALL_MATRIX_VALUE, _big_m


def reference_model(
    problem, labelled, formula: Formula, L: int, *, segment_safe: bool = True, semantics: str = "any", earliest=None
) -> highspy.Highs:
    """The mission MILP at horizon L, built term by term (not run)."""
    ab = labelled.abstraction
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = list(dyn.position)
    R = ab.n_regions
    h = new_highs()
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
            h.addConstr(
                X[t + 1][i]
                - sum(float(A[i, j]) * X[t][j] for j in range(n) if A[i, j] != 0)
                - sum(float(B[i, j]) * U[t][j] for j in range(m) if B[i, j] != 0)
                == 0.0
            )
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
            for s in (t, t + 1) if (segment_safe and t < L) else (t,):
                for row, rhs, mm in zip(H, hh, M):
                    if mm <= SMALL_MATRIX_VALUE:
                        continue  # the row holds everywhere in the workspace (up to HiGHS's tolerance)
                    h.addConstr(
                        sum(float(row[k]) * X[s][pos[k]] for k in range(len(pos)) if abs(row[k]) > SMALL_MATRIX_VALUE)
                        + float(mm) * Z[t][i]
                        <= float(rhs + mm)
                    )
    # the successor of the last position: stay (finite) or loop_j (x_L = x_{j-1})
    sels: list[tuple[Any, int, bool]] = []
    if semantics in ("any", "finite"):
        sels.append((h.addBinary(), L, False))
    if semantics in ("any", "lasso"):
        sels += [(h.addBinary(), j, True) for j in range(1, L + 1)]
    h.addConstr(sum(s for s, _, _ in sels) == 1.0)
    AI = A - np.eye(n)
    for s, j, is_loop in sels:
        if not is_loop:
            # stay: at rest, |((A - I) x_L + B u)_i| <= Mr_i (1 - stay) for an admissible u
            u = [h.addVariable(lb=-problem.input_bound, ub=problem.input_bound) for _ in range(m)]
            for i in range(n):
                Mr = float(
                    sum(abs(AI[i, k]) * max(abs(slo[k]), abs(shi[k])) for k in range(n))
                    + sum(abs(B[i, k]) for k in range(m)) * problem.input_bound
                )
                expr = sum(float(AI[i, k]) * X[L][k] for k in range(n) if AI[i, k] != 0) + sum(
                    float(B[i, k]) * u[k] for k in range(m) if B[i, k] != 0
                )
                h.addConstr(expr + Mr * s <= Mr)
                h.addConstr(-1.0 * expr + Mr * s <= Mr)
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
    if not isinstance(f, Const):
        h.addConstr(P[f, 0] >= 1.0)
    return h

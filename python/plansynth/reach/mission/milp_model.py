"""The mission MILP of one horizon (:mod:`plansynth.reach.mission.milp` states it in
full): Wolff, Topcu and Murray's encoding (ICRA 2014, Section IV) of the trajectory, the
obstacles and the labels, and Biere et al.'s linear encoding of the mission (their
Section V) over continuous [0, 1] variables, as a HiGHS model.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import highspy
import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.highs import Rows, csc_lp
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
    WeakNext,
    nnf,
    subformulas,
    unroll,
)
from plansynth.reach.mission.milp_geometry import MilpGeometry, ReachBoxes, Rows_
from plansynth.reach.problem import ReachProblem

__all__ = ["MissionMilp", "mission_milp"]

#: HiGHS drops matrix entries at most this small (its ``small_matrix_value``) and
#: answers such a row with a warning, which highspy raises; they are left out here.
SMALL_MATRIX_VALUE = 1e-9


@dataclass(frozen=True)
class MissionMilp:
    """The mission MILP of one horizon as a HiGHS model: ``lp`` (with its integrality),
    the states and inputs at columns ``0..(L+1) n - 1`` and ``(L+1) n ..``, the loop
    selectors ``(column, j, is_loop)`` (``stay`` has j = L), and the binary columns."""

    lp: highspy.HighsLp
    horizon: int
    n: int
    m: int
    sels: tuple[tuple[int, int, bool], ...]
    binaries: np.ndarray


class _Model:
    """Columns and rows of a MILP (the COO assembly of :func:`~plansynth.reach.highs.csc_lp`)."""

    def __init__(self) -> None:
        self.lo: list[float] = []
        self.hi: list[float] = []
        self.binary: list[int] = []
        self.rows = Rows(checkpoint)
        self._terms: list[tuple[list[int], list[float], float, float]] = []

    def col(self, lo: float, hi: float, *, binary: bool = False) -> int:
        self.lo.append(float(lo))
        self.hi.append(float(hi))
        if binary:
            self.binary.append(len(self.lo) - 1)
        return len(self.lo) - 1

    def cols(self, k: int, lo, hi) -> np.ndarray:
        lo = np.broadcast_to(np.asarray(lo, float), (k,))
        hi = np.broadcast_to(np.asarray(hi, float), (k,))
        first = len(self.lo)
        self.lo += lo.tolist()
        self.hi += hi.tolist()
        return np.arange(first, first + k)

    def row(self, cols: list[int], coefs: list[float], lo: float, hi: float) -> None:
        """``lo <= sum(coefs * x[cols]) <= hi``."""
        self._terms.append((cols, coefs, lo, hi))

    def lp(self) -> highspy.HighsLp:
        if self._terms:
            r = np.repeat(np.arange(len(self._terms)), [len(c) for c, _, _, _ in self._terms])
            c = np.fromiter((j for cs, _, _, _ in self._terms for j in cs), np.int64, len(r))
            v = np.fromiter((x for _, vs, _, _ in self._terms for x in vs), float, len(r))
            self.rows.add(
                r, c, v, np.array([t[2] for t in self._terms], float), np.array([t[3] for t in self._terms], float)
            )
            self._terms = []
        n_col = len(self.lo)
        R, C, V = self.rows.coo()
        key, inv = np.unique(R * n_col + C, return_inverse=True)  # a column twice in a row is one entry
        V = np.bincount(inv.ravel(), weights=V, minlength=len(key))
        keep = np.abs(V) > SMALL_MATRIX_VALUE
        R, C, V = (key // n_col)[keep], (key % n_col)[keep], V[keep]
        row_lo, row_hi = self.rows.bounds()
        integrality = np.full(n_col, highspy.HighsVarType.kContinuous)
        integrality[np.array(self.binary, dtype=np.int64)] = highspy.HighsVarType.kInteger
        return csc_lp(
            n_col,
            self.rows.n_row,
            R,
            C,
            V,
            np.zeros(n_col),
            np.array(self.lo),
            np.array(self.hi),
            row_lo,
            row_hi,
            integrality=list(integrality),
        )


INF = math.inf


def _box_range(H: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(min, max) of each row ``H_i p`` over the box [lo, hi]."""
    a, b = H * lo, H * hi
    return np.minimum(a, b).sum(axis=1), np.maximum(a, b).sum(axis=1)


class _Literals:
    """Each literal's expression at each step: a list of binary columns whose sum bounds
    it (or the constants ``True``/``False``), with the rows that tie the binaries to the
    positions."""

    def __init__(self, mdl: _Model, X: np.ndarray, pos: np.ndarray, boxes: Callable) -> None:
        self.mdl, self.X, self.pos, self.boxes = mdl, X, pos, boxes

    def _span(self, points: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
        lo = np.min([self.boxes(s)[0] for s in points], axis=0)
        hi = np.max([self.boxes(s)[1] for s in points], axis=0)
        return lo, hi

    def inside(self, pieces: tuple[Rows_, ...], points: tuple[int, ...]) -> list[int] | bool:
        """Every point of ``points`` in one of the convex ``pieces``: a binary per piece
        that meets the points' box (True when one piece holds the whole box)."""
        lo, hi = self._span(points)
        out: list[int] = []
        for H, h in pieces:
            mn, mx = _box_range(H, lo, hi)
            if np.any(mn > h + 1e-12):
                continue  # the piece misses the box
            if np.all(mx <= h):
                return True
            z = self.mdl.col(0, 1, binary=True)
            for i in np.nonzero(mx > h)[0]:
                M = float(mx[i] - h[i])
                for s in points:
                    self.mdl.row(list(self.X[s][self.pos]) + [z], list(H[i]) + [M], -INF, float(h[i] + M))
            out.append(z)
        return out if out else False

    def beyond(self, H: np.ndarray, h: np.ndarray, points: tuple[int, ...]) -> list[int] | bool:
        """Every point of ``points`` beyond one edge of the convex {H p <= h}
        (``H_i p >= h_i``): a binary per edge that can separate within the points' box
        (True when one edge separates the whole box, False when none can)."""
        lo, hi = self._span(points)
        mn, mx = _box_range(H, lo, hi)
        if np.any(mn >= h):
            return True
        out: list[int] = []
        # an edge whose outer side meets the box in a line only (an obstacle flush with the
        # workspace's border, clipped there in a robot's configuration space) separates
        # nothing: beyond it lies a slit of zero width, never a path (as for the regions)
        eps = 1e-9 * (1.0 + float(np.max(np.abs(np.concatenate([lo, hi])))))
        for i in np.nonzero(mx > h + eps)[0]:
            d = self.mdl.col(0, 1, binary=True)
            M = float(h[i] - mn[i])
            for s in points:
                self.mdl.row(list(self.X[s][self.pos]) + [d], list(H[i]) + [-M], float(h[i] - M), INF)
            out.append(d)
        return out if out else False


def mission_milp(
    problem: ReachProblem,
    planning: ReachProblem,
    geometry: MilpGeometry,
    formula: Formula,
    L: int,
    boxes: ReachBoxes,
    *,
    semantics: str = "any",
) -> MissionMilp | None:
    """The mission MILP at horizon L (the model :mod:`plansynth.reach.mission.milp` describes) for the
    mission ``problem`` planned in ``planning`` (:func:`~plansynth.reach.mission.labels.planning_problem`);
    ``None`` when the mission is ``false`` (no model can hold it)."""
    f = unroll(nnf(formula))
    if isinstance(f, Const) and not f.value:
        return None
    segment = problem.reading == "segment"
    free = problem.end == "free"
    dyn = planning.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = np.array(dyn.position)
    # finite bounds for the big-M rows: unbounded states get +-1e4
    slo, shi = (np.where(np.isfinite(b), b, s * 1e4) for b, s in zip(planning.state_box, (-1.0, 1.0)))
    mdl = _Model()
    lo_t = np.tile(slo, L + 1).reshape(L + 1, n)
    hi_t = np.tile(shi, L + 1).reshape(L + 1, n)
    for t in range(L + 1):
        lo_t[t, pos], hi_t[t, pos] = boxes(t)
    X = mdl.cols((L + 1) * n, lo_t.ravel(), hi_t.ravel()).reshape(L + 1, n)
    U = mdl.cols(L * m, -planning.input_bound, planning.input_bound).reshape(L, m)
    for i in range(n):
        mdl.row([int(X[0, i])], [1.0], float(planning.start[i]), float(planning.start[i]))
    for t in range(L):
        for i in range(n):
            cs, vs = [int(X[t + 1, i])], [1.0]
            for j in np.nonzero(A[i])[0]:
                cs.append(int(X[t, j])), vs.append(-float(A[i, j]))
            for j in np.nonzero(B[i])[0]:
                cs.append(int(U[t, j])), vs.append(-float(B[i, j]))
            mdl.row(cs, vs, 0.0, 0.0)
    lits = _Literals(mdl, X, pos, boxes)
    spans = [(t, t + 1) if segment and t < L else (t,) for t in range(L + 1)]
    # obstacles: at every sample (sample reading) or along every segment
    for t in range(L + 1):
        if segment and t == L and L > 0:
            continue  # p_L is the end of segment L - 1
        for H, h in geometry.obstacles:
            got = lits.beyond(H, h, spans[t])
            if got is False:
                mdl.row([mdl.col(0, 0)], [1.0], 1.0, INF)  # no edge can separate: no trajectory
            elif got is not True and len(got) > 0:
                mdl.row(got, [1.0] * len(got), 1.0, INF)
    # the literals the mission reads, at each step
    needed = {(g.name, False) for g in subformulas(f) if isinstance(g, Prop)}
    needed |= {(g.arg.name, True) for g in subformulas(f) if isinstance(g, Not)}
    expr: dict[tuple[str, bool, int], list[int] | bool] = {}
    for name, neg in sorted(needed):
        pieces = geometry.labels[name]
        for t in range(L + 1):
            if not neg:
                expr[(name, neg, t)] = lits.inside(pieces.inside, spans[t])
            elif pieces.outside is not None:
                expr[(name, neg, t)] = lits.beyond(pieces.outside[0], pieces.outside[1], spans[t])
            else:
                expr[(name, neg, t)] = lits.inside(pieces.complement, spans[t])
    # the successor of the last position: stay (finite) or loop_j (x_L = x_{j-1})
    sel_j: list[tuple[int, bool]] = []
    if semantics in ("any", "finite"):
        sel_j.append((L, False))
    if semantics in ("any", "lasso"):
        sel_j += [(j, True) for j in range(1, L + 1)]
    sels = tuple((mdl.col(0, 1, binary=True), j, lp) for j, lp in sel_j)
    mdl.row([s for s, _, _ in sels], [1.0] * len(sels), 1.0, 1.0)
    Mx = shi - slo
    AI = A - np.eye(n)
    for s, j, is_loop in sels:
        if not is_loop:
            if free:
                continue  # a free end asks nothing of x_L
            # at rest: (A - I) x_L + B u = 0 for an admissible u, each row within +-Mr (1 - stay)
            u_rest = mdl.cols(m, -planning.input_bound, planning.input_bound)
            Mr = np.abs(AI) @ np.maximum(np.abs(slo), np.abs(shi)) + np.abs(B).sum(axis=1) * planning.input_bound
            for i in range(n):
                cs = [int(X[L, k]) for k in np.nonzero(AI[i])[0]] + [int(u_rest[k]) for k in np.nonzero(B[i])[0]]
                vs = [float(AI[i, k]) for k in np.nonzero(AI[i])[0]] + [float(B[i, k]) for k in np.nonzero(B[i])[0]]
                mdl.row(cs + [s], vs + [float(Mr[i])], -INF, float(Mr[i]))
                mdl.row(cs + [s], [-v for v in vs] + [float(Mr[i])], -INF, float(Mr[i]))
            continue
        for i in range(n):
            mdl.row([int(X[L, i]), int(X[j - 1, i]), s], [1.0, -1.0, float(Mx[i])], -INF, float(Mx[i]))
            mdl.row([int(X[L, i]), int(X[j - 1, i]), s], [-1.0, 1.0, float(Mx[i])], -INF, float(Mx[i]))
    # the mission: P[g, t] in [0, 1] for t = 0..L + 1
    subs = [g for g in subformulas(f) if not isinstance(g, Const)]
    P0 = mdl.cols(len(subs) * (L + 2), 0.0, 1.0)
    index = {g: k for k, g in enumerate(subs)}

    def P(g: Formula, t: int) -> int:
        return int(P0[index[g] * (L + 2) + t])

    def le(v: int, terms: list, t: int, rhs: float = 0.0, later: tuple = ()) -> None:
        """v - sum(terms) <= rhs; a formula term is P[., t] (P[., t + 1] for those in
        ``later``), a Const moves to the rhs."""
        cs, vs = [v], [1.0]
        for g, at in [(g, t) for g in terms] + [(g, t + 1) for g in later]:
            if isinstance(g, Const):
                rhs += 1.0 if g.value else 0.0
            else:
                cs.append(P(g, at))
                vs.append(-1.0)
        mdl.row(cs, vs, -INF, rhs)

    def literal_row(v: int, e: list[int] | bool, rhs: float = 0.0) -> None:
        if e is True:
            return
        if e is False:
            mdl.row([v], [1.0], -INF, rhs)
            return
        mdl.row([v] + e, [1.0] + [-1.0] * len(e), -INF, rhs)

    # a touch is read one way per step (as the checker reads it): a and !a not both
    for name in sorted({nm for nm, neg in needed if neg and (nm, False) in needed}):
        for t in range(L + 2):
            mdl.row([P(Prop(name), t), P(Not(Prop(name)), t)], [1.0, 1.0], -INF, 1.0)
    for t in range(L + 1):
        for g in subs:
            v = P(g, t)
            if isinstance(g, Prop):
                literal_row(v, expr[(g.name, False, t)])
            elif isinstance(g, Not):
                literal_row(v, expr[(g.arg.name, True, t)])
            elif isinstance(g, And):
                le(v, [g.left], t)
                le(v, [g.right], t)
            elif isinstance(g, Or):
                le(v, [g.left, g.right], t)
            elif isinstance(g, (Next, WeakNext)):
                le(v, [g.arg], t + 1)
            elif isinstance(g, (Finally, Until)):  # b now, or a now and g next
                a = Const(True) if isinstance(g, Finally) else g.left
                b = g.arg if isinstance(g, Finally) else g.right
                le(v, [b, a], t)
                le(v, [b], t, later=(g,))
            elif isinstance(g, (Globally, Release)):  # b now, and a now or g next
                a = Const(False) if isinstance(g, Globally) else g.left
                b = g.arg if isinstance(g, Globally) else g.right
                le(v, [b], t)
                le(v, [a], t, later=(g,))
    for s, j, is_loop in sels:
        if not is_loop and free:  # the word ends at L: X fails there, eventualities are met by L
            for g in subs:
                if isinstance(g, Next):
                    mdl.row([P(g, L), s], [1.0, 1.0], -INF, 1.0)
                elif isinstance(g, (Finally, Until)):
                    b = g.arg if isinstance(g, Finally) else g.right
                    if not isinstance(b, Const):
                        mdl.row([P(g, L), P(b, L), s], [1.0, -1.0, 1.0], -INF, 1.0)
                    elif not b.value:  # F false, a U false: never met by L
                        mdl.row([P(g, L), s], [1.0, 1.0], -INF, 1.0)
            continue
        for g in subs:  # position L + 1 takes the values of the selected successor
            mdl.row([P(g, L + 1), P(g, j), s], [1.0, -1.0, 1.0], -INF, 1.0)
        if is_loop and segment:  # position L is position j - 1 again: its segment is that one's
            for name, neg in sorted(needed):
                g = Not(Prop(name)) if neg else Prop(name)
                if g not in index:
                    continue
                back = expr[(name, neg, j - 1)]
                if back is True:
                    continue
                cs, vs = [P(g, L), s], [1.0, 1.0]
                if back is not False:
                    cs += back
                    vs += [-1.0] * len(back)
                mdl.row(cs, vs, -INF, 1.0)
        if is_loop:  # position L is position j - 1 again: a boundary touch there is read one way
            for name, neg in sorted(needed):
                g = Not(Prop(name)) if neg else Prop(name)
                if g in index and j - 1 != L:
                    mdl.row([P(g, L), P(g, j - 1), s], [1.0, -1.0, 1.0], -INF, 1.0)
    # eventualities: an until true at L has its right side true at a loop position
    inloop = [int(c) for c in mdl.cols(L + 1, 0.0, 1.0)]
    for i in range(L + 1):
        here = [s for s, j, is_loop in sels if j == i and (is_loop or not free)]
        cs = [inloop[i]] + ([inloop[i - 1]] if i > 0 else []) + here
        mdl.row(cs, [1.0] + [-1.0] * (len(cs) - 1), -INF, 0.0)
    ends = [s for s, _, is_loop in sels if not is_loop and free]
    for g in subs:
        if isinstance(g, (Finally, Until)):
            b = g.arg if isinstance(g, Finally) else g.right
            w = [int(c) for c in mdl.cols(L + 1, 0.0, 1.0)]
            for i in range(L + 1):
                mdl.row([w[i], inloop[i]], [1.0, -1.0], -INF, 0.0)
                le(w[i], [b], i)
            mdl.row([P(g, L)] + w + ends, [1.0] + [-1.0] * (len(w) + len(ends)), -INF, 0.0)
    if not isinstance(f, Const):
        mdl.row([P(f, 0)], [1.0], 1.0, INF)
    return MissionMilp(mdl.lp(), L, n, m, sels, np.array(mdl.binary, dtype=np.int64))

"""The baseline: the bounded mission as one mixed-integer program per horizon in HiGHS,
encoded as Wolff, Topcu and Murray do ("Optimization-based trajectory generation with
linear temporal logic specifications", ICRA 2014), planner ``milp-ltl``.

No abstraction: the labels and the obstacles are polytopes stated directly on the
continuous positions, as Wolff et al. encode their atomic propositions (Section IV,
"mixed-integer encoding of polyhedra"), and the mission is the linear encoding of Biere
et al. over continuous [0, 1] variables (their Section V). For a horizon L:

* the trajectory: states x_0..x_L, inputs u_0..u_{L-1}, the start, the dynamics, the
  input and state bounds, and each position within the box the robot can reach from the
  start in t steps (:class:`ReachBoxes`, an LP per axis and step: it makes every big-M
  tight and drops the constraints that cannot bind);
* **obstacles** (each convex piece {H p <= h}): at each sample (the sample reading) or
  for each segment (the segment reading: both ends on the outer side of one edge, the
  classical sufficient condition of Richards and How, ACC 2002), a binary per edge that
  can separate within the reachable box, at least one of them set, with
  ``H_i p >= h_i - M_i (1 - d_i)``; an edge that separates the whole box drops the
  obstacle there;
* **labels** at their margins (:mod:`plansynth.reach.offsets`): ``a`` at step t is one
  binary z with ``H p <= h - r + M (1 - z)`` (the shrunk label, at both ends of the
  segment in the segment reading); ``!a`` is a binary per edge of the grown label, as for
  obstacles; a non-convex label (margin 0) is the union of its convex pieces (``a``) and
  of those of its complement in the workspace (``!a``), a binary per piece;
* the **successor of the last position** (Wolff et al.'s loop variables): binaries
  ``stay`` (a finite plan: at rest, ``(A - I) x_L + B u = 0`` for an admissible u; or a
  free end, the word ending at L) and ``loop_j`` with ``x_L = x_{j-1}`` (big-M);
* the **mission** (negation normal form, bounded operators unrolled) as continuous
  variables P[f, t] in [0, 1], t = 0..L + 1 (``P[a, t] + P[!a, t] <= 1``: a position on
  a label's edge is read as in or as out, as the checker reads it), with the one-sided rows of its recursive
  definition (``P[a & b, t] <= P[a, t]``, ``P[a U b, t] <= P[b, t] + P[a, t]``, ...; in
  negation normal form one direction suffices), position L + 1 taking the values of the
  loop's target, and the eventuality rows of the linear encoding; ``P[mission, 0] = 1``.

The binaries are those of the propositions, the obstacles and the loop only (Wolff et
al.'s count: linear in the horizon, independent of any decomposition). Horizons are
tried upwards from the proved lower bound of
:func:`~plansynth.reach.mission.horizon.horizon_lower_bound` over the regions one step
can connect (a bound for every trajectory, so for this model's plans too), as in the lazy
planner; the first with a solution is the shortest. ``milp-ltl-oneshot`` (``one_shot``) is
Wolff et al.'s setting as published: one MILP at the fixed horizon K = ``max_horizon``
(a plan of exactly K steps, not the shortest; no solution there proves nothing about
shorter horizons, so it is ``unknown`` unless the label proof decides).

**What its answers mean.** In the sample reading the model is exact: every trajectory
whose samples satisfy the mission is a solution, so no solution at L refutes L for the
problem, and the first horizon with one is the minimum. In the segment reading the
edge condition is sufficient, not necessary (a segment that passes an obstacle's corner
diagonally is excluded): the plans are valid, the refutations no proof. ``infeasible``
needs the labels' geometry's proof (:func:`~plansynth.reach.mission.proof.label_proof`)
or, in the sample reading, every horizon refuted. The trajectory is not taken from the
MILP (big-M rows slip by the integrality tolerance): with every binary fixed at its
rounded value the model is an LP, solved again.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget, BudgetExhausted, checkpoint
from plansynth.errors import InvalidOption
from plansynth.reach.geometry import convex_pieces, halfspaces, is_convex
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.claims import EXACT_SAMPLES
from plansynth.reach.mission.horizon import timed_horizon_bound
from plansynth.reach.mission.labels import LabelledAbstraction
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
    parse,
    subformulas,
    unroll,
)
from plansynth.reach.mission.options import MilpLtlOptions
from plansynth.reach.mission.proof import NOT_A_PROOF, timed_label_proof
from plansynth.reach.offsets import grown, shrunk
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "MissionMilp",
    "MilpGeometry",
    "ReachBoxes",
    "mission_milp",
    "plan_milp_ltl",
    "solve_mission_horizon",
    "MilpLtlOptions",
]

#: HiGHS drops matrix entries at most this small (its ``small_matrix_value``) and
#: answers such a row with a warning, which highspy raises; they are left out here.
SMALL_MATRIX_VALUE = 1e-9

Rows_ = tuple[np.ndarray, np.ndarray]  # (H, h) of a convex piece: {p : H p <= h}


# --------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class _LabelPieces:
    """A label's literals as polytopes: ``a`` holds in one of ``inside`` (convex pieces;
    empty when no point is deep enough); ``!a`` holds beyond one edge of ``outside`` (a
    convex label grown by its margin) or, for a non-convex label, in one of
    ``complement`` (convex pieces of the workspace outside it)."""

    inside: tuple[Rows_, ...]
    outside: Rows_ | None
    complement: tuple[Rows_, ...]


@dataclass(frozen=True)
class MilpGeometry:
    """The polytopes the model states: the planning problem's obstacles (convex pieces:
    grown by the obstacle margin, in a sized robot's configuration space) and each
    label's literals at its margin."""

    obstacles: tuple[Rows_, ...]
    labels: dict[str, _LabelPieces]

    @classmethod
    def of(cls, problem: ReachProblem, planning: ReachProblem) -> MilpGeometry:
        obstacles = tuple(piece for o in planning.obstacles for piece in convex_pieces(o))
        labels = {}
        ws = planning.workspace
        for name, shape in problem.mission_labels.items():
            r = problem.label_margin(name)
            if is_convex(shape):
                inner = shrunk(shape, r)
                labels[name] = _LabelPieces(
                    () if inner is None else (halfspaces(inner),), halfspaces(grown(shape, r)), ()
                )
            else:  # margin 0 (the door refuses a margin on a non-convex label)
                labels[name] = _LabelPieces(tuple(convex_pieces(shape)), None, _complement(shape, ws))
        return cls(obstacles, labels)


def _complement(shape, ws) -> tuple[Rows_, ...]:
    """Convex pieces (triangles) of the workspace box outside the polygon ``shape``."""
    import shapely

    from plansynth.reach.geometry import Polygon, shape_to_shapely

    rest = shape_to_shapely(ws).difference(shape_to_shapely(shape))
    out = []
    for tri in shapely.get_parts(shapely.constrained_delaunay_triangles(rest)):
        coords = list(tri.exterior.coords)[:-1]
        out.append(halfspaces(Polygon(tuple((float(x), float(y)) for x, y in coords))))
    return tuple(out)


class ReachBoxes:
    """The box of positions the robot can reach from the start in exactly t steps
    (dynamics, input and state bounds, workspace; obstacles ignored): for each step an LP
    per axis and direction, computed on demand and kept. A sound relaxation, so the model
    may bound its positions by it."""

    def __init__(self, planning: ReachProblem) -> None:
        self.problem = planning
        self.boxes: list[tuple[np.ndarray, np.ndarray]] = []
        self.lp_calls = 0

    def __call__(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        while len(self.boxes) <= t:
            checkpoint()
            self.boxes.append(self._box(len(self.boxes)))
        return self.boxes[t]

    def _box(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        p = self.problem
        pos = list(p.dynamics.position)
        start = np.asarray(p.start, float)
        if t == 0:
            return start[pos].copy(), start[pos].copy()
        lo_s, hi_s = p.state_box
        dyn = p.dynamics
        n, m = dyn.n_states, dyn.n_inputs
        A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        nx = (t + 1) * n
        ncol = nx + t * m
        R, C, V = [], [], []
        for s in range(t):
            for i in range(n):
                row = s * n + i
                R.append(row), C.append((s + 1) * n + i), V.append(1.0)
                for j in np.nonzero(A[i])[0]:
                    R.append(row), C.append(s * n + j), V.append(-A[i, j])
                for j in np.nonzero(B[i])[0]:
                    R.append(row), C.append(nx + s * m + j), V.append(-B[i, j])
        col_lo = np.concatenate([np.tile(lo_s, t + 1), np.full(t * m, -p.input_bound)])
        col_hi = np.concatenate([np.tile(hi_s, t + 1), np.full(t * m, p.input_bound)])
        col_lo[:n] = col_hi[:n] = start
        lp = csc_lp(
            ncol,
            t * n,
            np.array(R, np.int64),
            np.array(C, np.int64),
            np.array(V, float),
            np.zeros(ncol),
            col_lo,
            col_hi,
            np.zeros(t * n),
            np.zeros(t * n),
        )
        h = new_highs()
        h.passModel(lp)
        lo, hi = np.zeros(len(pos)), np.zeros(len(pos))
        for a, i in enumerate(pos):
            for sign, out in ((1.0, hi), (-1.0, lo)):
                cost = np.zeros(ncol)
                cost[t * n + i] = -sign  # HiGHS minimises: maximise sign * p_t[a]
                h.changeColsCost(ncol, np.arange(ncol, dtype=np.int32), cost)
                h.run()
                self.lp_calls += 1
                if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
                    out[a] = (p.workspace.hi if sign > 0 else p.workspace.lo)[a]  # no answer: the workspace
                    continue
                out[a] = sign * -h.getInfo().objective_function_value
        # rounding outwards (the LP's tolerance): never cut a reachable position off
        slack = 1e-7 * (1.0 + np.abs(np.concatenate([lo, hi])).max())
        ws_lo, ws_hi = np.asarray(p.workspace.lo, float), np.asarray(p.workspace.hi, float)
        return np.maximum(lo - slack, ws_lo), np.minimum(hi + slack, ws_hi)


# --------------------------------------------------------------------------- the model


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
    """The mission MILP at horizon L (the model the module docstring describes) for the
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


def solve_mission_horizon(
    problem: ReachProblem,
    planning: ReachProblem,
    geometry: MilpGeometry,
    formula: Formula,
    L: int,
    boxes: ReachBoxes,
    *,
    semantics: str = "any",
    seconds: float = math.inf,
) -> tuple[str, Trajectory | None, int | None, dict]:
    """One MILP at horizon L (:func:`mission_milp`), then the LP with its binaries fixed:
    ``(status, trajectory, loop_start, stats)`` with status ``found`` / ``infeasible`` /
    ``unknown`` (time limit, or a solution the LP does not confirm)."""
    t0 = time.perf_counter()
    model = mission_milp(problem, planning, geometry, formula, L, boxes, semantics=semantics)
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
    stats = {
        "binaries": int(len(model.binaries)),
        "mip_nodes": int(h.getInfo().mip_node_count),
        "solve_seconds": time.perf_counter() - t0,
        "build_seconds": build,
    }
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return "infeasible", None, None, stats
    if status != S.kOptimal:
        return "unknown", None, None, stats
    col = np.asarray(h.getSolution().col_value)
    chosen = max(model.sels, key=lambda sj: col[sj[0]])
    loop_start = chosen[1] - 1 if chosen[2] else None
    traj = _polish(model, col, seconds - (time.perf_counter() - t0), loop_start)
    if traj is None:
        stats["unconfirmed"] = True
        return "unknown", None, loop_start, stats
    return "found", traj, loop_start, stats


def _polish(model: MissionMilp, col: np.ndarray, seconds: float, loop_start: int | None) -> Trajectory | None:
    """The LP of the model with every binary fixed at its rounded value: its solution
    keeps each constraint the binaries switch on exactly (up to the LP's tolerance), not
    up to the integrality tolerance times a big-M."""
    lp = model.lp
    lo, hi = np.array(lp.col_lower_, float), np.array(lp.col_upper_, float)
    fixed = np.round(col[model.binaries])
    lo[model.binaries] = hi[model.binaries] = fixed
    lp.col_lower_, lp.col_upper_ = lo, hi
    lp.integrality_ = []
    h = new_highs()
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", max(1e-3, float(seconds)))
    h.passModel(lp)
    h.run()
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return None
    x = np.asarray(h.getSolution().col_value)
    L, n, m = model.horizon, model.n, model.m
    states = x[: (L + 1) * n].reshape(L + 1, n).copy()
    inputs = x[(L + 1) * n : (L + 1) * n + L * m].reshape(L, m).copy()
    if loop_start is not None:
        states[L] = states[loop_start]  # the closure holds to tolerance; make it exact
    return Trajectory(states=states, inputs=inputs)


# --------------------------------------------------------------------------- the planner


def plan_milp_ltl(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: MilpLtlOptions | None = None,
    progress: Callable[[int, int], None] | None = None,
    *,
    labelled: LabelledAbstraction | None = None,
) -> ReachResult:
    """MILPs at horizons up to max_horizon within ``budget`` (not yet validated:
    :func:`plansynth.reach.solve` does that, with the mission checker); ``options``
    (:class:`~plansynth.reach.mission.options.MilpLtlOptions`): ``horizon_bound``: from
    the proved lower bound of :func:`~plansynth.reach.mission.horizon.horizon_lower_bound`
    on, as the lazy planner; ``one_shot``: one MILP at ``max_horizon`` only (Wolff et
    al.'s fixed horizon; see the module doc), planner ``milp-ltl-oneshot``."""
    from plansynth.reach.mission.planner import mission_record, mission_setup

    opts = MilpLtlOptions() if options is None else options
    one_shot = opts.one_shot
    name = "milp-ltl-oneshot" if one_shot else "milp-ltl"
    if problem.mission is None:
        raise InvalidOption(
            name, "planner", "plans LTL missions, and this problem has none (plan it with a reach-avoid planner)"
        )
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    timings = {"abstraction": 0.0, "bounds": 0.0, "milp": 0.0, "lp": 0.0}
    formula = parse(problem.mission)
    segment = problem.reading == "segment"
    record = {
        **asdict(opts),
        "max_horizon": L_max,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
    counters: dict[str, Any] = {"milp_calls": 0, "mip_nodes": 0, "binaries": 0}

    def finish(status, horizon, message, traj=None, loop_start=None, minimal=None) -> ReachResult:
        timings["total"] = time.perf_counter() - t_start
        counters["iterations"] = clock.iterations
        if minimal is not None:
            counters["minimal"] = minimal
            counters["minimal_relative_to"] = "problem" if not segment else "model"
        rec = mission_record(problem, None)
        if traj is not None:
            rec.update(semantics="finite" if loop_start is None else "lasso", loop_start=loop_start)
        return ReachResult(
            status=status,
            solver=name,
            seconds=timings["total"],
            trajectory=traj,
            regions=None,
            horizon=horizon,
            counters=counters,
            timings=timings,
            options=record,
            message=message,
            guarantee="segments" if segment else "samples",
            mission=rec,
        )

    try:
        # the label refinement serves the geometry's proof and the horizon bound (over the
        # regions one step can connect: a bound for every trajectory), not the model
        planning, labelled, graph, earliest = mission_setup(
            problem, clock, timings, L_max, labelled=labelled, lower_bound=opts.lower_bound, steps=True
        )
        counters["regions"] = labelled.n_regions
        with clock.phase("the model's polytopes"):
            geometry = MilpGeometry.of(problem, planning)
        boxes = ReachBoxes(planning)
    except BudgetExhausted as exc:
        return finish(ReachStatus.UNKNOWN, None, str(exc))
    proved, why = timed_label_proof(problem, labelled, timings, counters, clock)
    if proved:
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    L0 = 0
    if one_shot:
        L0 = L_max
    elif opts.horizon_bound:
        L0 = timed_horizon_bound(graph, labelled, formula, earliest, L_max, timings, counters, clock, end=problem.end)
    L = L0
    exact = not segment and labelled.abstraction.exact
    try:
        for L in clock.steps(range(L0, L_max + 1), progress=progress, what="the MILP at horizon"):
            t0 = time.perf_counter()
            with clock.phase(f"the MILP at horizon {L}"):
                status, traj, loop_start, stats = solve_mission_horizon(
                    problem, planning, geometry, formula, L, boxes, semantics=opts.semantics, seconds=clock.remaining()
                )
            timings["milp"] += time.perf_counter() - t0
            timings["milp_solve"] = timings.get("milp_solve", 0.0) + stats.get("solve_seconds", 0.0)
            counters["milp_calls"] += 1
            counters["mip_nodes"] += stats.get("mip_nodes", 0)
            counters["binaries"] = stats.get("binaries", 0)
            counters["reach_box_lps"] = boxes.lp_calls
            if status == "unknown":
                why_unknown = (
                    "its binaries fixed, the LP has no solution (numerically borderline)"
                    if stats.get("unconfirmed")
                    else "HiGHS stopped without an answer (time limit)"
                )
                return finish(ReachStatus.UNKNOWN, L, f"the MILP at horizon {L}: {why_unknown}")
            if status == "found":
                if one_shot:
                    return finish(
                        ReachStatus.FOUND,
                        L,
                        f"found at horizon {L} (one MILP at the max horizon: a plan of exactly that many "
                        "steps, not the shortest)",
                        traj,
                        loop_start,
                        minimal=False,
                    )
                return finish(ReachStatus.FOUND, L, f"found at horizon {L}", traj, loop_start, minimal=exact)
    except BudgetExhausted as exc:
        said = str(exc) if exc.phase.startswith("before") or "horizon" in exc.phase else f"{exc} at horizon {L}"
        return finish(ReachStatus.UNKNOWN, L, said)
    if one_shot:
        return finish(
            ReachStatus.UNKNOWN,
            L_max,
            f"no MILP solution at horizon {L_max} (one MILP at the max horizon: shorter horizons not "
            f"tried, no proof); {NOT_A_PROOF} ({why})",
        )
    if exact:
        return finish(
            ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: every horizon refuted ({EXACT_SAMPLES})"
        )
    counters["abstraction_refuted"] = L_max
    return finish(
        ReachStatus.UNKNOWN,
        L_max,
        f"no MILP solution at any horizon up to {L_max} (segments: each kept beyond one edge of each "
        f"obstacle, a sufficient condition); {NOT_A_PROOF} ({why})",
    )

"""An exact MILP for missions in the sample reading, written from scratch for the tests
(it shares no code with plansynth.reach.mission): the oracle of "no plan is missed at
its horizon".

For a horizon N and one *shape* of plan (finite ending at rest, finite with a free end,
or a lasso back to step k), the word's positions and successors are fixed, so the
mission's truth is a Boolean circuit over the literals at the positions: ``a U b`` at i is
``OR_j (b_j & a_i & ... & a_{j-1})`` over the positions reachable from i in one turn of
the word, ``X a`` the successor's value (false past a free end), the bounded operators
their windows. Each literal at each position is a binary tied to the geometry of the
sample (big-M over the label's shrunk box for ``a``; one binary per edge of its grown
box for ``!a``; a and !a never both: a touch is read one way); obstacles are boxes kept
off each sample by one edge. The formula is in negation normal form, so one-sided rows
(a gate's value at most what its inputs allow) are exact. The least horizon with a
feasible shape is the problem's shortest plan in the sample reading, as the checker
judges plans.

In the segment reading (``segments=True``) position t is the segment [p_t, p_{t+1}] (the
last position of a finite plan its last sample; a lasso's positions are its N segments,
x_N = x_k): ``a`` asks both ends inside the shrunk box (exact: a box is convex), ``!a``
and every obstacle both ends beyond one common edge (sufficient, not necessary: a segment
that passes a corner, its ends beyond two different edges, misses the box too). So a plan
of this model is a plan of the problem, and its least horizon is an upper bound on the
shortest: no claim "refuted for the problem" may lie at or above it.
"""

from __future__ import annotations

import highspy
import numpy as np

from plansynth.reach.geometry import Box
from plansynth.reach.ltl import (
    And,
    Const,
    Finally,
    FinallyWithin,
    Globally,
    GloballyWithin,
    Next,
    Not,
    Or,
    Prop,
    Release,
    ReleaseWithin,
    Until,
    UntilWithin,
    WeakNext,
    nnf,
    parse,
    subformulas,
)

INF = highspy.kHighsInf


class _Model:
    def __init__(self) -> None:
        self.lo: list[float] = []
        self.hi: list[float] = []
        self.integer: list[int] = []
        self.rows: list[tuple[dict[int, float], float, float]] = []

    def var(self, lo: float, hi: float, integer: bool = False) -> int:
        self.lo.append(lo)
        self.hi.append(hi)
        if integer:
            self.integer.append(len(self.lo) - 1)
        return len(self.lo) - 1

    def row(self, coef: dict[int, float], lo: float, hi: float) -> None:
        self.rows.append((coef, lo, hi))

    def solve(self, seconds: float) -> bool | None:
        h = highspy.Highs()
        h.silent()
        h.setOptionValue("threads", 1)
        h.setOptionValue("time_limit", seconds)
        n = len(self.lo)
        h.addVars(n, np.array(self.lo), np.array(self.hi))
        if self.integer:
            h.changeColsIntegrality(
                len(self.integer),
                np.array(self.integer, dtype=np.int32),
                np.array([highspy.HighsVarType.kInteger] * len(self.integer)),
            )
        for coef, lo, hi in self.rows:
            idx = np.array(list(coef), dtype=np.int32)
            h.addRow(lo, hi, len(idx), idx, np.array([coef[i] for i in idx], float))
        h.run()
        st = h.getModelStatus()
        if st == highspy.HighsModelStatus.kOptimal:
            return True
        if st == highspy.HighsModelStatus.kInfeasible:
            return False
        return None


def _gate(m: _Model, xs: list, conj: bool):
    """A variable at most the AND (OR) of ``xs`` (variables or True/False)."""
    neutral, absorbing = bool(conj), not conj  # (the constants are the bools True and False)
    xs = [x for x in xs if x is not neutral]
    if any(x is absorbing for x in xs):
        return absorbing
    if not xs:
        return conj
    v = m.var(0, 1)
    if conj:
        for x in xs:
            m.row({v: 1.0, x: -1.0}, -INF, 0.0)
    else:
        coef = {v: 1.0}
        for x in xs:
            coef[x] = coef.get(x, 0.0) - 1.0
        m.row(coef, -INF, 0.0)
    return v


def _shape_model(problem, N: int, shape: tuple[str, int | None], segments: bool = False) -> _Model:
    """The model of one horizon and shape: ("rest", None), ("free", None) or ("lasso", k).
    ``segments``: the segment reading, by sufficient conditions (module docstring)."""
    kind, k = shape
    dyn = problem.dynamics
    n, mm = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = list(dyn.position)
    lo_s, hi_s = problem.state_box
    lo_s = np.where(np.isfinite(lo_s), lo_s, -1e4)
    hi_s = np.where(np.isfinite(hi_s), hi_s, 1e4)
    m = _Model()
    x = [[m.var(float(lo_s[i]), float(hi_s[i])) for i in range(n)] for _ in range(N + 1)]
    u = [[m.var(-problem.input_bound, problem.input_bound) for _ in range(mm)] for _ in range(N)]
    for i in range(n):
        m.row({x[0][i]: 1.0}, float(problem.start[i]), float(problem.start[i]))
    for t in range(N):
        for i in range(n):
            coef = {x[t + 1][i]: 1.0}
            for j in range(n):
                if A[i, j]:
                    coef[x[t][j]] = coef.get(x[t][j], 0.0) - A[i, j]
            for j in range(mm):
                if B[i, j]:
                    coef[u[t][j]] = -B[i, j]
            m.row(coef, 0.0, 0.0)
    if kind == "lasso":
        for i in range(n):
            m.row({x[N][i]: 1.0, x[k][i]: -1.0}, 0.0, 0.0)
    elif kind == "rest":
        ur = [m.var(-problem.input_bound, problem.input_bound) for _ in range(mm)]
        for i in range(n):
            coef = {x[N][i]: 1.0}
            for j in range(n):
                if A[i, j]:
                    coef[x[N][j]] = coef.get(x[N][j], 0.0) - A[i, j]
            for j in range(mm):
                if B[i, j]:
                    coef[ur[j]] = -B[i, j]
            m.row(coef, 0.0, 0.0)
    big = float(np.max(hi_s - lo_s)) * 4 + 10

    def point(t: int) -> list[int]:
        return [x[t][i] for i in pos]

    def ends(t: int) -> tuple[int, ...]:
        """The samples whose rows read position t: its segment's two ends in the segment
        reading (a box is convex: both ends inside, or both beyond one edge, is enough),
        the sample alone otherwise and at the last position of a finite plan."""
        return (t, t + 1) if segments and t < N else (t,)

    def inside(t: int, lo, hi) -> int:
        z = m.var(0, 1, integer=True)
        for q in ends(t):
            p = point(q)
            for a in range(2):
                m.row({p[a]: 1.0, z: big}, -INF, hi[a] + big)
                m.row({p[a]: -1.0, z: big}, -INF, -lo[a] + big)
        return z

    def beyond(t: int, lo, hi) -> list[int]:
        ds = []
        for a in range(2):
            for sign, edge in ((1.0, hi[a]), (-1.0, lo[a])):
                d = m.var(0, 1, integer=True)
                for q in ends(t):
                    m.row({point(q)[a]: sign, d: -big}, sign * edge - big, INF)
                ds.append(d)
        return ds

    for ob in problem.obstacles:
        assert isinstance(ob, Box)
        for t in range(N if segments and N > 0 else N + 1):
            ds = beyond(t, ob.lo, ob.hi)
            m.row(dict.fromkeys(ds, 1.0), 1.0, INF)
    # the word: positions and successors of this shape
    if kind == "lasso":
        n_pos = N
        succ = [i + 1 if i + 1 < N else k for i in range(N)]
    elif kind == "rest":
        n_pos = N + 1
        succ = [min(i + 1, N) for i in range(N + 1)]
    else:
        n_pos = N + 1
        succ = [i + 1 if i < N else None for i in range(N + 1)]
    f = nnf(parse(problem.mission))
    labels = problem.mission_labels
    lit: dict[tuple[str, bool, int], int] = {}

    def literal(name: str, neg: bool, i: int) -> int:
        key = (name, neg, i)
        if key not in lit:
            box = labels[name]
            r = problem.label_margin(name)
            if neg:
                ds = beyond(i, [v - r for v in box.lo], [v + r for v in box.hi])
                v = m.var(0, 1)
                m.row({v: 1.0, **{d: -1.0 for d in ds}}, -INF, 0.0)
            else:
                lo, hi = [v + r for v in box.lo], [v - r for v in box.hi]
                v = inside(i, lo, hi) if all(a <= b for a, b in zip(lo, hi)) else False
            lit[key] = v
            other = (name, not neg, i)
            if other in lit and v is not False and lit[other] is not False:
                m.row({v: 1.0, lit[other]: 1.0}, -INF, 1.0)  # a touch is read one way
        return lit[key]

    def ahead(i: int, steps: int) -> int | None:
        for _ in range(steps):
            if i is None:
                return None
            i = succ[i]
        return i

    def turn(i: int) -> list[int]:
        """The positions from i on, until they repeat (the word has no more)."""
        out, seen, j = [], set(), i
        while j is not None and j not in seen:
            seen.add(j)
            out.append(j)
            j = succ[j]
        return out

    val: dict = {}
    for g in subformulas(f):
        v = []
        for i in range(n_pos):
            if isinstance(g, Const):
                v.append(g.value)
            elif isinstance(g, Prop):
                v.append(literal(g.name, False, i))
            elif isinstance(g, Not):
                v.append(literal(g.arg.name, True, i))
            elif isinstance(g, (And, Or)):
                v.append(_gate(m, [val[g.left][i], val[g.right][i]], isinstance(g, And)))
            elif isinstance(g, (Next, WeakNext)):
                j = succ[i]
                v.append(val[g.arg][j] if j is not None else isinstance(g, WeakNext))
            elif isinstance(g, (Finally, Until, Globally, Release)):
                strong = isinstance(g, (Finally, Until))
                if isinstance(g, (Finally, Globally)):
                    a, b = [strong] * n_pos, val[g.arg]
                else:
                    a, b = val[g.left], val[g.right]
                if strong:  # some position (in one turn) with b, a at every one before it
                    terms, side = [], []
                    for j in turn(i):
                        terms.append(_gate(m, side + [b[j]], True))
                        side = side + [a[j]]
                    v.append(_gate(m, terms, False))
                else:  # release: b at each position until (and at) the first a; weak at a free end
                    out, seen_a = [], []
                    for j in turn(i):
                        out.append(_gate(m, [b[j], _gate(m, list(seen_a), False)], False))
                        seen_a.append(a[j])
                    v.append(_gate(m, out, True))
            elif isinstance(g, (FinallyWithin, GloballyWithin, UntilWithin, ReleaseWithin)):
                window = [(kk, ahead(i, kk)) for kk in range(g.lo, g.hi + 1)]
                if isinstance(g, (FinallyWithin, GloballyWithin)):
                    xs = [val[g.arg][j] for _, j in window if j is not None]
                    v.append(_gate(m, xs, isinstance(g, GloballyWithin)))
                else:
                    until = isinstance(g, UntilWithin)
                    terms = []
                    for kk, j in window:
                        if j is None:
                            break
                        before = [val[g.left][ahead(i, q)] for q in range(kk)]
                        if until:
                            terms.append(_gate(m, [val[g.right][j]] + before, True))
                        else:
                            terms.append(_gate(m, [val[g.right][j], _gate(m, before, False)], False))
                    v.append(_gate(m, terms, not until))
            else:
                raise TypeError(type(g).__name__)
        val[g] = v
    top = val[f][0]
    if top is False:
        m.row({m.var(0, 0): 1.0}, 1.0, INF)
    elif top is not True:
        m.row({top: 1.0}, 1.0, INF)
    return m


def shortest_horizon(problem, max_horizon: int, seconds: float = 30.0, *, segments: bool = False) -> int | None:
    """The least N <= max_horizon with a plan of some shape that satisfies the mission in
    the sample reading (the problem's end for finite plans), or None (every horizon
    refuted). Raises RuntimeError when HiGHS gives no answer in time. ``segments``: in
    the segment reading, by sufficient conditions (module docstring): the least N with
    such a plan, an upper bound on the shortest."""
    end = "rest" if problem.end == "rest" else "free"
    for N in range(max_horizon + 1):
        shapes = [(end, None)] + [("lasso", k) for k in range(N)]
        for shape in shapes:
            got = _shape_model(problem, N, shape, segments).solve(seconds)
            if got is None:
                raise RuntimeError(f"no answer at horizon {N}, shape {shape}")
            if got:
                return N
    return None

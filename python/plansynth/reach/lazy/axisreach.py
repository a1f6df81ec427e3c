"""Reachable sets per axis over the region graph: a sound horizon lower bound and a tube
for :func:`~plansynth.reach.lazy.minimal.prove_minimal` (beyond Shoukry et al., CDC 2016).

**What it computes.** When the dynamics separate by workspace axis into blocks of at
most two states (the double and single integrators: position and velocity per axis,
one input per axis, ``|u|_inf <= input_bound``), every constraint CON-PLAN writes for a
plan r_0..r_L is a constraint on one axis at a time, once each region is replaced by its
bounding box (exact for box regions): the dynamics, the input and state bounds, "p_t in
r_t", with segment safety "p_{t+1} in r_t", and "p_L in the goal" (its bounding box).
For each region i, time t and axis a, the sweep keeps a convex polygon F[i, t][a] in
that axis's (position, velocity) plane:

* F[i, 0] is the start state for the start regions;
* F[i, t+1][a] is the convex hull, over the regions j that DIS-PLAN lets precede i
  (j = i or j adjacent to i), of ``A_a F[j, t][a] + B_a [-u, u]`` cut to the state
  bounds and to "p in box(i)" (and "p in box(j)" with segment safety);
* (i, t) is dropped as soon as one axis's polygon is empty, and (with DIS-PLAN's time
  windows) when t < earliest[i] or t + to_go[i] exceeds the horizon asked about.

**Soundness** (by induction on t): for every plan DIS-PLAN may propose and every
trajectory x that CON-PLAN accepts for it, the projection of x_t on axis a lies in
F[r_t, t][a]. At t = 0, x_0 is the start and r_0 a start region. If it holds at t, then
x_{t+1} = A x_t + B u_t projects on axis a to ``A_a (x_t)_a + B_a (u_t)_a`` (the blocks
separate), which lies in the image of the convex polygon F[r_t, t][a] under the linear
map plus the segment of inputs (an image of a convex polygon is the hull of its
vertices' images; a Minkowski sum with a segment is the hull of the two shifted vertex
sets), and satisfies every bound of CON-PLAN's LP on that axis at t + 1 (so it lies in
the cut polygon), and a hull of a union contains each member. The windows drop only
pairs that no plan ending by the horizon asked about visits (they are DIS-PLAN's own
sound facts). Every cut is relaxed by :data:`EPS` (the sets only grow: floating-point
rounding and HiGHS's feasibility tolerance cannot make a realisable plan look
impossible). So when no goal region's polygons meet the goal box at step L on every
axis, *no plan of horizon L exists*: not through the region sequences DIS-PLAN
proposes, hence exactly what the lazy loop would prove by refuting L (minimal relative
to the same transition relation and semantics; the claims keep their labels). The
converse does not hold (the hull forgets which predecessor a state came from, and the
axes forget each other), so this is only a bound; on maze-1..4 it equals the minimal
horizon (57, 85, 113, 141) with no LP.

**The tube** for one horizon L: a backward sweep from the goal at L (the pre-image of
each polygon under the step, ``A_a^{-1}(Q + B_a [-u, u])``, cut by the constraints of
the earlier step and intersected with the forward polygon) leaves the pairs (i, t)
through which some trajectory of horizon L might pass; by the same induction, a
trajectory of horizon L visits only those, so "not region i at time t" holds for every
plan of horizon L at every other pair (DIS-PLAN adds these under that horizon's
activation literal).

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.abstraction import abstract
>>> p = maze(1); a = abstract(p)
>>> ar = AxisReach.build(p, a, a.adjacency, a.start_regions, a.goal_regions, segment_safe=True)
>>> ar.first_horizon(70)          # maze-1's minimal horizon (the region MILP's)
57
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.bounds import shape_box
from plansynth.reach.problem import ReachProblem

__all__ = ["AxisReach", "EPS", "MAX_SWEEPS"]

#: Every cut of a polygon by a bound is relaxed by this much (metres, metres per second):
#: the sets are over-approximations also in floating point and within LP tolerances.
EPS = 1e-6

#: The forward sweep stops after this many (region, step) polygon steps (maze-4: 303;
#: the GCS paper's 20 x 20 maze, 249 regions, would need tens of thousands, seconds).
MAX_SWEEPS = 3000

Poly = list[tuple[float, float]]


def _hull(points: Poly) -> Poly:
    """Convex hull (counter-clockwise, Andrew's monotone chain) of a few points; only
    exactly collinear, repeated or inner points are dropped (the hull never shrinks)."""
    pts = sorted(points)
    if len(pts) <= 2:
        return pts if len(pts) < 2 or pts[0] != pts[1] else pts[:1]
    lower: Poly = []
    upper: Poly = []
    for chain, seq in ((lower, pts), (upper, reversed(pts))):
        for p in seq:
            px, py = p
            while len(chain) >= 2:
                ox, oy = chain[-2]
                ax, ay = chain[-1]
                if (ax - ox) * (py - oy) - (ay - oy) * (px - ox) <= 0:
                    chain.pop()
                else:
                    break
            chain.append(p)
    out = lower[:-1] + upper[:-1]
    return out if out else pts[:1]


def _cut(P: Poly, a0: float, a1: float, b: float) -> Poly | None:
    """The convex polygon ``P`` cut to ``a0 x + a1 y <= b + EPS`` (None: empty)."""
    s = [a0 * x + a1 * y - b - EPS for x, y in P]
    if max(s) <= 0:
        return P
    if min(s) > 0:
        return None
    out: Poly = []
    n = len(P)
    for k in range(n):
        p, sp = P[k], s[k]
        q, sq = P[(k + 1) % n], s[(k + 1) % n]
        if sp <= 0:
            out.append(p)
        if (sp <= 0) != (sq <= 0):
            lam = sp / (sp - sq)
            out.append((p[0] + lam * (q[0] - p[0]), p[1] + lam * (q[1] - p[1])))
    return out


def _box(P: Poly | None, plo: float, phi: float, vlo: float, vhi: float) -> Poly | None:
    """``P`` cut to plo <= position <= phi, vlo <= velocity <= vhi (infinite: no cut)."""
    if P is None:
        return None
    xs = [x for x, _ in P]
    ys = [y for _, y in P]
    for a0, a1, b, top in (
        (1.0, 0.0, phi, max(xs)),
        (-1.0, 0.0, -plo, -min(xs)),
        (0.0, 1.0, vhi, max(ys)),
        (0.0, -1.0, -vlo, -min(ys)),
    ):
        if top <= b + EPS:  # (also b infinite) the polygon is within: no cut
            continue
        P = _cut(P, a0, a1, b)
        if P is None:
            return None
    return P


def _meet(P: Poly, Q: Poly) -> Poly | None:
    """``P`` intersected with the convex polygon ``Q`` (each edge of Q a cut; a point or a
    segment Q cuts along its own line both ways)."""
    n = len(Q)
    if n == 1:
        ((x, y),) = Q
        return _box(P, x, x, y, y)
    edges = [(Q[k], Q[(k + 1) % n]) for k in range(n)] if n > 2 else [(Q[0], Q[1]), (Q[1], Q[0])]
    for (x0, y0), (x1, y1) in edges:
        # the left side of the directed edge (counter-clockwise hull): -(y1-y0) x + (x1-x0) y >= ...
        a0, a1 = (y1 - y0), -(x1 - x0)
        P = _cut(P, a0, a1, a0 * x0 + a1 * y0)
        if P is None:
            return None
    if n == 2:  # also within the segment's extent along it
        (x0, y0), (x1, y1) = Q
        d0, d1 = x1 - x0, y1 - y0
        P = _cut(P, d0, d1, d0 * x1 + d1 * y1)
        P = None if P is None else _cut(P, -d0, -d1, -(d0 * x0 + d1 * y0))
    return P


class _Axis:
    """One axis's block: 2 x 2 ``A``, input columns (2-vectors, already times the
    bound), state bounds of its position and its second state (a single integrator's
    is a constant 0)."""

    def __init__(self, A: np.ndarray, cols: list[np.ndarray], lo: Sequence[float], hi: Sequence[float]) -> None:
        self.A = [[float(v) for v in row] for row in A]
        self.cols = [(float(c[0]), float(c[1])) for c in cols]
        self.lo, self.hi = (float(lo[0]), float(lo[1])), (float(hi[0]), float(hi[1]))
        det = self.A[0][0] * self.A[1][1] - self.A[0][1] * self.A[1][0]
        self.Ainv = (
            [[self.A[1][1] / det, -self.A[0][1] / det], [-self.A[1][0] / det, self.A[0][0] / det]]
            if abs(det) > 1e-12
            else None
        )

    def image(self, P: Poly) -> Poly:
        (a, b), (c, d) = self.A
        V = [(a * x + b * y, c * x + d * y) for x, y in P]
        return self._spread(V)

    def preimage(self, P: Poly) -> Poly:
        assert self.Ainv is not None
        (a, b), (c, d) = self.Ainv
        V = self._spread(P)
        return _hull([(a * x + b * y, c * x + d * y) for x, y in V])

    def _spread(self, V: Poly) -> Poly:
        for b0, b1 in self.cols:  # + B_a [-u, u], one input at a time
            V = [(x + b0, y + b1) for x, y in V] + [(x - b0, y - b1) for x, y in V]
        return _hull(V)


class AxisReach:
    """The per-axis sweep of the module docstring over one region graph (``adjacency``,
    start and goal regions: the relation DIS-PLAN uses), segment-safe or samples only.
    Build it with :meth:`build` (None when the problem does not separate)."""

    def __init__(
        self,
        axes: list[_Axis],
        boxes: list[tuple[list[float], list[float]]],
        goal: tuple[list[float], list[float]],
        start: list[tuple[float, float]],
        adjacency: Sequence[Sequence[int]],
        start_regions: Sequence[int],
        goal_regions: Sequence[int],
        segment_safe: bool,
    ) -> None:
        self.axes, self.boxes, self.goal, self.start = axes, boxes, goal, start
        self.adjacency = [tuple(a) for a in adjacency]
        self.start_regions, self.goal_regions = tuple(start_regions), tuple(goal_regions)
        self.segment_safe = segment_safe
        self.forward: list[dict[int, list[Poly]]] = []
        self.limit = -1  # the sets hold for the horizons up to this (the windows' pruning)
        self._early: list[float] = []
        self._togo: list[float] = []
        self.sweeps = 0  # polygon steps computed (a work counter)
        self.reached = False  # did first_horizon's answer reach the goal (else: its work cap)?

    @classmethod
    def build(
        cls,
        problem: ReachProblem,
        abstraction: Abstraction,
        adjacency: Sequence[Sequence[int]],
        start_regions: Sequence[int],
        goal_regions: Sequence[int],
        *,
        segment_safe: bool,
    ) -> AxisReach | None:
        """The sweep for ``problem``, or None unless its dynamics separate by position
        axis into blocks of one or two states with one input column each (see the module
        docstring); every other state, in no position's block, is left free (a
        relaxation)."""
        dyn = problem.dynamics
        A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        n, m = A.shape[0], B.shape[1]
        parent = list(range(n + m))

        def find(k: int) -> int:
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        for i, j in zip(*np.nonzero(A)):
            parent[find(int(i))] = find(int(j))
        for i, j in zip(*np.nonzero(B)):
            parent[find(int(i))] = find(n + int(j))
        lo, hi = problem.state_box
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        axes = []
        for p in dyn.position:
            root = find(p)
            states = [k for k in range(n) if find(k) == root]
            inputs = [j for j in range(m) if find(n + j) == root]
            if len(states) > 2 or sum(1 for q in dyn.position if find(q) == root) != 1:
                return None
            other = [k for k in states if k != p]
            ix = [p] + other
            Aa = A[np.ix_(ix, ix)]
            cols = [B[ix, j] * problem.input_bound for j in inputs]
            if not other:  # a single integrator: a constant second coordinate
                Aa = np.array([[Aa[0, 0], 0.0], [0.0, 1.0]])
                cols = [np.array([c[0], 0.0]) for c in cols]
                alo, ahi = [lo[p], 0.0], [hi[p], 0.0]
            else:
                alo, ahi = [lo[p], lo[other[0]]], [hi[p], hi[other[0]]]
            axes.append((_Axis(Aa, cols, alo, ahi), ix))
        boxes = []
        for r in abstraction.regions:
            v = np.asarray(r.vertices, float)
            boxes.append((v.min(axis=0).tolist(), v.max(axis=0).tolist()))
        glo, ghi = shape_box(problem.goal)
        x0 = np.asarray(problem.start, float)
        start = [(float(x0[ix[0]]), float(x0[ix[1]]) if len(ix) > 1 else 0.0) for _, ix in axes]
        return cls(
            [a for a, _ in axes],
            boxes,
            (list(map(float, glo)), list(map(float, ghi))),
            start,
            adjacency,
            start_regions,
            goal_regions,
            segment_safe,
        )

    # ------------------------------------------------------------------ the forward sweep
    def _reaches_goal(self, i: int, sets: list[Poly]) -> list[Poly] | None:
        (glo, ghi), (blo, bhi) = self.goal, self.boxes[i]
        out = []
        for a, (_ax, P) in enumerate(zip(self.axes, sets)):
            c = _box(P, max(glo[a], blo[a]), min(ghi[a], bhi[a]), -math.inf, math.inf)
            if c is None:
                return None
            out.append(c)
        return out

    def first_horizon(
        self, limit: int, earliest: Sequence[float] | None = None, to_go: Sequence[float] | None = None
    ) -> int | None:
        """The first horizon L <= ``limit`` at which the sweep reaches the goal (None: none
        does, so no plan of any horizon up to ``limit`` exists). Every horizon below the
        answer has no plan (module docstring). ``earliest``/``to_go``: DIS-PLAN's time
        windows (sound), which prune the sweep for the horizons up to ``limit``; the sets
        are kept for :meth:`tube` (at most ``limit``). After :data:`MAX_SWEEPS` polygon
        steps the sweep stops and answers the first step it did not sweep, still a lower
        bound, with ``reached`` False (True when the answer is a goal step)."""
        nr = len(self.boxes)
        self._early = [0.0] * nr if earliest is None else list(earliest)
        self._togo = [0.0] * nr if to_go is None else list(to_go)
        self.limit = limit
        self.reached = False
        self.forward = [{i: [[s] for s in self.start] for i in self.start_regions if self._togo[i] <= limit}]
        for t in range(0, limit + 1):
            if t > 0:
                if self.sweeps > MAX_SWEEPS:
                    return t  # no plan below t (swept so far); ``reached`` stays False
                self._step()
            G = self.forward[t]
            if any(self._reaches_goal(i, G[i]) is not None for i in self.goal_regions if i in G):
                self.reached = True
                return t
        return None

    def _step(self) -> None:
        """One more step of the forward sweep (module docstring)."""
        checkpoint()
        boxes, adj, axes = self.boxes, self.adjacency, self.axes
        early, togo, limit = self._early, self._togo, self.limit
        t = len(self.forward)
        G: dict[int, list[Poly]] = {}
        for j, sets in self.forward[t - 1].items():
            images = [ax.image(P) for ax, P in zip(axes, sets)]
            self.sweeps += 1
            for i in (j, *adj[j]):
                if t < early[i] or t + togo[i] > limit:
                    continue
                bi, bj = boxes[i], boxes[j]
                new = []
                for a, ax in enumerate(axes):
                    plo, phi = max(bi[0][a], ax.lo[0]), min(bi[1][a], ax.hi[0])
                    if self.segment_safe:
                        plo, phi = max(plo, bj[0][a]), min(phi, bj[1][a])
                    c = _box(images[a], plo, phi, ax.lo[1], ax.hi[1])
                    if c is None:
                        break
                    new.append(c)
                else:
                    G[i] = [_hull(old + c) for old, c in zip(G[i], new)] if i in G else new
        self.forward.append(G)

    # ------------------------------------------------------------------ the tube
    def tube(self, horizon: int) -> set[tuple[int, int]] | None:
        """The pairs (t, i) that a trajectory of horizon ``horizon`` may visit (module
        docstring), or None when the step cannot be inverted or :meth:`first_horizon`
        did not sweep that far. Every other (t, i) with t <= horizon is visited by no
        plan of that horizon."""
        if horizon > self.limit or any(ax.Ainv is None for ax in self.axes):
            return None
        while len(self.forward) <= horizon:
            self._step()
        F = self.forward
        axes, boxes, adj = self.axes, self.boxes, self.adjacency
        back: dict[int, list[Poly]] = {}
        for i in self.goal_regions:
            if i in F[horizon]:
                g = self._reaches_goal(i, F[horizon][i])
                if g is not None:
                    back[i] = g
        allowed = {(horizon, i) for i in back}
        for t in range(horizon - 1, -1, -1):
            checkpoint()
            G: dict[int, list[Poly]] = {}
            for k, sets in back.items():
                for i in (k, *adj[k]):
                    if i not in F[t]:
                        continue
                    bi = boxes[i]
                    new = []
                    for a, ax in enumerate(axes):
                        S = sets[a]
                        if self.segment_safe and i != k:  # p_{t+1} in r_t = i too
                            S = _box(S, bi[0][a], bi[1][a], -math.inf, math.inf)
                        c = None if S is None else _meet(ax.preimage(S), F[t][i][a])
                        if c is None:
                            break
                        new.append(c)
                    else:
                        G[i] = [_hull(old + c) for old, c in zip(G[i], new)] if i in G else new
            back = G
            allowed |= {(t, i) for i in G}
        return allowed

"""The theory of exact segment transitions (beyond Shoukry et al., CDC 2016, Section V,
whose CON-PLAN realises one region per time step): a plan of
:class:`~plansynth.reach.lazy.segments.SegmentDisPlan` (regions for the samples and for
points along the segments) is realised by a trajectory whose segments avoid every
obstacle exactly, refuted by a sound conflict, or answered with a
:class:`~plansynth.reach.lazy.segments.Refinement`.

The spec's segment safety ("the straight segment between two consecutive positions
avoids every obstacle's interior") is not a finite union of polyhedra in (p_t,
p_{t+1}): past a corner of a convex obstacle, with p_t beyond one face and p_{t+1}
beyond the next, it is the sign of a cross product, bilinear in the two positions. So no
single LP decides it. Three linear programs bracket it, each over the states x_0..x_N
(start, dynamics, input and state bounds, workspace, goal), in HiGHS:

* the *point LP* (necessary): every sample in its region and every point
  ``p_t + (f / DENOM)(p_{t+1} - p_t)`` of the plan in its region (linear in the two
  states). Infeasible: the plan is refuted for every segment-safe trajectory; the
  conflict is the support of HiGHS's Farkas certificate (dual ray), checked by an LP
  over exactly those literals, shrunk by a deletion filter, with the start and the goal
  dropped where an LP proves it unneeded (then it holds at every time shift, as
  CON-PLAN's). Feasible: its trajectory's segments are checked exactly
  (:func:`~plansynth.reach.lazy.bounds.depth.segment_depth`: how deep a segment enters a convex obstacle piece, from the
  breakpoints of a concave piecewise-linear function); within
  :data:`ACCEPT_DEPTH` of touching, the plan is realised.
* the *separating LP* (sufficient): the point LP plus, for each piece of a segment
  (between consecutive points of the plan) that the last solution drove into an
  obstacle, both ends of the piece beyond one supporting line of that obstacle: the
  face, or in 2-D the line through a vertex along the piece, that the solution violates
  least (a half-space is convex, so the piece misses the obstacle). Repeated while new
  pieces cut in, up to :data:`TIGHTEN_ROUNDS` times (sequential linear programming); a
  feasible one realises the plan.
* otherwise the deepest point of each cutting segment becomes a new point along every
  segment (:class:`~plansynth.reach.lazy.segments.Refinement`), which cuts the solution
  off; when no new point is left (:data:`~plansynth.reach.lazy.segments.MAX_POINTS`, or
  the grid of fractions is used up there) the plan is blocked *without a proof*
  (``undecided``; the planner then claims neither ``infeasible`` nor a minimal horizon).

A plan without points (a plain region tuple: the re-timed and compressed plans of
:mod:`~plansynth.reach.lazy.minimal`) is checked the same way over its samples; it is
never blocked without a proof.

Obstacle faces flush with the workspace's boundary are left out of the depth (a
zero-width slit is no free space for the decomposition: see
:mod:`plansynth.reach.lazy.claims`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import convex_pieces
from plansynth.reach.lazy.bounds import step_reach
from plansynth.reach.lazy.bounds.depth import segment_depth
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.pointlp import PointLP, Vias
from plansynth.reach.lazy.segments import DENOM, MAX_POINTS, Refinement, SegmentPlan
from plansynth.reach.lazy.transit import TransitCheck
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "SegmentTheory",
    "ClosedConflict",
    "PointLP",
    "ObstaclePiece",
    "ACCEPT_DEPTH",
    "TIGHTEN_ROUNDS",
    "FILTER_MAX",
]

#: How deep a segment may enter an obstacle and still count as touching it (below the
#: validator's default tolerance, 1e-6; HiGHS's feasibility tolerance is 1e-7).
ACCEPT_DEPTH = 2e-7
#: Rounds of the separating LP (see the module docstring).
TIGHTEN_ROUNDS = 4
#: The deletion filter runs on conflicts of at most this many literals.
FILTER_MAX = 40


class ObstaclePiece:
    """A convex obstacle piece: (H, h) without faces flush with the workspace's boundary,
    its bounding box and (2-D) its vertices."""

    def __init__(
        self, H: np.ndarray, h: np.ndarray, ws_lo: np.ndarray, ws_hi: np.ndarray, *, slits: bool = True
    ) -> None:
        top = np.sum(np.maximum(H * ws_lo, H * ws_hi), axis=1)
        keep = (h < top - 1e-12) if slits else np.ones(len(h), bool)  # beyond a flush face: a slit at most
        self.H_all, self.h_all = H, h
        self.H, self.h = H[keep], h[keep]
        d = H.shape[1]
        if d == 2:
            pts = []
            for i in range(len(h)):
                for j in range(i + 1, len(h)):
                    M = H[[i, j]]
                    if abs(np.linalg.det(M)) < 1e-12:
                        continue
                    v = np.linalg.solve(M, h[[i, j]])
                    if np.all(H @ v <= h + 1e-9 * (1 + np.abs(h))):
                        pts.append(v)
            self.vertices = np.array(pts) if pts else np.zeros((0, 2))
            lo = self.vertices.min(axis=0) if pts else np.full(2, -np.inf)
            hi = self.vertices.max(axis=0) if pts else np.full(2, np.inf)
        else:
            self.vertices = np.zeros((0, d))
            lo, hi = np.full(d, -np.inf), np.full(d, np.inf)
            for a in range(d):  # boxes (3-D obstacles are boxes): their face rows
                up = np.nonzero((H[:, a] == 1.0) & (np.abs(H).sum(axis=1) == 1.0))[0]
                dn = np.nonzero((H[:, a] == -1.0) & (np.abs(H).sum(axis=1) == 1.0))[0]
                if up.size:
                    hi[a] = h[up].min()
                if dn.size:
                    lo[a] = -h[dn].max()
        self.lo, self.hi = lo, hi

    def separators(self, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, float]:
        """A half-space ``n.x >= c`` beyond which the piece lies (a face, or in 2-D the
        line through a vertex along b - a) with the widest margin ``min(n.a, n.b) - c``
        for the points a and b (when both cannot be beyond one, the one they violate
        least). In 2-D a segment [a, b] that avoids the piece has one with margin >= 0
        (separating axes: the faces' normals and the segment's)."""
        best: tuple[float, np.ndarray, float] | None = None
        for n, c in zip(self.H_all, self.h_all):  # beyond face f: H_f x >= h_f
            v = min(float(n @ a - c), float(n @ b - c))
            if best is None or v > best[0]:
                best = (v, n, float(c))
        d = b - a
        if len(a) == 2 and len(self.vertices) and float(np.hypot(*d)) > 0:
            for sign in (1.0, -1.0):
                n = sign * np.array([-d[1], d[0]]) / float(np.hypot(*d))
                c = float(np.max(self.vertices @ n))  # the supporting line with the piece below it
                v = min(float(n @ a) - c, float(n @ b) - c)
                if v > best[0]:
                    best = (v, n, c)
        assert best is not None
        return best[1], best[2]


@dataclass(frozen=True)
class ClosedConflict:
    """A conflict whose proof needs a mission plan's closure (``("loop", k)`` or
    ``("rest",)``, see :meth:`PointLP.load`): no trajectory realises its literals
    together with the closure, at its horizon; the mission's DIS-PLAN blocks it with the
    plan's loop or stay selector."""

    conflict: Conflict
    closure: tuple


class SegmentTheory:
    """The :class:`~plansynth.reach.lazy.loop.TheoryChecker` of exact segment transitions
    (see the module docstring). ``transit`` (optional): the transit layer over CON-PLAN
    *without* segment rows (its leg conflicts are about samples only, which every
    segment-safe trajectory keeps in its regions: sound here). ``labels`` (a mission's
    segment reading: name -> the shape a segment reading ``!name`` must stay out of, the
    label grown by its margin): :meth:`check_closed` keeps segment t out of the labels
    ``avoid[t]`` names as it keeps every segment off the obstacles. Counters:
    ``lp_calls``, ``plans_checked``, ``realised`` (plans whose point LP's trajectory was
    segment-safe), ``separated`` (realised by the separating LP), ``refinements``,
    ``undecided``."""

    def __init__(
        self,
        problem: ReachProblem,
        abstraction: Abstraction,
        *,
        transit: TransitCheck | None = None,
        clock: Clock | None = None,
        boxes: Mapping[tuple[int, int], tuple[np.ndarray, ...]] | None = None,
        labels: Mapping[str, object] | None = None,
    ) -> None:
        self.problem = problem
        self.lp = PointLP(problem, abstraction, clock, boxes)
        self.transit = transit
        self.expendable = False
        ws_lo, ws_hi = np.asarray(problem.workspace.lo, float), np.asarray(problem.workspace.hi, float)
        self.pieces = [ObstaclePiece(H, h, ws_lo, ws_hi) for o in problem.obstacles for H, h in convex_pieces(o)]
        self.piece_label: list[str | None] = [None] * len(self.pieces)
        for name, shape in (labels or {}).items():
            for H, h in convex_pieces(shape):
                self.pieces.append(ObstaclePiece(H, h, ws_lo, ws_hi, slits=False))
                self.piece_label.append(name)
        self._closure: tuple | None = None
        self._avoid: Mapping[int, frozenset[str]] = {}
        self.plans_checked = 0
        self.realised = 0
        self.separated = 0
        self.refinements = 0
        self.undecided = 0
        self.conflicts = 0
        self.too_far = 0
        # the regions' bounding boxes and the largest change of position per step (finite)
        down, up = step_reach(problem)
        corners = [np.asarray(r.vertices, float) for r in abstraction.regions]  # (2-D polygons, 3-D boxes)
        finite = bool(np.all(np.isfinite(down)) and np.all(np.isfinite(up)))
        known = bool(corners) and all(len(v) for v in corners)
        self._reach = (np.asarray(down, float), np.asarray(up, float)) if finite and known else None
        self._box_lo = np.array([v.min(axis=0) for v in corners]) if known else None
        self._box_hi = np.array([v.max(axis=0) for v in corners]) if known else None
        self._span = float(np.max(np.asarray(problem.workspace.hi, float) - np.asarray(problem.workspace.lo, float)))

    @property
    def lp_calls(self) -> int:
        return self.lp.lp_calls

    def first_gap(self, a: int, b: int) -> int:
        """The transit layer's (the guide's first leg)."""
        assert self.transit is not None
        return self.transit.first_gap(a, b)

    # ---------------------------------------------------------------- the check
    def check(self, plan: Sequence[int]) -> Feasible | Conflict | Refinement | tuple:
        """:meth:`check_closed` without a closure (reach-avoid)."""
        return self.check_closed(plan)  # type: ignore[return-value]

    def check_closed(
        self,
        plan: Sequence[int],
        closure: tuple | None = None,
        avoid: Mapping[int, frozenset[str]] | None = None,
        vias: Vias | None = None,
    ) -> Feasible | Conflict | ClosedConflict | Refinement | tuple:
        """Realise ``plan`` (a :class:`~plansynth.reach.lazy.segments.SegmentPlan`, or a
        region tuple with its points ``vias``), with a mission plan's ``closure`` and the
        labels each segment must stay out of (``avoid``, t -> names) when given, or answer
        with a sound conflict (a :class:`ClosedConflict` when its proof needs the closure)
        or a :class:`~plansynth.reach.lazy.segments.Refinement` (module docstring)."""
        regions = tuple(int(r) for r in plan)
        decided = vias is not None or isinstance(plan, SegmentPlan)  # DIS-PLAN's plan, not a hint
        if vias is None:
            vias = plan.vias if isinstance(plan, SegmentPlan) else {}
        N = len(regions) - 1
        self._closure = closure
        self._avoid = {} if avoid is None else avoid
        if self.transit is not None:
            known = self.transit.violations(regions, known_only=True)
            if known:
                return tuple(known)
        samples = dict(enumerate(regions))
        far = self._too_far(samples, vias, N)
        if far is not None:
            self.conflicts += 1
            self.too_far += 1
            return far
        self.plans_checked += 1
        sol = self.lp.solve(samples, vias, 0, N, start=True, goal=True, closure=closure)
        if sol is None:
            c = self._conflict(samples, vias, N)
            self.conflicts += 1
            if isinstance(c, ClosedConflict):
                return c
            if self.transit is not None:
                span = (0 if c.anchored_start else c.first_time, N if c.anchored_goal else c.last_time)
                return (c, *self.transit.violations(regions, span))
            return c
        X, U = sol
        cuts = self._cuts(X, vias)
        if not cuts:
            self.realised += 1
            return Feasible(Trajectory(states=X, inputs=U))
        found = self._separated(samples, vias, N, cuts, X)
        if found is not None:
            self.separated += 1
            return found
        new = self._new_fractions(cuts, vias)
        if new:
            self.refinements += 1
            return Refinement(tuple(new))
        if not decided:
            return Refinement(())  # a hint, not DIS-PLAN's plan: nothing to block
        self.undecided += 1
        whole = Conflict(
            tuple(samples.items()),
            anchored_start=True,
            anchored_goal=True,
            horizon=N,
            vias=tuple((t, f, r) for (t, f), r in vias.items()),
        )
        return whole if closure is None else ClosedConflict(whole, closure)

    # ---------------------------------------------------------------- distances
    def _too_far(self, samples: dict[int, int], vias: Vias, N: int) -> Conflict | None:
        """Two points of the plan (samples or points along segments, at times t + f /
        DENOM) whose regions' bounding boxes lie farther apart along some axis than the
        time between them allows, or None: the position moves by at most ``up`` (and
        ``down``) per step along each axis (:func:`~plansynth.reach.lazy.bounds.step_reach`),
        so along a polyline of steps by at most that times the time between two of its
        points. The conflict of the closest such pair in time (two literals, no start or
        goal: it holds at every time shift); no LP."""
        if self._reach is None:
            return None
        down, up = self._reach
        lits = [("s", t, r) for t, r in samples.items()] + [("v", t, f, r) for (t, f), r in vias.items()]
        tau = np.array([g[1] + (g[2] / DENOM if g[0] == "v" else 0.0) for g in lits])
        reg = np.array([g[-1] for g in lits])
        order = np.argsort(tau, kind="stable")
        tau, reg = tau[order], reg[order]
        lo, hi = self._box_lo[reg], self._box_hi[reg]
        dt = tau[None, :] - tau[:, None]  # [i, j]: from point i to the later point j
        rise = lo[None, :, :] - hi[:, None, :]  # the least change along each axis, i -> j
        fall = lo[:, None, :] - hi[None, :, :]
        slack = 1e-9 * (1.0 + self._span)
        bad = np.any((rise > up * dt[:, :, None] + slack) | (fall > down * dt[:, :, None] + slack), axis=2)
        bad &= dt > 0
        if not bad.any():
            return None
        i, j = np.argwhere(bad)[np.argmin(dt[bad])]
        pair = [lits[order[i]], lits[order[j]]]
        times = [g[1] for g in pair] + [g[1] + 1 for g in pair if g[0] == "v"]
        return Conflict(
            tuple((g[1], g[2]) for g in pair if g[0] == "s"),
            anchored_start=False,
            anchored_goal=False,
            horizon=N,
            first_time=min(times),
            last_time=max(times),
            vias=tuple(g[1:] for g in pair if g[0] == "v"),
        )

    # ---------------------------------------------------------------- exact check
    def cuts(self, X: np.ndarray) -> list[tuple[int, float, int, float]]:
        """The segments of the states ``X`` that cut an obstacle piece (see :meth:`_cuts`)."""
        return self._cuts(X, {})

    def _cuts(self, X: np.ndarray, vias: Vias) -> list[tuple[int, float, int, float]]:
        """The segments of ``X`` that enter an obstacle (or a label ``avoid`` keeps them out
        of) deeper than :data:`ACCEPT_DEPTH`: (t, deepest fraction, piece, depth), the
        deepest piece per segment."""
        P = X[:, self.pos]
        if len(P) < 2 or not self.pieces:
            return []
        a, b = P[:-1], P[1:]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        best: dict[int, tuple[int, float, int, float]] = {}
        for k, pc in enumerate(self.pieces):
            if not len(pc.h):
                continue
            near = np.all(lo < pc.hi, axis=1) & np.all(hi > pc.lo, axis=1)
            name = self.piece_label[k]
            if name is not None:  # a label: only the segments that must stay out of it
                near &= np.array([name in self._avoid.get(t, ()) for t in range(len(a))], dtype=bool)
            near = np.nonzero(near)[0]
            if not near.size:
                continue
            depth, s = segment_depth(a[near], b[near], pc.H, pc.h)
            for t, dep, at in zip(near.tolist(), depth.tolist(), s.tolist()):
                if dep > ACCEPT_DEPTH and (t not in best or dep > best[t][3]):
                    best[t] = (t, at, k, dep)
        return sorted(best.values())

    @property
    def pos(self) -> np.ndarray:
        return self.lp.pos

    # ---------------------------------------------------------------- the separating LP
    def _separated(self, samples: dict[int, int], vias: Vias, N: int, cuts: list, X: np.ndarray) -> Feasible | None:
        """The separating LP (module docstring), repeated while new pieces cut in."""
        extra: list[tuple[int, int, np.ndarray, float]] = []
        done: set[tuple[int, int, int]] = set()
        fr = _per_segment(vias)
        for _ in range(TIGHTEN_ROUNDS):
            P = X[:, self.pos]
            for t, s, k, _ in cuts:
                a_f, b_f = _around(fr.get(t, ()), s)
                if (t, a_f, k) in done:
                    continue
                done.add((t, a_f, k))
                pa = P[t] + a_f / DENOM * (P[t + 1] - P[t])
                pb = P[t] + b_f / DENOM * (P[t + 1] - P[t])
                n, c = self.pieces[k].separators(pa, pb)
                extra += [(t, a_f, n, c), (t, b_f, n, c)]
            sol = self.lp.solve(samples, vias, 0, N, start=True, goal=True, extra=extra, closure=self._closure)
            if sol is None:
                return None
            X, U = sol
            cuts = self._cuts(X, vias)
            if not cuts:
                return Feasible(Trajectory(states=X, inputs=U))
        return None

    # ---------------------------------------------------------------- refinement
    def _new_fractions(self, cuts: list, vias: Vias) -> list[tuple[int, int]]:
        """A new point (t, f), f over DENOM, at the deepest point of each cutting segment
        t, on the grid and strictly between the plan's points around it; none for a
        segment whose grid there or :data:`MAX_POINTS` is used up."""
        fr = _per_segment(vias)
        out: list[tuple[int, int]] = []
        for t, s, _, _ in cuts:
            mine = [f for f in fr.get(t, ()) if f < DENOM]
            a, b = _around(mine, s)
            if b - a < 2 or len(mine) >= MAX_POINTS:
                continue
            out.append((t, _simplest(a, b, s)))
        return out

    # ---------------------------------------------------------------- conflicts
    def _conflict(self, samples: dict[int, int], vias: Vias, N: int) -> Conflict | ClosedConflict:
        """The conflict of the infeasible point LP just solved: its Farkas support, checked
        and shrunk (module docstring). Every conflict returned is the literals of an LP
        that HiGHS found infeasible, over the states it claims (with the closure when it
        is among them: then a :class:`ClosedConflict`, start-anchored)."""
        sup = self.lp.support()
        every = {("s", t, r) for t, r in samples.items()} | {("v", t, f, r) for (t, f), r in vias.items()}
        if self._closure is not None:
            every.add(("closure",))
        lits, goal = every, True
        if sup is not None:
            lits, goal = every & sup, ("goal",) in sup
            if not self._infeasible(lits, N, start=True, goal=goal):
                lits, goal = every, True
                self._infeasible(lits, N, start=True, goal=True)  # (known infeasible: load it for the filter)
        if len(lits) <= FILTER_MAX:  # deletion filter, warm-started in the loaded LP
            off: set[tuple] = set()
            for tag in sorted(lits, key=lambda g: (-g[1] if len(g) > 1 else 1, g)):  # the latest first
                if self.lp.run(off | {tag}) is None:
                    off.add(tag)
            lits = lits - off
        span = self.lp.span  # (the states the last infeasible LP used)
        closed = ("closure",) in lits
        start = True
        if not closed and lits and self._infeasible(lits, N, start=False, goal=goal):
            start, span = False, self.lp.span
        if goal and lits and self._infeasible(lits, N, start=start, goal=False):
            goal, span = False, self.lp.span
        c = Conflict(
            tuple((g[1], g[2]) for g in lits if g[0] == "s"),
            anchored_start=start,
            anchored_goal=goal,
            horizon=N,
            first_time=span[0],
            last_time=N if closed else span[1],
            vias=tuple(g[1:] for g in lits if g[0] == "v"),
        )
        return ClosedConflict(c, self._closure) if closed else c

    def _infeasible(self, lits: set[tuple], N: int, *, start: bool, goal: bool) -> bool:
        """Is the point LP of exactly these literals (tags) infeasible, over the states a
        conflict would claim (0 with the start, N with the goal or the closure, else the
        literals' span)? The LP stays loaded."""
        closed = ("closure",) in lits
        times = [g[1] for g in lits if g[0] != "closure"] + [g[1] + 1 for g in lits if g[0] == "v"]
        lo = 0 if start or not times else min(times)
        hi = N if goal or closed or not times else max(times)
        if closed and self._closure is not None and self._closure[0] == "loop":
            lo = min(lo, int(self._closure[1]))
        s = {g[1]: g[2] for g in lits if g[0] == "s"}
        v = {(g[1], g[2]): g[3] for g in lits if g[0] == "v"}
        self.lp.load(s, v, lo, hi, start=start, goal=goal, closure=self._closure if closed else None)
        return self.lp.run() is None


def _around(fractions: Sequence[int], s: float) -> tuple[int, int]:
    """The plan's points (fractions over DENOM, with 0 and DENOM) just below and above s."""
    at = s * DENOM
    below = max([0] + [f for f in fractions if f <= at])
    above = min([DENOM] + [f for f in fractions if f > at])
    if below == above:  # pragma: no cover - (below <= at < above)
        above = below + 1
    return below, above


def _simplest(a: int, b: int, s: float) -> int:
    """A fraction (over DENOM) strictly between a and b, near s: the one with the fewest
    binary digits within a quarter of b - a of s (so that segments share their points
    and a conflict about a point holds at more time shifts), else the nearest to s.

    >>> _simplest(0, DENOM, 0.55) == DENOM // 2, _simplest(DENOM // 2, DENOM, 0.9) == 7 * DENOM // 8
    (True, True)
    """
    at = s * DENOM
    w = (b - a) / 4
    lo, hi = max(a + 1, math.ceil(at - w)), min(b - 1, math.floor(at + w))
    step = DENOM
    while step >= 1:
        f = -(-lo // step) * step  # the first multiple of step at or above lo
        if f <= hi:
            return int(f)
        step //= 2
    return min(max(int(round(at)), a + 1), b - 1)


def _per_segment(vias: Vias) -> dict[int, list[int]]:
    """The plan's fractions per segment, sorted."""
    out: dict[int, list[int]] = {}
    for t, f in vias:
        out.setdefault(t, []).append(f)
    return {t: sorted(fs) for t, fs in out.items()}

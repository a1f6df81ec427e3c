"""Exact segment transitions in DIS-PLAN: points along every segment (beyond Shoukry et
al., CDC 2016, whose DIS-PLAN, Section IV, puts one region per time step and, for
segment safety, keeps each segment in one region).

A segment-safe step may cross several regions: the segment from p_t to p_{t+1} only
has to stay in the free space, which the regions of an exact decomposition cover. So
DIS-PLAN steps between regions one such segment can connect
(:func:`~plansynth.reach.lazy.bounds.segment_adjacency`), and, besides the samples'
variables ``b[t, i]``, it has variables ``v[t, f, i]`` for *points along the segments*:
"the point ``p_t + (f / DENOM) (p_{t+1} - p_t)`` lies in region i", for the fractions f
of a set F_t per segment that grows (:class:`Refinement`). Per point exactly one region,
and from each point to the next along the segment only the regions such a piece can
connect (``segment_adjacency`` at the piece's share of the step; every two points of a segment,
and each point and the two samples, are linked so, not only neighbours: the segment is
straight). Every segment-safe
trajectory has every point of every segment in some region, so every clause here, and
every conflict of the theory (:mod:`plansynth.reach.lazy.segtheory`, an LP over the
samples and the points, necessary for segment safety), holds for it: a refuted horizon
is refuted *for the problem*. The theory accepts a trajectory only when its segments
avoid every obstacle exactly; when a segment of the LP's solution cuts an obstacle, it
asks for the point there, which cuts that solution off. As F_t grows the points'
condition tends to segment safety (the free space is closed), and a trajectory that
keeps a margin from the obstacles is found: complete in the limit, with
:data:`MAX_POINTS` points per segment at most (beyond that the theory gives a plan up
without a proof, and the answer says so).

Fractions are integers over :data:`DENOM` (exact). A conflict that holds at every time
shift is added at the shifts where the segments have the fractions it names (the
others are merely not added, which is sound); every segment starts with
:data:`START_POINTS`, and a refinement adds a point to one segment only, where a
solution cut an obstacle (a corner may need points close together there; the same
points on every segment would multiply DIS-PLAN's size).

>>> from plansynth.reach.lazy.displan import RegionGraph
>>> g = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(2,))
>>> d = SegmentDisPlan(g, lambda scale: g.adjacency, fractions=(32,))
>>> plan = d.plan(2)
>>> plan, sorted(plan.vias)                 # the midpoints of both segments have regions too
((0, 1, 2), [(0, 32), (1, 32)])
>>> all(plan.vias[(t, 32)] in (plan[t], plan[t + 1]) for t in range(2))
True
>>> d.learn(Refinement(((1, 16),)))
>>> d.points(0), d.points(1)
([32], [16, 32])
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from pysat.card import CardEnc, EncType

from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.displan import CARDINALITY_ENCODINGS, PAIRWISE_MAX_REGIONS, DisPlan, RegionGraph, SatOutcome

__all__ = ["DENOM", "MAX_POINTS", "START_POINTS", "Refinement", "SegmentPlan", "SegmentDisPlan", "Adjacency"]

#: Fractions along a segment are f / DENOM, 0 < f < DENOM.
DENOM = 1 << 16
#: Points per segment DIS-PLAN may get at most (then a plan the theory cannot decide is
#: given up without a proof).
MAX_POINTS = 24
#: Points per segment to begin with (the midpoint).
START_POINTS: tuple[int, ...] = ()

Adjacency = tuple[tuple[int, ...], ...]


@dataclass(frozen=True)
class Refinement:
    """The theory's answer when a segment of the LP's solution cuts an obstacle and no
    sufficient LP repairs it: more points along the segments, as (t, f): segment t gets
    the point at fraction f / :data:`DENOM`. Not a refutation: no plan is excluded, the
    points exclude the solution that cut the obstacle."""

    points: tuple[tuple[int, int], ...]


class SegmentPlan(tuple):
    """A plan of :class:`SegmentDisPlan`: the samples' regions r_0..r_N (a tuple, as every
    DIS-PLAN plan) and ``vias[(t, f)]``, the region of the point at fraction f / DENOM of
    the segment from p_t to p_{t+1}."""

    vias: dict[tuple[int, int], int]

    def __new__(cls, regions: Sequence[int], vias: dict[tuple[int, int], int]) -> SegmentPlan:
        plan = super().__new__(cls, tuple(regions))
        plan.vias = dict(vias)
        return plan


class SegmentDisPlan(DisPlan):
    """DIS-PLAN (:class:`~plansynth.reach.lazy.displan.DisPlan`) with points along the
    segments (see the module docstring). ``relation(scale)``: the regions a piece of a
    segment of that share of one step can connect (``segment_adjacency``; ``graph``'s
    adjacency is the one of a whole step). The dense encodings only (not ``paths``).
    ``fractions``: each segment's first points. Counters: ``refinements`` (points added)."""

    def __init__(
        self,
        graph: RegionGraph,
        relation: Callable[[float], Adjacency],
        *,
        fractions: Sequence[int] = START_POINTS,
        cardinality: str = "auto",
        **kw,
    ) -> None:
        if cardinality in ("auto", "paths"):
            cardinality = "pairwise" if graph.n_regions <= PAIRWISE_MAX_REGIONS else "seqcounter"
        super().__init__(graph, cardinality=cardinality, **kw)
        self._relation = functools.lru_cache(maxsize=None)(relation)
        self.first_points = sorted({int(f) for f in fractions if 0 < int(f) < DENOM})
        self._points: list[list[int]] = []  # per encoded segment, its fractions
        self._by_fraction: dict[int, list[Conflict]] = {}  # free conflicts by the fractions they name
        self.refinements = 0

    def points(self, t: int) -> list[int]:
        """The fractions (over DENOM) of the points along segment t (encoded ones)."""
        return list(self._points[t])

    @property
    def most_points(self) -> int:
        """The most points any segment has."""
        return max(map(len, self._points), default=len(self.first_points))

    # -- variables ---------------------------------------------------------------
    def via(self, t: int, f: int, i: int) -> int:
        """v[t, f, i]: the point at fraction f / DENOM of segment t lies in region i."""
        return self.pool.id(("via", t, f, i))

    def _point(self, t: int, f: int, i: int) -> int:
        """The variable of the point at fraction f of segment t in region i (f = 0: the
        sample t, f = DENOM: the sample t + 1)."""
        if f == 0:
            return self.at(t, i)
        if f == DENOM:
            return self.at(t + 1, i)
        return self.via(t, f, i)

    # -- encoding ----------------------------------------------------------------
    def _built_to(self, t: int) -> None:
        # the points of the segments that step t completes come before the free conflicts
        # (which may name them) are instantiated there
        while len(self._points) < t:
            u = len(self._points)
            self._points.append(list(self.first_points))
            for f in self.first_points:
                self._encode_point(u, f)
            cuts = [0, *self.first_points, DENOM]
            for k, a in enumerate(cuts):
                for b in cuts[k + 1 :]:
                    if (a, b) != (0, DENOM):  # (the samples' own transition: DIS-PLAN's graph)
                        self._link(u, a, b)
        super()._built_to(t)

    def _encode_point(self, t: int, f: int) -> None:
        lits = [self.via(t, f, i) for i in range(self.graph.n_regions)]
        enc = CardEnc.equals(
            lits=lits,
            bound=1,
            vpool=self.pool,
            encoding=EncType.pairwise if self.cardinality == "pairwise" else CARDINALITY_ENCODINGS[self.cardinality],
        )
        for c in enc.clauses:
            self._add(c)
        self.sat_clauses_encoding += len(enc.clauses)

    def _link(self, t: int, a: int, b: int) -> None:
        """From the point at fraction a to the one at b of segment t: only the regions a
        piece of (b - a) / DENOM of a step can connect."""
        adj = self._relation((b - a) / DENOM)
        for i in range(self.graph.n_regions):
            self._add([-self._point(t, a, i), self._point(t, b, i)] + [self._point(t, b, j) for j in adj[i]])
        self.sat_clauses_encoding += self.graph.n_regions

    def refine(self, points: Sequence[tuple[int, int]]) -> None:
        """More points along segments, (t, f) each: the point's exactly-one and its links
        to every other point of its segment and to the two samples (a straight piece
        between any two of them is one segment of its share of the step). Points of
        segments not encoded yet, past :data:`MAX_POINTS` or already there are
        ignored."""
        for t, f in sorted({(int(t), int(f)) for t, f in points}):
            if not 0 <= t < len(self._points) or not 0 < f < DENOM:
                continue
            mine = self._points[t]
            if f in mine or len(mine) >= MAX_POINTS:
                continue
            self._encode_point(t, f)
            for g in [0, *mine, DENOM]:
                self._link(t, min(f, g), max(f, g))
            mine.append(f)
            mine.sort()
            self.refinements += 1
            # the conflicts that hold at every shift and name a point at fraction f, now
            # also where their point lands on this segment
            for c in self._by_fraction.get(f, ()):
                for tv, fv, _ in c.vias:
                    if fv == f and 0 <= c.first_time + t - tv and c.last_time + t - tv <= self.built:
                        self._clause(c, t - tv, None)

    def _literals(self, c: Conflict, shift: int) -> list[int] | None:
        lits = []
        for t, i in c.literals:
            if not self.exists(t + shift, i):
                return None
            lits.append(self.at(t + shift, i))
        for t, f, i in c.vias:
            u = t + shift
            if u < 0:
                return None
            if u >= len(self._points):  # pragma: no cover - segments are encoded with their steps
                raise AssertionError(f"segment {u} is not encoded")
            if f not in self._points[u]:
                return None  # (not added where the point is missing: sound, only weaker)
            lits.append(self.via(u, f, i))
        return lits

    def learn(self, conflict: Conflict | Refinement) -> None:  # type: ignore[override]
        """A conflict (as :meth:`DisPlan.learn`) or a request for more points."""
        if isinstance(conflict, Refinement):
            self.refine(conflict.points)
            return
        if not conflict.anchored_start and not conflict.anchored_goal:
            for f in {f for _, f, _ in conflict.vias}:
                self._by_fraction.setdefault(f, []).append(conflict)
        super().learn(conflict)

    # -- solving -----------------------------------------------------------------
    def solve(self, horizon: int, clock=None, *, lowest: int | None = None):
        outcome, plan = super().solve(horizon, clock, lowest=lowest)
        if outcome is not SatOutcome.SAT or plan is None:
            return outcome, plan
        true = {v for v in self.solver.get_model() if v > 0}
        obj = self.pool.obj2id
        vias: dict[tuple[int, int], int] = {}
        for t in range(len(plan) - 1):
            for f in self._points[t]:
                i = next((i for i in range(self.graph.n_regions) if obj.get(("via", t, f, i)) in true), None)
                if i is None:  # pragma: no cover - exactly-one forbids it
                    raise AssertionError(f"SAT model leaves point ({t}, {f}) without a region")
                vias[(t, f)] = i
        return outcome, SegmentPlan(plan, vias)

    def prefer(self, plan: Sequence[int]) -> None:
        """:meth:`DisPlan.prefer`, and each segment's points in the region of its first sample."""
        super().prefer(plan)
        self._extend(len(plan) - 1)
        self.solver.set_phases([self.via(t, f, plan[t]) for t in range(len(plan) - 1) for f in self._points[t]])

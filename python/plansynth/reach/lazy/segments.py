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
from plansynth.reach.lazy.displan import PAIRWISE_MAX_REGIONS, DisPlan, RegionGraph, SatOutcome

__all__ = [
    "DENOM",
    "MAX_POINTS",
    "START_POINTS",
    "Refinement",
    "SegmentPlan",
    "SegmentPoints",
    "SegmentDisPlan",
    "Adjacency",
]

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


class SegmentPoints:
    """The points along the segments of a DIS-PLAN's encoding (see the module docstring):
    variables ``("via", t, f, i)`` in the host's pool, clauses through the host's ``_add``,
    the samples' variables through its ``at(t, i)``. :class:`SegmentDisPlan` and the
    mission's DIS-PLAN (:class:`~plansynth.reach.mission.bmc.MissionDisPlan`) each hold
    one; the host calls :meth:`encode_segment` once sample t + 1 has variables, and hands
    shifted conflicts back through ``reinstantiate(conflict, shift)`` when a refinement
    adds a point that free conflicts name.

    ``ends`` (a mission's segment reading, where a segment reads its own letter): the
    segment's end p_{t+1} is a point of its own (fraction DENOM, variables ``("via", t,
    DENOM, i)``) in a region equal or touching (``near``) r_{t+1}'s, so that two
    segments meeting on a label's edge each read it their way; the links run to it, not
    to the sample. ``on_point(t, f)``: called for every point the host encodes (the host
    adds its clauses about the point, a mission its letters)."""

    def __init__(
        self,
        host,
        n_regions: int,
        relation: Callable[[float], Adjacency],
        *,
        fractions: Sequence[int] = START_POINTS,
        pairwise: bool = True,
        ends: bool = False,
        near: Adjacency | None = None,
        reinstantiate: Callable[[Conflict, int], None] | None = None,
        on_point: Callable[[int, int], None] | None = None,
    ) -> None:
        self.host = host
        self.n = n_regions
        self._relation = functools.lru_cache(maxsize=None)(relation)
        self.first = sorted({int(f) for f in fractions if 0 < int(f) < DENOM})
        self.pairwise = pairwise
        self.ends = bool(ends)
        if self.ends and near is None:
            raise ValueError("end points need the regions' touching relation")
        self.near = near
        self._reinstantiate = reinstantiate
        self._on_point = on_point
        self.points: list[list[int]] = []  # per encoded segment, its fractions
        self._by_fraction: dict[int, list[Conflict]] = {}  # free conflicts by the fractions they name
        self.refinements = 0
        self.clauses = 0

    @property
    def segments(self) -> int:
        return len(self.points)

    @property
    def most(self) -> int:
        """The most points any segment has."""
        return max(map(len, self.points), default=len(self.first))

    def via(self, t: int, f: int, i: int) -> int:
        """v[t, f, i]: the point at fraction f / DENOM of segment t lies in region i."""
        return self.host.pool.id(("via", t, f, i))

    def _point(self, t: int, f: int, i: int) -> int:
        """The variable of the point at fraction f of segment t in region i (f = 0: the
        sample t, f = DENOM: the sample t + 1)."""
        if f == 0:
            return self.host.at(t, i)
        if f == DENOM and not self.ends:
            return self.host.at(t + 1, i)
        return self.via(t, f, i)

    def _add(self, clause: list[int]) -> None:
        self.host._add(clause)
        self.clauses += 1

    def encode_segment(self) -> None:
        """The points of the next segment (its samples have their variables)."""
        u = len(self.points)
        self.points.append(list(self.first))
        for f in self.first:
            self._encode_point(u, f)
        if self.ends:
            self._encode_point(u, DENOM)
            for q in range(self.n):  # p_{t+1} in q and in r_{t+1}: the same region or touching ones
                self._add([-self.via(u, DENOM, q)] + [self.host.at(u + 1, j) for j in (q, *self.near[q])])
        cuts = [0, *self.first, DENOM]
        for k, a in enumerate(cuts):
            for b in cuts[k + 1 :]:
                if (a, b) != (0, DENOM) or self.ends:  # (sample to sample: DIS-PLAN's graph)
                    self._link(u, a, b)

    def _encode_point(self, t: int, f: int) -> None:
        lits = [self.via(t, f, i) for i in range(self.n)]
        enc = CardEnc.equals(
            lits=lits,
            bound=1,
            vpool=self.host.pool,
            encoding=EncType.pairwise if self.pairwise else EncType.seqcounter,
        )
        for c in enc.clauses:
            self._add(c)
        if self._on_point is not None:
            self._on_point(t, f)

    def _link(self, t: int, a: int, b: int) -> None:
        """From the point at fraction a to the one at b of segment t: only the regions a
        piece of (b - a) / DENOM of a step can connect."""
        adj = self._relation((b - a) / DENOM)
        for i in range(self.n):
            self._add([-self._point(t, a, i), self._point(t, b, i)] + [self._point(t, b, j) for j in adj[i]])

    def refine(self, points: Sequence[tuple[int, int]]) -> None:
        """More points along segments, (t, f) each: the point's exactly-one and its links
        to every other point of its segment and to the two samples (a straight piece
        between any two of them is one segment of its share of the step). Points of
        segments not encoded yet, past :data:`MAX_POINTS` or already there are
        ignored."""
        for t, f in sorted({(int(t), int(f)) for t, f in points}):
            if not 0 <= t < len(self.points) or not 0 < f < DENOM:
                continue
            mine = self.points[t]
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
            if self._reinstantiate is not None:
                for c in self._by_fraction.get(f, ()):
                    for tv, fv, _ in c.vias:
                        if fv == f:
                            self._reinstantiate(c, t - tv)

    def remember(self, conflict: Conflict) -> None:
        """A free conflict (no start, no goal) that names points: kept by fraction, for
        the segments that get those points later."""
        if not conflict.anchored_start and not conflict.anchored_goal:
            for f in {f for _, f, _ in conflict.vias}:
                self._by_fraction.setdefault(f, []).append(conflict)

    def has(self, t: int, f: int) -> bool:
        """Is the point at fraction f of segment t encoded?"""
        return 0 <= t < len(self.points) and (f in self.points[t] or (f == DENOM and self.ends))

    def literals(self, vias: Sequence[tuple[int, int, int]], shift: int) -> list[int] | None:
        """The variables of the point literals (t, f, i) shifted by ``shift``, or None when
        a point does not exist there (then the clause is not added: sound, only weaker)."""
        out = []
        for t, f, i in vias:
            u = t + shift
            if u < 0 or not self.has(u, f):
                return None
            out.append(self.via(u, f, i))
        return out

    def read(self, true: set[int], horizon: int) -> dict[tuple[int, int], int]:
        """The points' regions in a model (``true``: its true variables) up to ``horizon``."""
        obj = self.host.pool.obj2id
        vias: dict[tuple[int, int], int] = {}
        for t in range(horizon):
            for f in self.points[t] + ([DENOM] if self.ends else []):
                i = next((i for i in range(self.n) if obj.get(("via", t, f, i)) in true), None)
                if i is None:  # pragma: no cover - exactly-one forbids it
                    raise AssertionError(f"SAT model leaves point ({t}, {f}) without a region")
                vias[(t, f)] = i
        return vias

    def phases(self, plan: Sequence[int]) -> list[int]:
        """Decision phases: each segment's points in the region of its first sample."""
        out = [self.via(t, f, plan[t]) for t in range(len(plan) - 1) for f in self.points[t]]
        if self.ends:
            out += [self.via(t, DENOM, plan[t + 1]) for t in range(len(plan) - 1)]
        return out


class SegmentDisPlan(DisPlan):
    """DIS-PLAN (:class:`~plansynth.reach.lazy.displan.DisPlan`) with points along the
    segments (see the module docstring; :class:`SegmentPoints`). ``relation(scale)``:
    the regions a piece of a segment of that share of one step can connect
    (``segment_adjacency``; ``graph``'s adjacency is the one of a whole step). The dense
    encodings only (not ``paths``). ``fractions``: each segment's first points.
    Counters: ``refinements`` (points added)."""

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
        self.segment_points = SegmentPoints(
            self,
            graph.n_regions,
            relation,
            fractions=fractions,
            pairwise=cardinality == "pairwise",
            reinstantiate=self._reinstantiate,
        )
        super().__init__(graph, cardinality=cardinality, **kw)

    @property
    def refinements(self) -> int:
        return self.segment_points.refinements

    @property
    def most_points(self) -> int:
        """The most points any segment has."""
        return self.segment_points.most

    def points(self, t: int) -> list[int]:
        """The fractions (over DENOM) of the points along segment t (encoded ones)."""
        return list(self.segment_points.points[t])

    def via(self, t: int, f: int, i: int) -> int:
        return self.segment_points.via(t, f, i)

    # -- encoding ----------------------------------------------------------------
    def _built_to(self, t: int) -> None:
        # the points of the segments that step t completes come before the free conflicts
        # (which may name them) are instantiated there
        while self.segment_points.segments < t:
            self.segment_points.encode_segment()
        super()._built_to(t)

    def _reinstantiate(self, c: Conflict, shift: int) -> None:
        if 0 <= c.first_time + shift and c.last_time + shift <= self.built:
            self._clause(c, shift, None)

    def refine(self, points: Sequence[tuple[int, int]]) -> None:
        self.segment_points.refine(points)

    def _literals(self, c: Conflict, shift: int) -> list[int] | None:
        lits = []
        for t, i in c.literals:
            if not self.exists(t + shift, i):
                return None
            lits.append(self.at(t + shift, i))
        vias = self.segment_points.literals(c.vias, shift)
        return None if vias is None else lits + vias

    def learn(self, conflict: Conflict | Refinement) -> None:  # type: ignore[override]
        """A conflict (as :meth:`DisPlan.learn`) or a request for more points."""
        if isinstance(conflict, Refinement):
            self.refine(conflict.points)
            return
        self.segment_points.remember(conflict)
        super().learn(conflict)

    # -- solving -----------------------------------------------------------------
    def solve(self, horizon: int, clock=None, *, lowest: int | None = None):
        outcome, plan = super().solve(horizon, clock, lowest=lowest)
        if outcome is not SatOutcome.SAT or plan is None:
            return outcome, plan
        true = {v for v in self.solver.get_model() if v > 0}
        return outcome, SegmentPlan(plan, self.segment_points.read(true, len(plan) - 1))

    def prefer(self, plan: Sequence[int]) -> None:
        """:meth:`DisPlan.prefer`, and each segment's points in the region of its first sample."""
        super().prefer(plan)
        self._extend(len(plan) - 1)
        self.solver.set_phases(self.segment_points.phases(plan))

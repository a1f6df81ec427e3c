"""The abstraction that respects labels.

The convex decomposition of the free space (:func:`plansynth.reach.abstraction.abstract`,
Shoukry et al., CDC 2016, Section III) is refined by the label boundaries so that every
region lies inside or outside each label (interiors disjoint). A region sequence then
fixes which labels hold at every sample, and, with segment safety (the segment
[p_t, p_{t+1}] lies in region r_t), along every segment too.

Refinement, per region and label: a convex label splits a region into the part inside
it and at most one convex piece outside per label edge (cut off one supporting
half-plane at a time); a non-convex polygon label cuts the region along the supporting
line of every edge that crosses it, after which no piece crosses the label's boundary,
so each lies inside or outside it. Adjacency is inherited: two pieces are adjacent
when they come from the same or from adjacent regions and share an edge of positive
length (collinear, overlapping edges, within a tolerance relative to the workspace).

>>> from plansynth.reach.problem import Box, ReachProblem
>>> from plansynth.reach.dynamics import single_integrator
>>> p = ReachProblem(workspace=Box((0, 0), (4, 4)), obstacles=(), goal=None,
...     dynamics=single_integrator(2, 1.0), start=[0.5, 0.5], input_bound=1.0,
...     labels=(("a", Box((1, 1), (2, 2))),), mission="F a")
>>> la = label_abstraction(p)
>>> la.n_regions, sorted(sum((list(s) for s in la.labels_of), []))
(5, ['a'])
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from shapely.geometry import Point
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.abstraction.regions import region_from_cycle
from plansynth.reach.geometry import Box, Polygon, Shape, halfspaces, is_convex, polygon_halfspaces
from plansynth.reach.problem import ReachProblem

__all__ = ["LabelledAbstraction", "label_abstraction", "clip", "planning_problem"]


def planning_problem(problem: ReachProblem) -> ReachProblem:
    """The problem the reach-avoid machinery (decomposition, CON-PLAN) plans in for a
    mission: the goal replaced by the whole workspace, so that "p_N in the goal" holds
    for every position and the mission alone constrains the plan."""
    return replace(problem, goal=problem.workspace)


Pt = tuple[float, float]


@dataclass(frozen=True, eq=False)
class LabelledAbstraction:
    """Regions refined by the labels: ``abstraction`` (its ``goal_regions`` are all
    regions: a mission has no fixed goal), ``labels_of[i]`` the labels region i lies
    in, ``parent[i]`` the region of the unrefined decomposition it came from."""

    abstraction: Abstraction
    names: tuple[str, ...]
    labels_of: tuple[frozenset[str], ...]
    parent: tuple[int, ...]

    @property
    def n_regions(self) -> int:
        return self.abstraction.n_regions

    def regions_with(self, name: str) -> tuple[int, ...]:
        return tuple(i for i, s in enumerate(self.labels_of) if name in s)


def clip(poly: Sequence[Pt], n: np.ndarray, c: float) -> list[Pt]:
    """Sutherland-Hodgman: the part of the convex polygon ``poly`` with ``n . p <= c``.

    >>> clip([(0, 0), (2, 0), (2, 2), (0, 2)], np.array([1.0, 0.0]), 1.0)
    [(0, 0), (1.0, 0.0), (1.0, 2.0), (0, 2)]
    """
    out: list[Pt] = []
    k = len(poly)
    for i in range(k):
        p, q = poly[i], poly[(i + 1) % k]
        fp = n[0] * p[0] + n[1] * p[1] - c
        fq = n[0] * q[0] + n[1] * q[1] - c
        if fp <= 0:
            out.append(p)
        if (fp < 0 < fq) or (fq < 0 < fp):
            t = float(fp / (fp - fq))
            out.append((float(p[0] + t * (q[0] - p[0])), float(p[1] + t * (q[1] - p[1]))))
    return out


def _area(poly: Sequence[Pt]) -> float:
    if len(poly) < 3:
        return 0.0
    s = 0.0
    for i in range(len(poly)):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % len(poly)]
        s += x0 * y1 - x1 * y0
    return abs(0.5 * s)


def _split_convex(piece: list[Pt], H: np.ndarray, h: np.ndarray, tiny: float) -> list[list[Pt]]:
    """``piece`` cut into the part inside the convex ``{H p <= h}`` and the convex parts
    outside it (one per half-plane, each cut off before the next)."""
    out = []
    rest = piece
    for n, c in zip(H, h):
        outside = clip(rest, -n, -c)
        if _area(outside) > tiny:
            out.append(outside)
            rest = clip(rest, n, c)
        if _area(rest) <= tiny:
            return out
    out.append(rest)
    return out


def _split_lines(piece: list[Pt], H: np.ndarray, h: np.ndarray, tiny: float) -> list[list[Pt]]:
    pieces = [piece]
    for n, c in zip(H, h):
        nxt = []
        for pc in pieces:
            a, b = clip(pc, n, c), clip(pc, -n, -c)
            if _area(a) > tiny and _area(b) > tiny:
                nxt += [a, b]
            else:
                nxt.append(pc)
        pieces = nxt
    return pieces


def _label_rows(shape: Shape) -> tuple[np.ndarray, np.ndarray, bool]:
    if is_convex(shape):
        H, h = halfspaces(shape)
        return H, h, True
    assert isinstance(shape, Polygon)
    H, h = polygon_halfspaces(np.array(shape.vertices))
    return H, h, False


def _adjacent(a: list[Pt], b: list[Pt], tol: float) -> bool:
    """Do the convex polygons share an edge piece longer than ``tol``? (Plain float
    arithmetic: a region pair's handful of edges in numpy, one small array per vertex,
    was half the time of :func:`label_abstraction`.)"""
    na, nb = len(a), len(b)
    for i in range(na):
        px, py = a[i]
        qx, qy = a[(i + 1) % na]
        ex, ey = qx - px, qy - py
        L = math.hypot(ex, ey)
        if L <= tol:
            continue
        ux, uy = ex / L, ey / L
        nx, ny = -uy, ux
        for j in range(nb):
            rx, ry = b[j][0] - px, b[j][1] - py
            sx, sy = b[(j + 1) % nb][0] - px, b[(j + 1) % nb][1] - py
            if abs(nx * rx + ny * ry) > tol or abs(nx * sx + ny * sy) > tol:
                continue
            ur, us = ux * rx + uy * ry, ux * sx + uy * sy
            lo = max(0.0, min(ur, us))
            hi = min(L, max(ur, us))
            if hi - lo > tol:
                return True
    return False


def label_abstraction(problem: ReachProblem, base: Abstraction | None = None) -> LabelledAbstraction:
    """Refine ``base`` (default: :func:`abstract` of the problem) by the problem's
    mission labels (``problem.mission_labels``: the labels and the goal). 2-D only."""
    t0 = time.perf_counter()
    if base is None:
        base = abstract(planning_problem(problem))
    labels = problem.mission_labels
    names = tuple(labels)
    ws = problem.workspace
    scale = max(h - l for l, h in zip(ws.lo, ws.hi))
    tiny = 1e-10 * scale * scale
    tol = 1e-7 * scale
    pieces: list[list[Pt]] = []
    parent: list[int] = []
    for reg in base.regions:
        cur = [[(float(x), float(y)) for x, y in reg.vertices]]
        for name in names:
            H, h, convex = _label_rows(labels[name])
            nxt = []
            for pc in cur:
                nxt += _split_convex(pc, H, h, tiny) if convex else _split_lines(pc, H, h, tiny)
            cur = nxt
        for pc in cur:
            pieces.append(pc)
            parent.append(reg.index)
    regions = [region_from_cycle(i, pc) for i, pc in enumerate(pieces)]
    geoms = {n: (ShPolygon(labels[n].vertices) if isinstance(labels[n], Polygon) else None) for n in names}
    labels_of = []
    for r in regions:
        c = r.center
        inside = set()
        for n in names:
            s = labels[n]
            if isinstance(s, Box):
                if all(l < x < hh for l, hh, x in zip(s.lo, s.hi, c)):
                    inside.add(n)
            elif geoms[n].contains(Point(float(c[0]), float(c[1]))):
                inside.add(n)
        labels_of.append(frozenset(inside))
    near = {(i, j) for i in range(base.n_regions) for j in (i, *base.adjacency[i])}
    nbrs: list[list[int]] = [[] for _ in regions]
    verts = [[(float(x), float(y)) for x, y in r.vertices.tolist()] for r in regions]
    boxes = [
        (min(x for x, _ in v) - tol, min(y for _, y in v) - tol, max(x for x, _ in v) + tol, max(y for _, y in v) + tol)
        for v in verts
    ]
    for i in range(len(regions)):
        bi = boxes[i]
        for j in range(i + 1, len(regions)):
            if (parent[i], parent[j]) not in near:
                continue
            bj = boxes[j]
            if bi[2] < bj[0] or bi[3] < bj[1] or bj[2] < bi[0] or bj[3] < bi[1]:
                continue
            if _adjacent(verts[i], verts[j], tol):
                nbrs[i].append(j)
                nbrs[j].append(i)
    start = problem.start_position
    start_regions = tuple(r.index for r in regions if r.contains(start, 1e-9 * scale))
    abstraction = Abstraction(
        regions=tuple(regions),
        adjacency=tuple(tuple(sorted(n)) for n in nbrs),
        start_regions=start_regions,
        goal_regions=tuple(range(len(regions))),
        seconds=base.seconds + time.perf_counter() - t0,
        method=f"{base.method}+labels",
        candidates=base.candidates,
        exact=base.exact,  # the pieces tile the base regions: they cover what those cover
    )
    return LabelledAbstraction(abstraction, names, tuple(labels_of), tuple(parent))

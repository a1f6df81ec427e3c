"""The geometry kernel of the independent validator (:mod:`plansynth.reach.validate`,
whose docstring states what it checks): whether a point or a segment enters an
obstacle's interior deeper than the tolerance (boxes exactly, polygons by shapely; a
disc robot by its clearance, a box robot by the swept box), and whether a point lies in
a shape. Like the validator, it knows nothing of the planner.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.geometry import Box, Shape, halfspaces
from plansynth.reach.problem import ReachProblem

__all__ = [
    "BOX_CHUNK",
    "hits_all",
    "hits_table",
    "in_shape",
    "obstacle_checks",
    "segment_enters_open_box",
    "segments_enter_open_box",
]


def segment_enters_open_box(p: np.ndarray, q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> bool:
    """Does the closed segment p-q meet the open box (lo, hi)? (Liang-Barsky, strict.)"""
    if np.any(lo >= hi):
        return False
    t0, t1 = -np.inf, np.inf
    d = q - p
    for k in range(len(p)):
        if d[k] == 0.0:
            if not lo[k] < p[k] < hi[k]:
                return False
            continue
        a, b = (lo[k] - p[k]) / d[k], (hi[k] - p[k]) / d[k]
        if a > b:
            a, b = b, a
        t0, t1 = max(t0, a), min(t1, b)
    return t0 < t1 and t0 < 1.0 and t1 > 0.0


def segments_enter_open_box(P: np.ndarray, Q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """:func:`segment_enters_open_box` for every segment P[i]-Q[i] at once (the same
    arithmetic, per axis over all segments)."""
    n = len(P)
    if np.any(lo >= hi) or n == 0:
        return np.zeros(n, dtype=bool)
    ok = np.ones(n, dtype=bool)
    t0, t1 = np.full(n, -np.inf), np.full(n, np.inf)
    D = Q - P
    for k in range(P.shape[1]):
        d, p = D[:, k], P[:, k]
        still = d == 0.0
        ok &= ~still | ((lo[k] < p) & (p < hi[k]))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            a, b = (lo[k] - p) / d, (hi[k] - p) / d
        a, b = np.where(still, -np.inf, np.minimum(a, b)), np.where(still, np.inf, np.maximum(a, b))
        t0, t1 = np.maximum(t0, a), np.minimum(t1, b)
    return ok & (t0 < t1) & (t0 < 1.0) & (t1 > 0.0)


def hits_all(ob: Any, P: np.ndarray, Q: np.ndarray | None = None) -> np.ndarray:
    """``ob.hits(P[i], Q[i])`` (``Q`` None: ``ob.hits(P[i])``) for every i, vectorised for
    box obstacles."""
    if isinstance(ob, _Obstacle) and ob.geom is None:
        return segments_enter_open_box(P, P if Q is None else Q, ob.lo, ob.hi)
    if Q is None:
        return np.array([ob.hits(p) for p in P], dtype=bool)
    return np.array([ob.hits(p, q) for p, q in zip(P, Q)], dtype=bool)


#: Box obstacles tested against all segments at once, this many at a time (a prefilter
#: table of chunk x segments x axes booleans).
BOX_CHUNK = 256


def hits_table(obstacles: Sequence[Any], P: np.ndarray, Q: np.ndarray | None = None) -> np.ndarray:
    """``hits_all(ob, P, Q)`` for every obstacle, as an (obstacles x segments) table. Box
    obstacles go together: a segment can meet an open box only if its bounding box does
    (strictly, on every axis), so the exact test of :func:`segments_enter_open_box` runs
    only on the (box, segment) pairs that pass that filter; the others one by one."""
    Q = P if Q is None else Q
    out = np.zeros((len(obstacles), len(P)), dtype=bool)
    boxes = [i for i, ob in enumerate(obstacles) if isinstance(ob, _Obstacle) and ob.geom is None]
    for i in set(range(len(obstacles))) - set(boxes):
        out[i] = hits_all(obstacles[i], P, Q)
    if not boxes or len(P) == 0:
        return out
    smin, smax = np.minimum(P, Q), np.maximum(P, Q)
    for c in range(0, len(boxes), BOX_CHUNK):
        idx = np.array(boxes[c : c + BOX_CHUNK])
        lo = np.array([obstacles[i].lo for i in idx])
        hi = np.array([obstacles[i].hi for i in idx])
        near = np.all((smax[None, :, :] > lo[:, None, :]) & (smin[None, :, :] < hi[:, None, :]), axis=2)
        for b in np.flatnonzero(near.any(axis=1)):
            seg = np.flatnonzero(near[b])
            out[idx[b], seg] = segments_enter_open_box(P[seg], Q[seg], lo[b], hi[b])
    return out


class _Obstacle:
    """One obstacle shrunk by ``tol``: "inside deeper than tol" = meets the open shrunk set."""

    def __init__(self, shape: Shape, tol: float) -> None:
        self.shape = shape
        if isinstance(shape, Box):
            self.lo = np.array(shape.lo) + tol
            self.hi = np.array(shape.hi) - tol
            self.geom = None
        else:
            poly = ShPolygon(shape.vertices)
            self.geom = poly.buffer(-tol, join_style="mitre") if tol > 0 else poly
            shapely.prepare(self.geom)

    def hits(self, p: np.ndarray, q: np.ndarray | None = None) -> bool:
        if q is None:
            q = p
        if self.geom is None:
            return segment_enters_open_box(p, q, self.lo, self.hi)
        if self.geom.is_empty:
            return False
        g = Point(p[0], p[1]) if np.array_equal(p, q) else LineString([p[:2], q[:2]])
        # interiors meet: DE-9IM "T********"
        return bool(shapely.relate_pattern(self.geom, g, "T********"))


class _DiscClearance:
    """A disc robot of radius R against one obstacle: a sample or a segment is too close
    when its Euclidean distance to the obstacle is below R - tol, or it meets the
    obstacle's interior deeper than tol (as for a point robot: with R <= tol the
    distance test alone would never fire)."""

    def __init__(self, shape: Shape, radius: float, tol: float) -> None:
        from plansynth.reach.geometry import shape_to_shapely

        self.geom = shape_to_shapely(shape)
        shapely.prepare(self.geom)
        self.inner = self.geom.buffer(-tol, join_style="mitre") if tol > 0 else self.geom
        if not self.inner.is_empty:
            shapely.prepare(self.inner)
        self.limit = radius - tol

    def hits(self, p: np.ndarray, q: np.ndarray | None = None) -> bool:
        g = Point(p[0], p[1]) if q is None or np.array_equal(p, q) else LineString([p[:2], q[:2]])
        if self.geom.distance(g) < self.limit:
            return True
        return (not self.inner.is_empty) and bool(shapely.relate_pattern(self.inner, g, "T********"))


class _SweptBox:
    """A box robot against a polygon obstacle: the robot's box at a sample, or the area
    it sweeps along a segment (the convex hull of the boxes at both ends), must not meet
    the obstacle's interior deeper than tol."""

    def __init__(self, shape: Shape, half: tuple[float, ...], tol: float) -> None:
        poly = ShPolygon(shape.vertices)  # type: ignore[union-attr]
        self.geom = poly.buffer(-tol, join_style="mitre") if tol > 0 else poly
        shapely.prepare(self.geom)
        self.h = np.array(half[:2])

    def hits(self, p: np.ndarray, q: np.ndarray | None = None) -> bool:
        if self.geom.is_empty:
            return False
        pts = [p[:2]] if q is None else [p[:2], q[:2]]
        corners = [
            c + s * self.h
            for c in pts
            for s in (np.array([-1, -1]), np.array([1, -1]), np.array([1, 1]), np.array([-1, 1]))
        ]
        body = shapely.MultiPoint([tuple(c) for c in corners]).convex_hull
        return bool(shapely.relate_pattern(self.geom, body, "T********"))


def obstacle_checks(problem: ReachProblem, tol: float) -> list:
    """One checker per obstacle, for the point robot or the problem's sized robot."""
    robot = problem.robot_shape
    if robot is None or robot.is_point:
        return [_Obstacle(o, tol) for o in problem.obstacles]
    out: list = []
    for o in problem.obstacles:
        if robot.radius is not None:
            out.append(_DiscClearance(o, robot.radius, tol))
        elif isinstance(o, Box):
            h = robot.half_extent
            out.append(
                _Obstacle(Box(tuple(l - e for l, e in zip(o.lo, h)), tuple(u + e for u, e in zip(o.hi, h))), tol)
            )  # exact
        else:
            out.append(_SweptBox(o, robot.half_extent, tol))  # type: ignore[arg-type]
    return out


def in_shape(shape: Shape, p: np.ndarray, tol: float) -> bool:
    if isinstance(shape, Box):
        return bool(np.all(p >= np.array(shape.lo) - tol) and np.all(p <= np.array(shape.hi) + tol))
    H, h = halfspaces(shape)
    return bool(np.all(H @ p <= h + tol))

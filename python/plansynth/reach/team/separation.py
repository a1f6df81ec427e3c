"""The separation between robots, and between a robot and a moving obstacle, exactly
(the semantics of a team problem's ``separation``; cf. the SMC encoding of Shoukry et
al., CDC 2017, Section IV, whose robots keep ``|x_i - x_j|_inf >= d``).

Two shapes placed at ``p_i`` and ``p_j`` keep the separation ``d`` in a norm with unit
ball ``P`` (a centrally symmetric convex polygon; ``None``: the infinity norm) when no
point of one lies within norm-distance ``d`` of the other, i.e. when the relative
position ``z = p_i - p_j`` lies outside the open *zone*

    ``int(d P + K_i + (-K_j))``

(Minkowski sums; ``K`` a robot's extent around its reference point, or an obstacle's
shape). A disc of radius R is not a polygon: the zone is then the set of points at
Euclidean distance below ``R`` (the radii summed) from the polygon ``d P + boxes``,
which is exactly ``d P + boxes + disc``. :class:`Zone` holds the polygon's half-spaces
and ``R``; :meth:`Zone.intrusion` measures how deep a straight relative motion
``z0 -> z1`` enters the zone (positive: it enters).

This module is the problem's definition, used at the door (the robots' starts) and by
the independent team validator (:mod:`plansynth.reach.team.validate`); the planners
encode the zones their own way (:mod:`plansynth.reach.team.geometry`: the facets of an
outer polygon, one side held per step) and never call this module.

>>> z = Zone(np.array([[1.0, 0], [0, 1], [-1, 0], [0, -1]]), np.array([0.5, 0.5, 0.5, 0.5]), 0.0)
>>> round(z.intrusion(np.array([-2.0, 0.1]), np.array([2.0, 0.1])), 9)   # passes through the middle
0.4
>>> z.intrusion(np.array([-2.0, 0.6]), np.array([2.0, 0.6])) < 0         # passes above it
True
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPoint

__all__ = ["Zone", "minkowski_vertices", "zone_of"]


@dataclass(frozen=True, eq=False)
class Zone:
    """The open set ``{z : dist_2(z, {H z <= h}) < radius}`` (``radius`` 0: the
    polygon's interior). Rows of ``H`` have unit norm."""

    H: np.ndarray
    h: np.ndarray
    radius: float

    def intrusion(self, z0: np.ndarray, z1: np.ndarray) -> float:
        """How far the segment z0 -> z1 enters the zone: with radius 0, the largest depth
        ``min_k (h_k - H_k z)`` over the segment; with a radius, ``radius`` minus the
        segment's Euclidean distance to the polygon (plus the depth when it meets it).
        Positive: the segment enters the zone (by that much)."""
        return float(self.intrusions(np.asarray(z0, float)[None, :], np.asarray(z1, float)[None, :])[0])

    def polygon(self) -> shapely.Geometry:
        """The polygon ``{H z <= h}`` as a shapely geometry (the zone is its interior
        grown by ``radius``; empty when it has no area)."""
        if float(np.max(self.h + self.h[_opposite_rows(self.H)])) <= 0.0:
            return shapely.Polygon()
        return shapely.Polygon(_polygon_vertices(self.H, self.h))

    def intrusions(self, Z0: np.ndarray, Z1: np.ndarray) -> np.ndarray:
        """:meth:`intrusion` of each segment ``Z0[s] -> Z1[s]`` (rows)."""
        depth = _largest_depths(self.H, self.h, np.asarray(Z0, float), np.asarray(Z1, float))
        if self.radius <= 0.0:
            return depth
        out = self.radius + depth
        poly = shapely.Polygon(_polygon_vertices(self.H, self.h))
        for s in np.flatnonzero(depth < 0.0):
            a, b = Z0[s], Z1[s]
            geom = shapely.Point(*a) if np.array_equal(a, b) else LineString([tuple(a), tuple(b)])
            out[s] = self.radius - float(poly.distance(geom))
        return out


def _largest_depths(H: np.ndarray, h: np.ndarray, Z0: np.ndarray, Z1: np.ndarray) -> np.ndarray:
    """Per segment, ``max_{s in [0, 1]} min_k (h_k - H_k z(s))``: a concave piecewise
    linear function of s, so its maximum is at an end or where two of its lines cross."""
    c = h[None, :] - Z0 @ H.T  # (T, K): value at s = 0 per facet
    g = -((Z1 - Z0) @ H.T)  # (T, K): slope per facet
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (c[:, None, :] - c[:, :, None]) / (g[:, :, None] - g[:, None, :])  # (T, K, K)
    s = s.reshape(len(c), -1)
    s = np.where(np.isfinite(s) & (s > 0.0) & (s < 1.0), s, 0.0)
    cand = np.concatenate([np.zeros((len(c), 1)), np.ones((len(c), 1)), s], axis=1)  # (T, C)
    vals = np.min(c[:, None, :] + cand[:, :, None] * g[:, None, :], axis=2)  # (T, C)
    return vals.max(axis=1)


def _opposite_rows(H: np.ndarray) -> np.ndarray:
    """Per row the row closest to its opposite (the width of the polygon across it is
    ``h_k + h_opposite``)."""
    return np.argmin(H @ H.T, axis=1)


def _polygon_vertices(H: np.ndarray, h: np.ndarray) -> list[tuple[float, float]]:
    """The vertices of the bounded 2-D polygon ``{H z <= h}``, by intersecting
    consecutive facets sorted by angle (every facet is an edge: the zones are hulls)."""
    ang = np.arctan2(H[:, 1], H[:, 0])
    order = np.argsort(ang)
    pts = []
    for a, b in zip(order, np.roll(order, -1)):
        M = np.array([H[a], H[b]])
        pts.append(tuple(np.linalg.solve(M, np.array([h[a], h[b]]))))
    return pts


def minkowski_vertices(*vertex_sets: np.ndarray) -> np.ndarray:
    """The vertices (CCW) of the convex hull of the Minkowski sum of the point sets.

    >>> minkowski_vertices(np.array([[-1.0, -1], [1, -1], [1, 1], [-1, 1]]), np.zeros((1, 2))).tolist()
    [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
    """
    pts = np.zeros((1, vertex_sets[0].shape[1]))
    for vs in vertex_sets:
        pts = (pts[:, None, :] + np.asarray(vs, float)[None, :, :]).reshape(-1, pts.shape[1])
    hull = MultiPoint([tuple(p) for p in pts]).convex_hull
    if hull.geom_type != "Polygon":
        return np.zeros((1, pts.shape[1]))
    ring = shapely.geometry.polygon.orient(hull, 1.0).exterior.coords[:-1]
    return _from_lowest(np.asarray(ring, float))


def _from_lowest(v: np.ndarray) -> np.ndarray:
    """The CCW ring started at its lowest-then-leftmost vertex (a canonical order)."""
    i = min(range(len(v)), key=lambda k: (v[k, 1], v[k, 0]))
    return np.roll(v, -i, axis=0)


def zone_of(distance: float, norm_vertices: np.ndarray | None, parts: list[tuple[str, np.ndarray | float]]) -> Zone:
    """The zone of a pair: ``distance`` times the norm's unit ball (``None``: the box
    of the infinity norm), plus each part: ``("box", half_extents)``, ``("polygon",
    vertices)`` or ``("disc", radius)``. In 3-D only boxes (and the infinity norm).

    >>> z = zone_of(0.5, None, [("box", np.array([0.1, 0.2])), ("box", np.array([0.1, 0.2]))])
    >>> z.h.tolist(), z.radius
    ([0.7, 0.9, 0.7, 0.9], 0.0)
    """
    radius = float(sum(float(p) for kind, p in parts if kind == "disc"))
    boxes = [np.asarray(p, float) for kind, p in parts if kind == "box"]
    polys = [np.asarray(p, float) for kind, p in parts if kind == "polygon"]
    d = len(boxes[0]) if boxes else 2
    if norm_vertices is None and not polys:
        half = float(distance) + (np.sum(boxes, axis=0) if boxes else np.zeros(d))
        eye = np.eye(d)
        return Zone(np.vstack([eye, -eye]), np.concatenate([half, half]), radius)
    base = (
        np.asarray(norm_vertices, float) * float(distance)
        if norm_vertices is not None
        else float(distance) * np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    )
    sets = [base] + [np.array([[s0 * b[0], s1 * b[1]] for s0 in (-1, 1) for s1 in (-1, 1)]) for b in boxes] + polys
    verts = minkowski_vertices(*sets)
    if len(verts) < 3:  # no area: nothing is forbidden (points at distance 0)
        eye = np.eye(2)
        return Zone(np.vstack([eye, -eye]), np.zeros(4), radius)
    H, h = [], []
    for a, b in zip(verts, np.roll(verts, -1, axis=0)):
        e = b - a
        n = np.array([e[1], -e[0]]) / float(np.hypot(e[0], e[1]))
        H.append(n)
        h.append(float(n @ a))
    return Zone(np.array(H), np.array(h), radius)

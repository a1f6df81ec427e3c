"""Shapes pushed out or in by a distance: the margins of missions.

A mission's margin r reads a convex label P = {p : H p <= h} (rows of unit norm) at
depth or at distance r: "inside at depth >= r" is the shrunk shape {H p <= h - r} (every
point within r of p lies in P: the Euclidean erosion, exact for a convex shape), "outside
at distance >= r" the complement of the grown shape {H p <= h + r} (each edge pushed out
by r, corners mitred; for a box, the box grown by r along each axis). These are the
polyhedral margins of the temporal-logic planning literature (the robustness of a
conjunction of linear predicates, as STL planners encode it), so a MILP states them
exactly. Obstacles grow the same way when a mission asks for an obstacle margin; a
non-convex obstacle grows by shapely's mitred buffer (each edge pushed out by r).

>>> grown(Box((0, 0), (2, 1)), 0.5), shrunk(Box((0, 0), (2, 1)), 0.25)
(Box(lo=(-0.5, -0.5), hi=(2.5, 1.5)), Box(lo=(0.25, 0.25), hi=(1.75, 0.75)))
>>> shrunk(Box((0, 0), (2, 1)), 0.5) is None
True
>>> [tuple(round(c, 6) for c in v) for v in grown(Polygon(((0, 0), (2, 0), (0, 2))), 1.0).vertices][:2]
[(-1.0, -1.0), (4.414214, -1.0)]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely

from plansynth.reach.geometry import Box, Polygon, Shape, halfspaces, is_convex, shape_to_shapely

__all__ = ["grown", "shrunk", "offset_rows", "clip", "area"]

Pt = tuple[float, float]


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


def offset_rows(shape: Shape, r: float) -> tuple[np.ndarray, np.ndarray]:
    """``(H, h + r)`` of a convex shape ``{H p <= h}`` (unit rows): pushed out by r (in,
    for r < 0)."""
    H, h = halfspaces(shape)
    return H, h + r


def area(poly: Sequence[Pt]) -> float:
    """The area of the polygon ``poly`` (0 for fewer than three vertices)."""
    if len(poly) < 3:
        return 0.0
    s = 0.0
    for i in range(len(poly)):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % len(poly)]
        s += x0 * y1 - x1 * y0
    return abs(0.5 * s)


def _convex_offset(shape: Shape, r: float) -> Shape | None:
    """The convex shape ``{H p <= h + r}`` (None when empty or flat)."""
    if isinstance(shape, Box):
        lo = tuple(v - r for v in shape.lo)
        hi = tuple(v + r for v in shape.hi)
        return Box(lo, hi) if all(a < b for a, b in zip(lo, hi)) else None
    H, h = offset_rows(shape, r)
    xs = [x for x, _ in shape.vertices]
    ys = [y for _, y in shape.vertices]
    pad = abs(r) * 4 + 1.0 + max(max(xs) - min(xs), max(ys) - min(ys))
    poly: list[Pt] = [
        (min(xs) - pad, min(ys) - pad),
        (max(xs) + pad, min(ys) - pad),
        (max(xs) + pad, max(ys) + pad),
        (min(xs) - pad, max(ys) + pad),
    ]
    for n, c in zip(H, h):
        poly = clip(poly, n, float(c))
        if len(poly) < 3:
            return None
    scale = max(max(xs) - min(xs), max(ys) - min(ys))
    if area(poly) <= 1e-12 * scale * scale:
        return None
    return Polygon(tuple((float(x), float(y)) for x, y in poly))


def grown(shape: Shape, r: float) -> Shape:
    """``shape`` with each edge pushed out by ``r >= 0``, corners mitred (a convex shape:
    exactly ``{H p <= h + r}``; a non-convex polygon: shapely's mitred buffer)."""
    if r <= 0:
        return shape
    if is_convex(shape):
        out = _convex_offset(shape, r)
        assert out is not None
        return out
    g = shape_to_shapely(shape).buffer(r, join_style="mitre", mitre_limit=1e6)
    ring = shapely.simplify(shapely.Polygon(g.exterior.coords), 0.0)
    return Polygon(tuple((float(x), float(y)) for x, y in ring.exterior.coords[:-1]))


def shrunk(shape: Shape, r: float) -> Shape | None:
    """The convex ``shape`` with each edge pulled in by ``r >= 0``: ``{H p <= h - r}``,
    the points at depth >= r (None when no such point has area)."""
    if r <= 0:
        return shape
    if not is_convex(shape):
        raise ValueError("shrunk() needs a convex shape")
    return _convex_offset(shape, -r)

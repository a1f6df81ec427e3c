"""The shapes of reach-avoid problems and the small geometry kernel around them
(Shoukry et al., CDC 2016, Section II: a box workspace, obstacles that are boxes or
simple polygons, possibly non-convex, and a convex goal).

:class:`Box` and :class:`Polygon` are frozen values (arrays read-only, equality by
value); :func:`halfspaces` gives the ``H p <= h`` form of a convex shape that CON-PLAN
and the MILPs use; :func:`shape_to_shapely` the shapely geometry the abstraction and
the validator use.

>>> H, h = halfspaces(Box((0, 0), (2, 1)))
>>> H.tolist(), h.tolist()
([[1.0, 0.0], [0.0, 1.0], [-1.0, -0.0], [-0.0, -1.0]], [2.0, 1.0, -0.0, -0.0])
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely.geometry import Polygon as _ShPolygon
from shapely.geometry import box as _sh_box

from plansynth.budget import checkpoint

__all__ = [
    "Box",
    "Polygon",
    "Shape",
    "halfspaces",
    "polygon_halfspaces",
    "is_convex",
    "polygon_problem",
    "convex_pieces",
    "shape_to_shapely",
    "point_in_interior",
    "box_difference",
    "free_measure",
]


def _frozen_array(a: Any, dtype: Any = float) -> np.ndarray:
    arr = np.array(a, dtype=dtype, copy=True)
    arr.flags.writeable = False
    return arr


def _array_key(a: np.ndarray | None) -> Any:
    return None if a is None else (a.shape, a.tobytes())


@dataclass(frozen=True)
class Box:
    """An axis-aligned box ``{p : lo <= p <= hi}``; ``dim = len(lo)``.

    >>> Box((0, 0), (2, 1)).dim
    2
    >>> Box((0, 0), (2, 1)).contains((2, 0.5))
    True
    """

    lo: tuple[float, ...]
    hi: tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "lo", tuple(float(v) for v in self.lo))
        object.__setattr__(self, "hi", tuple(float(v) for v in self.hi))
        if len(self.lo) != len(self.hi):
            raise ValueError(f"box corners of different dimensions: {self.lo} and {self.hi}")

    @property
    def dim(self) -> int:
        return len(self.lo)

    def is_degenerate(self) -> bool:
        """True when some side has zero (or negative) length."""
        return any(not h > l for l, h in zip(self.lo, self.hi))

    def contains(self, p: Sequence[float], tol: float = 0.0) -> bool:
        """Closed containment, enlarged by ``tol`` on every side."""
        return all(l - tol <= x <= h + tol for l, h, x in zip(self.lo, self.hi, p))

    def volume(self) -> float:
        return float(np.prod([h - l for l, h in zip(self.lo, self.hi)]))


@dataclass(frozen=True)
class Polygon:
    """A simple 2-D polygon (possibly non-convex), vertices stored counter-clockwise.

    The constructor reorders clockwise input; it does not check simplicity (the loader
    does, see :func:`polygon_problem`).

    >>> Polygon(((0, 0), (0, 1), (1, 0))).vertices   # given clockwise
    ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0))
    """

    vertices: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        vs = tuple((float(x), float(y)) for x, y in self.vertices)
        if len(vs) >= 2 and vs[0] == vs[-1]:
            vs = vs[:-1]  # a closing repeat of the first vertex is allowed
        if _signed_area(vs) < 0:
            vs = (vs[0],) + tuple(reversed(vs[1:]))
        object.__setattr__(self, "vertices", vs)

    @property
    def dim(self) -> int:
        return 2

    def area(self) -> float:
        return _signed_area(self.vertices)


Shape = Box | Polygon


def _signed_area(vs: Sequence[tuple[float, float]]) -> float:
    s = 0.0
    for i in range(len(vs)):
        x0, y0 = vs[i]
        x1, y1 = vs[(i + 1) % len(vs)]
        s += x0 * y1 - x1 * y0
    return 0.5 * s


def polygon_problem(poly: Polygon) -> str | None:
    """Why ``poly`` is not a proper simple polygon, or None when it is.

    >>> polygon_problem(Polygon(((0, 0), (1, 1), (2, 2))))
    'degenerate polygon (zero area)'
    >>> polygon_problem(Polygon(((0, 0), (2, 2), (2, 0), (0, 2))))
    'self-intersecting polygon'
    """
    vs = poly.vertices
    if len(vs) < 3:
        return f"a polygon needs at least 3 vertices, got {len(vs)}"
    if len(set(vs)) != len(vs):
        return "repeated vertex"
    sh = _ShPolygon(vs)
    if not sh.convex_hull.area > 0:
        return "degenerate polygon (zero area)"
    if not sh.is_valid or not sh.exterior.is_simple:
        return "self-intersecting polygon"
    if sh.area <= 1e-12 * max(1.0, sh.length**2):
        return "degenerate polygon (zero area)"
    return None


def is_convex(shape: Shape) -> bool:
    """Boxes are convex; a polygon is convex when it makes no right turn (CCW order).

    >>> is_convex(Polygon(((0, 0), (2, 0), (1, 1))))
    True
    >>> is_convex(Polygon(((0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2))))
    False
    """
    if isinstance(shape, Box):
        return True
    vs = shape.vertices
    k = len(vs)
    for i in range(k):
        (ax, ay), (bx, by), (cx, cy) = vs[i - 1], vs[i], vs[(i + 1) % k]
        if (bx - ax) * (cy - by) - (by - ay) * (cx - bx) < 0:
            return False
    return True


def halfspaces(shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """``(H, h)`` with ``shape = {p : H p <= h}`` for a convex shape; rows of H have unit norm.

    Raises ValueError for a non-convex polygon.

    >>> H, h = halfspaces(Box((0, 1), (2, 3)))
    >>> H.tolist(), h.tolist()
    ([[1.0, 0.0], [0.0, 1.0], [-1.0, -0.0], [-0.0, -1.0]], [2.0, 3.0, -0.0, -1.0])
    """
    if isinstance(shape, Box):
        d = shape.dim
        eye = np.eye(d)
        H = np.vstack([eye, -eye])
        h = np.concatenate([np.array(shape.hi), -np.array(shape.lo)])
        return H, h
    if not is_convex(shape):
        raise ValueError("halfspaces() needs a convex shape; this polygon is not convex")
    return polygon_halfspaces(np.array(shape.vertices))


def polygon_halfspaces(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half-spaces of a convex CCW polygon: one unit-normal row per non-degenerate edge."""
    rows, rhs = [], []
    k = len(vertices)
    for i in range(k):
        a, b = vertices[i], vertices[(i + 1) % k]
        e = b - a
        nrm = math.hypot(e[0], e[1])
        if nrm == 0.0:
            continue
        n = np.array([e[1], -e[0]]) / nrm  # outward normal of a CCW edge
        rows.append(n)
        rhs.append(float(n @ a))
    return np.array(rows), np.array(rhs)


def convex_pieces(shape: Shape) -> list[tuple[np.ndarray, np.ndarray]]:
    """Half-space forms ``(H, h)`` of convex pieces whose union is ``shape``: a box or a
    convex polygon as it is, a non-convex polygon by shapely's constrained Delaunay
    triangulation (the obstacle pieces of the big-M MILP and of the lazy planner's
    relaxation).

    >>> len(convex_pieces(Box((0, 0), (1, 1))))
    1
    >>> L = Polygon(((0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)))
    >>> len(convex_pieces(L)) >= 2
    True
    """
    if isinstance(shape, Box) or is_convex(shape):
        return [halfspaces(shape)]
    tris = shapely.constrained_delaunay_triangles(shape_to_shapely(shape))
    pieces = []
    for tri in shapely.get_parts(tris):
        checkpoint()  # thousands of triangles: within the budget phase, if any
        coords = list(tri.exterior.coords)[:-1]
        poly = Polygon(tuple((float(x), float(y)) for x, y in coords))
        pieces.append(halfspaces(poly))
    return pieces


def convex_hull(points: np.ndarray) -> shapely.Geometry:
    """The convex hull of 2-D points (rows) as a shapely geometry (a point, a segment or
    a polygon).

    The points go to GEOS once each: its hull of repeated points can keep an inner
    point as a vertex when three are nearly collinear (a polygon that is not convex and
    misses part of the hull; shapely issue 1593), seen with GEOS 3.14 on the Minkowski
    sums that the robust checks build.

    >>> P = np.array([[0.0096664, -0.01626655], [0.00681996, -0.00992106],
    ...               [0.00609915, -0.0050624], [-0.02258551, 0.03125]]) + [5.68292337, 6.09557343]
    >>> len(convex_hull(np.repeat(P, 16, axis=0)).exterior.coords)  # a triangle, closed
    4
    """
    return shapely.convex_hull(shapely.multipoints(np.unique(np.asarray(points, float), axis=0)))


def shape_to_shapely(shape: Shape) -> shapely.Geometry:
    """The 2-D shapely geometry of a shape (boxes must be 2-D)."""
    if isinstance(shape, Box):
        if shape.dim != 2:
            raise ValueError("shapely geometry only for 2-D shapes")
        return _sh_box(shape.lo[0], shape.lo[1], shape.hi[0], shape.hi[1])
    return _ShPolygon(shape.vertices)


# ---------------------------------------------------------------- small geometry kernel


def point_in_interior(shape: Shape, p: Sequence[float], tol: float = 0.0) -> bool:
    """Is ``p`` in the interior of ``shape``, deeper than ``tol``?

    A point on the boundary is not in the interior.

    >>> point_in_interior(Box((0, 0), (1, 1)), (1, 0.5))
    False
    >>> point_in_interior(Polygon(((0, 0), (2, 0), (0, 2))), (0.5, 0.5))
    True
    """
    if isinstance(shape, Box):
        return all(l + tol < x < h - tol for l, h, x in zip(shape.lo, shape.hi, p))
    sh = _ShPolygon(shape.vertices)
    pt = shapely.Point(float(p[0]), float(p[1]))
    if not sh.contains(pt):
        return False
    return tol <= 0.0 or sh.exterior.distance(pt) > tol


def _box_intersection(a: Box, b: Box) -> Box | None:
    lo = tuple(max(x, y) for x, y in zip(a.lo, b.lo))
    hi = tuple(min(x, y) for x, y in zip(a.hi, b.hi))
    if any(not h > l for l, h in zip(lo, hi)):
        return None
    return Box(lo, hi)


def box_difference(a: Box, b: Box) -> list[Box]:
    """``a`` minus the interior of ``b`` as at most 2d interior-disjoint boxes.

    >>> [(x.lo, x.hi) for x in box_difference(Box((0, 0), (3, 1)), Box((1, -1), (2, 2)))]
    [((0.0, 0.0), (1.0, 1.0)), ((2.0, 0.0), (3.0, 1.0))]
    """
    inter = _box_intersection(a, b)
    if inter is None:
        return [a]
    out: list[Box] = []
    lo, hi = list(a.lo), list(a.hi)
    for k in range(a.dim):
        if lo[k] < inter.lo[k]:
            nh = hi.copy()
            nh[k] = inter.lo[k]
            out.append(Box(tuple(lo), tuple(nh)))
        if inter.hi[k] < hi[k]:
            nl = lo.copy()
            nl[k] = inter.hi[k]
            out.append(Box(tuple(nl), tuple(hi)))
        lo[k], hi[k] = inter.lo[k], inter.hi[k]
    return out


def _measure_in_workspace(ws: Box, shape: Shape) -> float:
    if isinstance(shape, Box):
        inter = _box_intersection(ws, shape)
        return 0.0 if inter is None else inter.volume()
    return float(shape_to_shapely(ws).intersection(shape_to_shapely(shape)).area)


def free_measure(ws: Box, obstacles: Sequence[Shape], shape: Shape) -> float:
    """Area (2-D) or volume (3-D) of ``shape`` inside the workspace and outside obstacles.

    Tiny results (below 1e-12 of the workspace measure) count as zero.
    """
    tiny = 1e-12 * ws.volume()
    if ws.dim == 2:
        geom = shape_to_shapely(ws).intersection(shape_to_shapely(shape))
        if obstacles:
            geom = geom.difference(shapely.union_all([shape_to_shapely(o) for o in obstacles]))
        a = float(geom.area)
        return a if a > tiny else 0.0
    assert isinstance(shape, Box)
    first = _box_intersection(ws, shape)
    pieces = [] if first is None else [first]
    for ob in obstacles:
        assert isinstance(ob, Box)
        pieces = [q for pc in pieces for q in box_difference(pc, ob)]
    v = sum(pc.volume() for pc in pieces)
    return v if v > tiny else 0.0

"""The values of the discrete abstraction (Shoukry et al., CDC 2016, Section III): a
convex :class:`Region` of the free space, and the :class:`Abstraction` (regions, their
adjacency graph, start and goal regions) that :func:`~plansynth.reach.abstraction.abstract`
builds; :func:`region_from_cycle` and :func:`region_from_box` make regions of the
constructions' pieces.

>>> r = region_from_box(0, np.array([0.0, 0.0]), np.array([2.0, 1.0]))
>>> r.measure(), r.center.tolist(), r.contains((2.0, 0.5))
(2.0, [1.0, 0.5], True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction.predicates import Pt, ccw, drop_collinear
from plansynth.reach.geometry import polygon_halfspaces

__all__ = ["Region", "Abstraction", "region_from_cycle", "region_from_box"]


@dataclass(frozen=True, eq=False)
class Region:
    """A convex, full-dimensional region ``{p : H p <= h}`` (rows of H have unit norm).

    ``vertices``: in 2-D the CCW polygon (v x 2), in 3-D the 8 box corners.
    Regions compare by identity (they hold arrays).
    """

    index: int
    H: np.ndarray
    h: np.ndarray
    vertices: np.ndarray

    @property
    def dim(self) -> int:
        return int(self.H.shape[1])

    @cached_property
    def center(self) -> np.ndarray:
        """A point strictly inside: the area centroid (2-D) or the box centre (3-D)."""
        v = self.vertices
        if self.dim != 2:
            return (v.min(axis=0) + v.max(axis=0)) / 2
        x, y = v[:, 0], v[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        cross = x * yn - xn * y
        a = cross.sum() / 2
        return np.array([((x + xn) * cross).sum() / (6 * a), ((y + yn) * cross).sum() / (6 * a)])

    def contains(self, p: Sequence[float], tol: float = 1e-9) -> bool:
        """Closed containment with tolerance ``tol``."""
        return bool(np.all(self.H @ np.asarray(p, dtype=float) <= self.h + tol))

    def measure(self) -> float:
        """Area (2-D) or volume (3-D)."""
        v = self.vertices
        if self.dim != 2:
            return float(np.prod(v.max(axis=0) - v.min(axis=0)))
        return float(ShPolygon(v).area)


@dataclass(frozen=True, eq=False)
class Abstraction:
    """The discrete abstraction: regions, their adjacency graph, start and goal regions.

    ``adjacency[i]`` is the sorted tuple of neighbours of region i (symmetric, no
    self-loops). ``start_regions``: regions whose closure contains the start position;
    ``goal_regions``: regions whose closure meets the goal (a face or a point is
    enough: a plan may end there, where the goal's interior beside it is obstacle). ``method`` says
    which construction won; ``candidates`` gives the region count of each one tried.
    ``exact``: the regions cover exactly the free space; False when some finely sampled
    convex obstacle was decomposed around its outer polygon (:func:`outer_polygon`),
    so the regions cover a subset of the free space (sound for plans, which stay in
    the regions, but nothing about the abstraction then bounds the real problem).
    """

    regions: tuple[Region, ...]
    adjacency: tuple[tuple[int, ...], ...]
    start_regions: tuple[int, ...]
    goal_regions: tuple[int, ...]
    seconds: float
    method: str = ""
    candidates: tuple[tuple[str, int], ...] = ()
    exact: bool = True

    @property
    def n_regions(self) -> int:
        return len(self.regions)

    @property
    def n_edges(self) -> int:
        """Number of undirected adjacency edges."""
        return sum(len(a) for a in self.adjacency) // 2

    def regions_containing(self, p: Sequence[float], tol: float = 1e-9) -> tuple[int, ...]:
        return tuple(r.index for r in self.regions if r.contains(p, tol))


def region_from_cycle(index: int, cyc: list[Pt]) -> Region:
    v = np.array(drop_collinear(ccw(list(cyc))), dtype=float)
    H, h = polygon_halfspaces(v)
    return Region(index=index, H=_ro(H), h=_ro(h), vertices=_ro(v))


def region_from_box(index: int, lo: np.ndarray, hi: np.ndarray) -> Region:
    d = len(lo)
    eye = np.eye(d)
    H = np.vstack([eye, -eye])
    h = np.concatenate([hi, -lo])
    if d == 2:
        v = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    else:
        v = np.array(
            [[(lo, hi)[bx][0], (lo, hi)[by][1], (lo, hi)[bz][2]] for bz in (0, 1) for by in (0, 1) for bx in (0, 1)]
        )
    return Region(index=index, H=_ro(H), h=_ro(h), vertices=_ro(v.astype(float)))


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a

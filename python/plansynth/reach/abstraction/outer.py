"""Coarsening (beyond Shoukry et al., CDC 2016, Section III): a convex obstacle
sampled with many vertices is decomposed around an outer polygon of few sides, so that
the abstraction needs few regions; the abstraction is then not ``exact`` (its regions
cover a subset of the free space: sound for plans, but no proof about the problem).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.abstraction.predicates import Pt
from plansynth.reach.geometry import Polygon, is_convex
from plansynth.reach.problem import ReachProblem

__all__ = ["OUTER_VERTICES", "outer_polygon", "coarsened"]

# a convex obstacle polygon with more vertices than this is decomposed around an outer
# polygon with this many sides (see :func:`outer_polygon`)
OUTER_VERTICES = 64


def outer_polygon(poly: Polygon, sides: int = OUTER_VERTICES) -> Polygon:
    """A convex polygon with at most ``sides`` vertices that contains the convex
    ``poly``: the intersection of its supporting half-planes in ``sides`` evenly spaced
    directions (each pushed out by a rounding margin).

    A convex obstacle sampled with thousands of vertices (a circle) makes every
    decomposition fan out into thousands of sliver regions, which DIS-PLAN crosses at
    one region per step; around the outer polygon the free space needs few regions.
    A circle of radius r grows by at most ``r (1/cos(pi/sides) - 1)`` (0.12 % at 64).

    >>> from shapely.geometry import Polygon as ShPolygon
    >>> sq = Polygon(tuple((math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 1000, endpoint=False)))
    >>> out = outer_polygon(sq, 8)
    >>> len(out.vertices), ShPolygon(out.vertices).contains(ShPolygon(sq.vertices))
    (8, True)
    """
    v = np.asarray(poly.vertices, dtype=float)
    ang = 2 * math.pi * np.arange(sides) / sides
    n = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    scale = 1.0 + float(np.abs(v).max())
    h = (v @ n.T).max(axis=0) + 1e-9 * scale
    pts: list[Pt] = []
    for k in range(sides):
        k2 = (k + 1) % sides
        p = np.linalg.solve(np.stack([n[k], n[k2]]), np.array([h[k], h[k2]]))
        q = (float(p[0]), float(p[1]))
        if not pts or math.dist(q, pts[-1]) > 1e-12 * scale:
            pts.append(q)
    if len(pts) > 1 and math.dist(pts[0], pts[-1]) <= 1e-12 * scale:
        pts.pop()
    return Polygon(tuple(pts))


def coarsened(problem: ReachProblem) -> ReachProblem | None:
    """``problem`` with every convex polygon of more than :data:`OUTER_VERTICES`
    vertices replaced by :func:`outer_polygon` (None: nothing to replace, or the start
    or the goal would be covered)."""
    if problem.dim != 2:
        return None
    obstacles = []
    changed = False
    for ob in problem.obstacles:
        if isinstance(ob, Polygon) and len(ob.vertices) > OUTER_VERTICES and is_convex(ob):
            obstacles.append(outer_polygon(ob))
            changed = True
        else:
            obstacles.append(ob)
    if not changed:
        return None
    try:
        return dataclasses.replace(problem, obstacles=tuple(obstacles))
    except InvalidProblem:  # the outer polygon covers the start or the goal
        return None

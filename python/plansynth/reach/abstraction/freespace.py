"""The free space of a 2-D problem as polygons with holes (the workspace minus the
obstacles, Shoukry et al., CDC 2016, Section III), the input of the 2-D constructions,
with collinear vertices dropped exactly.
"""

from __future__ import annotations

from collections.abc import Iterable

import shapely
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction.predicates import Pt, drop_collinear
from plansynth.reach.geometry import shape_to_shapely
from plansynth.reach.problem import ReachProblem

__all__ = ["free_polygons", "boundary_rings"]


def free_polygons(problem: ReachProblem) -> list[ShPolygon]:
    ws = shape_to_shapely(problem.workspace)
    free = ws
    if problem.obstacles:
        free = ws.difference(shapely.union_all([shape_to_shapely(o) for o in problem.obstacles]))
    polys = [g for g in getattr(free, "geoms", [free]) if isinstance(g, ShPolygon) and not g.is_empty]
    out = []
    tiny = 1e-12 * ws.area
    for g in polys:
        shell = drop_collinear([tuple(c) for c in g.exterior.coords[:-1]])
        holes = [drop_collinear([tuple(c) for c in r.coords[:-1]]) for r in g.interiors]
        q = ShPolygon(shell, [h for h in holes if len(h) >= 3])
        if q.area > tiny:
            out.append(q)
    return out


def boundary_rings(polys: Iterable[ShPolygon]) -> list[list[Pt]]:
    rings = []
    for g in polys:
        rings.append([tuple(c) for c in g.exterior.coords[:-1]])
        rings.extend([tuple(c) for c in r.coords[:-1]] for r in g.interiors)
    return rings

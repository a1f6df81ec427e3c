"""The ``hertel-mehlhorn`` construction (2-D; Shoukry et al., CDC 2016, Section III):
shapely's constrained Delaunay triangulation of the free polygons, then Hertel-Mehlhorn
removal of every diagonal whose two sides stay convex (at most 4x the optimal number of
convex pieces). Triangles sharing an edge are the contacts the merged regions inherit.
"""

from __future__ import annotations

import shapely
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction.pieces import Pieces
from plansynth.reach.abstraction.predicates import Pt, ccw, orient

__all__ = ["hertel_mehlhorn"]


def hertel_mehlhorn(polys: list[ShPolygon], order=None) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
    cycles: list[list[Pt]] = []
    for g in polys:
        tris = shapely.constrained_delaunay_triangles(g)
        for t in getattr(tris, "geoms", []):
            c = [tuple(x) for x in t.exterior.coords[:-1]]
            if len(c) != 3 or orient(c[0], c[1], c[2]) == 0:
                continue
            cycles.append(ccw(c))
    edge_owner: dict[frozenset, list[int]] = {}
    for i, c in enumerate(cycles):
        for k in range(3):
            edge_owner.setdefault(frozenset((c[k], c[(k + 1) % 3])), []).append(i)
    contacts = [(o[0], o[1]) for o in edge_owner.values() if len(o) == 2]
    pieces = Pieces(cycles, contacts, order)
    pieces.merge_all()
    return pieces.result()

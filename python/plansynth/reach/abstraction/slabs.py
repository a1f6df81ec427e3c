"""The ``slab-y`` and ``slab-x`` constructions (2-D; Shoukry et al., CDC 2016,
Section III): trapezoids between consecutive vertex coordinates along the sweep axis,
then greedy merging of neighbours whose union is convex. Trapezoids whose intervals on a
common sweep line overlap are the contacts the merged regions inherit.
"""

from __future__ import annotations

from shapely.geometry import Polygon as ShPolygon

from plansynth.budget import checkpoint
from plansynth.reach.abstraction.freespace import boundary_rings
from plansynth.reach.abstraction.pieces import Pieces
from plansynth.reach.abstraction.predicates import Pt, drop_collinear, snap_levels

__all__ = ["slabs"]


def slabs(polys: list[ShPolygon], axis: int) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
    """Trapezoids between consecutive vertex coordinates along ``axis`` (1: horizontal
    lines, sweeping y; 0: vertical lines, sweeping x).

    Sweep coordinates closer than ``1e-12`` times the largest coordinate are snapped to one
    level: mirror-image vertices often differ by a rounding error (a shapely disc's
    ``sin(t)`` and ``sin(pi - t)``), and a level per copy would cut a slab 1e-15 thick.
    Its slivers then stand between the pieces below and above, which share a facet of
    positive length but would only be linked through a region no path can cross.
    """

    def s_of(p):
        return p[axis]

    def r_of(p):
        return p[1 - axis]

    def point(s: float, r: float) -> Pt:
        return (r, s) if axis == 1 else (s, r)

    raw = boundary_rings(polys)
    if not raw:
        return [], set()
    extent = max(max(abs(c) for p in ring for c in p) for ring in raw)
    snap = snap_levels((s_of(p) for ring in raw for p in ring), 1e-12 * max(extent, 1.0))
    rings = []
    for ring in raw:
        snapped = [point(snap[s_of(p)], r_of(p)) for p in ring]
        rings.append([p for i, p in enumerate(snapped) if p != snapped[i - 1]])

    edges = []
    for ring in rings:
        for i in range(len(ring)):
            a, b = ring[i], ring[(i + 1) % len(ring)]
            if s_of(a) == s_of(b):
                continue
            if s_of(a) > s_of(b):
                a, b = b, a
            edges.append((a, b))
    vertices = {p for ring in rings for p in ring}
    levels = sorted({s_of(p) for p in vertices})

    def r_at(e: tuple[Pt, Pt], s: float) -> float:
        a, b = e
        if s == s_of(a):
            return r_of(a)
        if s == s_of(b):
            return r_of(b)
        t = (s - s_of(a)) / (s_of(b) - s_of(a))
        return r_of(a) + t * (r_of(b) - r_of(a))

    cycles: list[list[Pt]] = []
    contacts: list[tuple[int, int]] = []
    straight: set[Pt] = set()  # corners strictly inside a boundary edge
    prev: list[tuple[int, float, float]] = []  # (piece, r_lo, r_hi) on the previous level
    for s0, s1 in zip(levels, levels[1:]):
        checkpoint()
        mid = (s0 + s1) / 2
        active = [e for e in edges if s_of(e[0]) <= s0 and s_of(e[1]) >= s1]
        active.sort(key=lambda e: r_at(e, mid))
        bottom: list[tuple[int, float, float]] = []
        top: list[tuple[int, float, float]] = []
        for lo_e, hi_e in zip(active[0::2], active[1::2]):
            a0, b0 = r_at(lo_e, s0), r_at(hi_e, s0)
            a1, b1 = r_at(lo_e, s1), r_at(hi_e, s1)
            cyc = [point(s0, a0), point(s0, b0), point(s1, b1), point(s1, a1)]
            straight.update(p for p in cyc if p not in vertices)
            # CCW by construction (r_lo < r_hi, s0 < s1); the (x, y) swap mirrors it
            cyc = drop_collinear(cyc if axis == 1 else cyc[::-1])
            if len(cyc) < 3:
                continue
            pid = len(cycles)
            cycles.append(cyc)
            bottom.append((pid, a0, b0))
            top.append((pid, a1, b1))
        for pid, a, b in bottom:
            for qid, c, d in prev:
                if max(a, c) < min(b, d):
                    contacts.append((pid, qid))
        prev = top
    pieces = Pieces(cycles, contacts, straight=straight)
    pieces.merge_all()
    return pieces.result()

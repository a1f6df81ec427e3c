"""Which regions a trajectory can pass between (beyond Shoukry et al., CDC 2016, whose
DIS-PLAN, Section IV, moves between adjacent regions only): :func:`touching`, regions
whose closures meet (a segment-safe trajectory may cross a single contact point), and
:func:`step_adjacency`, the regions one step can connect (a samples-only trajectory may
jump over thin obstacles).
"""

from __future__ import annotations

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import convex_hull
from plansynth.reach.lazy.bounds.step import step_reach
from plansynth.reach.problem import ReachProblem

__all__ = ["touching", "step_adjacency"]


def touching(abstraction: Abstraction, tol: float = 1e-9) -> tuple[tuple[int, ...], ...]:
    """Pairs of regions whose closures meet (within ``tol`` times the workspace size),
    including contacts in a single point, which :attr:`Abstraction.adjacency` leaves
    out: a segment-safe trajectory may pass through such a point.

    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.abstraction import abstract
    >>> touching(abstract(maze(1)))
    ((1,), (0, 2), (1,))
    """
    regions = abstraction.regions
    k = len(regions)
    if k == 0:
        return ()
    lo = np.array([r.vertices.min(axis=0) for r in regions])
    hi = np.array([r.vertices.max(axis=0) for r in regions])
    eps = tol * (1.0 + float(np.max(hi) - np.min(lo)))
    out: list[set[int]] = [set() for _ in range(k)]
    if regions[0].dim == 2:
        import shapely
        from shapely.geometry import Polygon as ShPolygon

        polys = [ShPolygon(r.vertices) for r in regions]
        tree = shapely.STRtree(polys)
        left, right = tree.query(polys, predicate="dwithin", distance=eps)
        for i, j in zip(left.tolist(), right.tolist()):
            if i != j:
                out[i].add(j)
                out[j].add(i)
    else:  # boxes
        for i in range(k):
            meet = np.all(lo <= hi[i] + eps, axis=1) & np.all(hi >= lo[i] - eps, axis=1)
            for j in np.nonzero(meet)[0].tolist():
                if j != i:
                    out[i].add(j)
                    out[j].add(i)
    return tuple(tuple(sorted(n)) for n in out)


def step_adjacency(
    problem: ReachProblem, abstraction: Abstraction, reach: tuple[np.ndarray, np.ndarray] | None = None
) -> tuple[tuple[int, ...], ...]:
    """The regions one step can connect, for samples-only trajectories (beyond Shoukry
    et al., CDC 2016, whose DIS-PLAN, Section IV, moves to adjacent regions only): j is listed for i when some p in region i and q in region j have
    ``q - p`` in the box ``[-r, r]`` with ``r = max(step_down, step_up)`` per axis
    (:func:`step_reach`; symmetric, so the relation is too). Every step of every
    trajectory goes between two such regions (the displacement of one step lies in
    ``[-step_down, step_up]``), so with this relation, and regions that cover the free
    space (an ``exact`` abstraction), DIS-PLAN's plans include the region sequence of
    every samples-only trajectory; a pair no step can realise is refuted by CON-PLAN's
    LP, whose counterexamples stay sound. The decomposition's own adjacency is included.

    2-D: exact for the box (the Minkowski sum of a convex region and the box is the
    convex hull of its vertices shifted to the box's corners; shapely tests it against
    the other region, within 1e-9 of the workspace size); 3-D: the regions' bounding
    boxes (boxes there).

    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.abstraction import abstract
    >>> step_adjacency(maze(1), abstract(maze(1)))   # 1 m steps jump the 1 m walls
    ((1, 2), (0, 2), (0, 1))
    """
    regions = abstraction.regions
    k = len(regions)
    if k == 0:
        return ()
    down, up = step_reach(problem) if reach is None else reach
    lo = np.array([r.vertices.min(axis=0) for r in regions])
    hi = np.array([r.vertices.max(axis=0) for r in regions])
    size = float(np.max(hi) - np.min(lo))
    eps = 1e-9 * (1.0 + size)
    r = np.maximum(np.asarray(down, float), np.asarray(up, float))
    r = np.where(np.isfinite(r), r, 2.0 * size + 1.0) + eps
    out: list[set[int]] = [set(a) for a in abstraction.adjacency]
    if regions[0].dim == 2:
        import shapely
        from shapely.geometry import Polygon as ShPolygon

        polys = [ShPolygon(g.vertices) for g in regions]
        corners = np.array([[-r[0], -r[1]], [r[0], -r[1]], [r[0], r[1]], [-r[0], r[1]]])
        grown = [convex_hull((np.asarray(g.vertices)[:, None, :] + corners[None]).reshape(-1, 2)) for g in regions]
        tree = shapely.STRtree(polys)
        left, right = tree.query(grown, predicate="dwithin", distance=eps)
        pairs = zip(left.tolist(), right.tolist())
    else:
        pairs = (
            (i, int(j))
            for i in range(k)
            for j in np.nonzero(np.all(lo <= hi[i] + r, axis=1) & np.all(hi >= lo[i] - r, axis=1))[0]
        )
    for i, j in pairs:
        checkpoint()
        if i != j:
            out[i].add(j)
            out[j].add(i)
    return tuple(tuple(sorted(n)) for n in out)

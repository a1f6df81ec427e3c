"""Which regions a trajectory can pass between (beyond Shoukry et al., CDC 2016, whose
DIS-PLAN, Section IV, moves between adjacent regions only): :func:`touching`, regions
whose closures meet (a segment-safe trajectory may cross a single contact point),
:func:`step_adjacency`, the regions one step can connect (a samples-only trajectory may
jump over thin obstacles), and :func:`segment_adjacency`, the regions one straight
segment through the free space can connect (a segment-safe step may cross several
regions, never an obstacle).
"""

from __future__ import annotations

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import convex_hull
from plansynth.reach.lazy.bounds.step import step_boxes
from plansynth.reach.problem import ReachProblem

__all__ = ["touching", "step_adjacency", "segment_adjacency"]


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
    lo, hi, size, r = step_boxes(problem, regions, reach)
    eps = 1e-9 * (1.0 + size)
    r = r + eps
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


def segment_adjacency(
    problem: ReachProblem,
    abstraction: Abstraction,
    scale: float = 1.0,
    *,
    reach: tuple[np.ndarray, np.ndarray] | None = None,
    near: tuple[tuple[int, ...], ...] | None = None,
) -> tuple[tuple[int, ...], ...]:
    """The regions one segment-safe step can connect (beyond Shoukry et al., CDC 2016):
    j is listed for i when a straight segment from a point of region i to a point of
    region j, its displacement within ``scale`` times the per-step box
    (:func:`step_reach`, made symmetric: ``r = max(step_down, step_up)`` per axis), may
    stay in the free space. An over-approximation, sound for every segment-safe
    trajectory when the regions cover the free space (an ``exact`` abstraction):

    the segment [a, b] (a in region i, b in region j, b - a in the box ``B = [-r, r]``)
    lies in ``W = (box(i) + B) & (box(j) + B)`` (every point a + s (b - a) is within B
    of a and of b), and, lying in the free space, it passes through a chain of regions
    whose closures meet one after the other (:func:`touching`, or ``near``), each of
    which meets W. So j is listed when a breadth-first search from i over touching
    regions whose bounding boxes meet the box W reaches j. A thin wall that one step
    could jump (:func:`step_adjacency`) is not crossed unless a way around it lies
    within the step's reach. ``scale`` < 1: the pieces of a segment between the points
    at fractions s < s' of it (scale s' - s), for
    :class:`~plansynth.reach.lazy.segments.SegmentDisPlan`. Symmetric; the
    decomposition's own adjacency is included.

    >>> from plansynth.reach import load
    >>> from plansynth.reach.abstraction import abstract
    >>> p = load("examples/reach/claims/gcs-maze-10.yaml")    # walls 0.1 m thick, steps 0.5 m
    >>> a = abstract(p)
    >>> [sum(map(len, adj)) // 2 for adj in (a.adjacency, step_adjacency(p, a), segment_adjacency(p, a))]
    [54, 156, 84]
    """
    regions = abstraction.regions
    k = len(regions)
    if k == 0:
        return ()
    lo, hi, size, r = step_boxes(problem, regions, reach)
    eps = 1e-9 * (1.0 + size)
    r = scale * r + eps
    graph = touching(abstraction) if near is None else near
    out: list[set[int]] = [set(a) for a in abstraction.adjacency]
    for i in range(k):
        checkpoint()
        cand = np.nonzero(np.all(lo <= hi[i] + r, axis=1) & np.all(hi >= lo[i] - r, axis=1))[0]
        for j in cand.tolist():
            if j == i or j in out[i]:
                continue
            w_lo = np.maximum(lo[i], lo[j]) - r  # the box W (see above)
            w_hi = np.minimum(hi[i], hi[j]) + r
            if np.any(w_lo > w_hi):
                continue
            inside = np.all(lo <= w_hi + eps, axis=1) & np.all(hi >= w_lo - eps, axis=1)
            if _connected(graph, inside, i, j):
                out[i].add(j)
                out[j].add(i)
    return tuple(tuple(sorted(n)) for n in out)


def _connected(graph: tuple[tuple[int, ...], ...], inside: np.ndarray, i: int, j: int) -> bool:
    """Is j reachable from i over ``graph`` through nodes with ``inside`` true?"""
    seen = {i}
    todo = [i]
    while todo:
        a = todo.pop()
        for b in graph[a]:
            if b == j:
                return True
            if b not in seen and inside[b]:
                seen.add(b)
                todo.append(b)
    return False

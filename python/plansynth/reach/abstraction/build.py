"""The front of the abstraction (Shoukry et al., CDC 2016, Section III, Algorithm 1
line 1): :func:`abstract` runs the applicable constructions (:mod:`.boxes`,
:mod:`.slabs`, :mod:`.hertel_mehlhorn`), keeps the one with the fewest regions,
numbers its regions and finds the start and goal regions.
"""

from __future__ import annotations

import dataclasses
import time

from plansynth.budget import checkpoint
from plansynth.reach.abstraction.boxes import grid_boxes
from plansynth.reach.abstraction.freespace import free_polygons
from plansynth.reach.abstraction.goal import regions_meeting_goal
from plansynth.reach.abstraction.hertel_mehlhorn import hertel_mehlhorn
from plansynth.reach.abstraction.outer import coarsened
from plansynth.reach.abstraction.regions import Abstraction, Region, region_from_box, region_from_cycle
from plansynth.reach.abstraction.slabs import slabs
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["METHODS", "abstract"]

METHODS = ("auto", "hertel-mehlhorn", "slab-y", "slab-x", "boxes")
#: ``method="auto"`` on a world of box obstacles keeps the boxes construction alone when
#: it has more than this many regions: the polygon constructions take several times as
#: long there and give more regions on such grids (the GCS paper's 50 x 50 maze: boxes
#: 1,571 regions in 0.36 s, the others 1,654-1,659 in 2.3 s together).
BOXES_ALONE_ABOVE = 1000


def _candidates(problem: ReachProblem, method: str) -> list[tuple[str, list[Region], set[tuple[int, int]]]]:
    all_boxes = all(isinstance(o, Box) for o in problem.obstacles)
    if problem.dim == 3:
        if method not in ("auto", "boxes"):
            raise ValueError(f"3-D workspaces are decomposed with method 'boxes', not {method!r}")
        boxes, adj = grid_boxes(problem)
        return [("boxes", [region_from_box(i, lo, hi) for i, (lo, hi) in enumerate(boxes)], adj)]
    if method == "boxes" and not all_boxes:
        raise ValueError("method 'boxes' needs every obstacle to be a box")
    if method not in METHODS:
        raise ValueError(f"unknown decomposition method {method!r} (known: {', '.join(METHODS)})")
    out = []
    if method in ("auto", "boxes") and all_boxes:
        boxes, adj = grid_boxes(problem)
        out.append(("boxes", [region_from_box(i, lo, hi) for i, (lo, hi) in enumerate(boxes)], adj))
        if len(boxes) > BOXES_ALONE_ABOVE:
            return out
    if method != "boxes":
        polys = free_polygons(problem)
        builders = {
            "slab-y": lambda: slabs(polys, 1),
            "slab-x": lambda: slabs(polys, 0),
            "hertel-mehlhorn": lambda: hertel_mehlhorn(polys),
        }
        for name, build in builders.items():
            if method in ("auto", name):
                cycles, adj = build()
                regions = []
                for i, c in enumerate(cycles):
                    checkpoint()
                    regions.append(region_from_cycle(i, c))
                out.append((name, regions, adj))
    return out


def abstract(problem: ReachProblem, *, method: str = "auto", coarsen: bool = True) -> Abstraction:
    """Decompose the free space of ``problem`` into convex regions (Section III).

    ``method="auto"`` tries every applicable construction (see the module doc) and
    keeps the one with the fewest regions; ties go to the earlier of
    ``boxes, slab-y, slab-x, hertel-mehlhorn``. On a box world whose boxes construction
    has more than :data:`BOXES_ALONE_ABOVE` regions, that one alone. With ``coarsen`` (the default), a
    convex obstacle polygon of more than :data:`~plansynth.reach.abstraction.outer.OUTER_VERTICES` vertices is replaced by
    its :func:`~plansynth.reach.abstraction.outer.outer_polygon` first (the abstraction is then not ``exact``); if the
    start or the goal then has no region, the exact obstacles are used.

    Inside a budget phase (``with clock.phase(...)``, :mod:`plansynth.budget`) the
    constructions check the clock as they go and raise
    :class:`~plansynth.budget.BudgetExhausted` once it is out of time.
    """
    if coarsen:
        coarse = coarsened(problem)
        if coarse is not None:
            a = abstract(coarse, method=method, coarsen=False)
            if a.start_regions and a.goal_regions:
                return dataclasses.replace(a, exact=False)
    t0 = time.perf_counter()
    cands = _candidates(problem, method)
    name, regions, adj = min(cands, key=lambda c: len(c[1]))
    # number regions bottom-up (last axis first), for readable pictures and logs
    order = sorted(range(len(regions)), key=lambda i: tuple(regions[i].center[::-1].round(9)))
    new_index = {old: new for new, old in enumerate(order)}
    regions = [
        Region(index=k, H=regions[o].H, h=regions[o].h, vertices=regions[o].vertices) for k, o in enumerate(order)
    ]
    adj = {(min(new_index[i], new_index[j]), max(new_index[i], new_index[j])) for i, j in adj}
    nbrs: list[list[int]] = [[] for _ in regions]
    for i, j in adj:
        nbrs[i].append(j)
        nbrs[j].append(i)
    adjacency = tuple(tuple(sorted(set(n))) for n in nbrs)

    scale = max(h - l for l, h in zip(problem.workspace.lo, problem.workspace.hi))
    start = problem.start_position
    start_regions = tuple(r.index for r in regions if r.contains(start, 1e-9 * scale))
    goal_regions = regions_meeting_goal(problem, regions)
    return Abstraction(
        regions=tuple(regions),
        adjacency=adjacency,
        start_regions=start_regions,
        goal_regions=goal_regions,
        seconds=time.perf_counter() - t0,
        method=name,
        candidates=tuple((n, len(r)) for n, r, _ in cands),
    )

"""A reference region sequence that DIS-PLAN prefers (beyond the paper).

DIS-PLAN (Section IV) may return any region sequence that satisfies its clauses, and a
SAT solver left to itself tends to rush through some regions and dawdle in others;
CON-PLAN then refutes the rushed legs one counterexample at a time. A robot that
spreads its time evenly along a short route is far more likely to be realisable, so
the lazy loop sets the SAT solver's decision phases to such a sequence: the shortest
route through the region graph (Dijkstra over the distances between region centres,
from the start position to the goal's centre), travelled at constant speed so that it
ends exactly at the horizon, and sampled at every step (on the leg between two region
centres, the next region once the point lies in it).

Phases are only hints: the solver still returns a sequence that satisfies every
clause, the reference need not be a valid plan, and no answer depends on it.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.decompose import abstract
>>> p = maze(1); a = abstract(p)
>>> ref = reference_plan(p, a, 60)
>>> len(ref), ref[0], ref[-1], sorted(set(ref))
(61, 0, 2, [0, 1, 2])
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from plansynth.reach.decompose import Abstraction
from plansynth.reach.problem import Box, ReachProblem

__all__ = ["reference_plan", "route"]


def _goal_center(problem: ReachProblem) -> np.ndarray:
    g = problem.goal
    if isinstance(g, Box):
        return (np.asarray(g.lo, float) + np.asarray(g.hi, float)) / 2
    return np.mean(np.asarray(g.vertices, float), axis=0)


def route(problem: ReachProblem, abstraction: Abstraction) -> list[int] | None:
    """The regions of the shortest start-to-goal route through region centres (None
    when the goal regions are not reachable)."""
    regions = abstraction.regions
    start = np.asarray(problem.start_position, float)
    goal = _goal_center(problem)
    centers = [r.center for r in regions]
    dist = {i: float(np.linalg.norm(centers[i] - start)) for i in abstraction.start_regions}
    prev: dict[int, int] = {}
    heap = [(d, i) for i, d in dist.items()]
    heapq.heapify(heap)
    goals = set(abstraction.goal_regions)
    best: tuple[float, int] | None = None
    while heap:
        d, i = heapq.heappop(heap)
        if d > dist.get(i, math.inf):
            continue
        if i in goals:
            total = d + float(np.linalg.norm(goal - centers[i]))
            if best is None or total < best[0]:
                best = (total, i)
        for j in abstraction.adjacency[i]:
            nd = d + float(np.linalg.norm(centers[j] - centers[i]))
            if nd < dist.get(j, math.inf):
                dist[j] = nd
                prev[j] = i
                heapq.heappush(heap, (nd, j))
    if best is None:
        return None
    path = [best[1]]
    while path[-1] in prev:
        path.append(prev[path[-1]])
    return path[::-1]


def reference_plan(problem: ReachProblem, abstraction: Abstraction, horizon: int) -> tuple[int, ...] | None:
    """The route travelled at constant speed, sampled at steps 0..horizon (see the module
    docstring); None when there is no route."""
    path = route(problem, abstraction)
    if path is None:
        return None
    regions = abstraction.regions
    points = [np.asarray(problem.start_position, float)]
    points += [regions[i].center for i in path[1:-1]]
    goal = _goal_center(problem)
    points.append(goal if regions[path[-1]].contains(goal, tol=1e-9) else regions[path[-1]].center)
    seg = [float(np.linalg.norm(b - a)) for a, b in zip(points, points[1:])]
    total = sum(seg) or 1.0
    cum = np.concatenate([[0.0], np.cumsum(seg)]) / total
    plan = []
    k = 0  # index into path of the current region; it moves on by at most one per step
    for t in range(horizon + 1):
        s = t / horizon if horizon else 1.0
        w = min(max(int(np.searchsorted(cum, s, side="right")) - 1, 0), len(points) - 2)
        frac = 1.0 if seg[w] == 0 else min(max((s - cum[w]) * total / seg[w], 0.0), 1.0)
        p = points[w] + frac * (points[w + 1] - points[w])
        # on the leg from path[w] to path[w + 1]: the next region once the point is in it
        nxt = min(w + 1, len(path) - 1)
        target = nxt if regions[path[nxt]].contains(p, tol=1e-9) else w
        k = min(k + 1, max(k, target))
        plan.append(path[k])
    return tuple(plan)

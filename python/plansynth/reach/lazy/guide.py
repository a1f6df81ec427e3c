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

A robot that starts at rest cannot keep that constant speed on its first leg: a long
integrator chain needs many steps to accelerate (maze-4, order 25: 58 steps to the first
gap, where constant speed allots 38 of 191), and one that arrives in the fewest steps
arrives too fast to turn. ``depart`` therefore sets when the reference enters the
route's second region; the lazy loop passes the fewest steps the transit layer proved
for that leg, plus :data:`DEPART_SLACK` (5%), and the rest of the route is travelled at
constant speed in the remaining steps. The reference is only ever held back by it,
never rushed.

Phases are only hints: the solver still returns a sequence that satisfies every
clause, the reference need not be a valid plan, and no answer depends on it.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.abstraction import abstract
>>> p = maze(1); a = abstract(p)
>>> ref = reference_plan(p, a, 60)
>>> len(ref), ref[0], ref[-1], sorted(set(ref))
(61, 0, 2, [0, 1, 2])
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Sequence

import numpy as np

from plansynth.reach.abstraction import Abstraction, Region
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["reference_plan", "reference_plans", "route", "departure", "DEPART_SLACK"]

DEPART_SLACK = 0.05  # the first leg takes this much longer than its fewest steps


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


def departure(first_leg_steps: int, slack: float = DEPART_SLACK) -> int:
    """The ``depart`` step for a first leg proved to need ``first_leg_steps``.

    >>> departure(58)
    61
    """
    return math.ceil((1.0 + slack) * first_leg_steps)


def reference_plan(
    problem: ReachProblem,
    abstraction: Abstraction,
    horizon: int,
    *,
    depart: int | None = None,
    path: list[int] | None = None,
) -> tuple[int, ...] | None:
    """The route (``path``, default :func:`route`) travelled at constant speed, sampled at
    steps 0..horizon (see the module docstring); with ``depart``, the route's second
    region is entered no earlier than that step. None when there is no route."""
    path = route(problem, abstraction) if path is None else path
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

    # time warp: route fraction s(t), linear; with depart, linear in two pieces that
    # meet where the first leg enters the route's second region
    s1, t1 = 0.0, 0
    if depart is not None and len(path) > 1 and 0 < depart < horizon:
        e1 = _entry_fraction(regions[path[1]], points[0], points[1], seg[0] / total)
        if e1 * horizon < depart:  # constant speed would enter earlier: hold it back
            s1, t1 = e1, depart
    t = np.arange(horizon + 1, dtype=float)
    if horizon > t1:
        s = s1 + (1.0 - s1) * (t - t1) / (horizon - t1)
    else:
        s = np.ones(horizon + 1)
    if t1:
        s = np.where(t <= t1, s1 * t / t1, s)
    # the leg and the point at each step's route fraction
    P = np.asarray(points, float)
    seg_a = np.asarray(seg)
    w = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(points) - 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(seg_a[w] == 0, 1.0, np.clip((s - cum[w]) * total / seg_a[w], 0.0, 1.0))
    pts = P[w] + frac[:, None] * (P[w + 1] - P[w])
    # on the leg from path[w] to path[w + 1]: the next region once the point is in it
    nxt = np.minimum(w + 1, len(path) - 1)
    inside = np.zeros(horizon + 1, dtype=bool)
    for j in sorted(set(nxt.tolist())):  # (not np.unique, which imports numpy.ma: 25 ms of a first run)
        at = nxt == j
        reg = regions[path[j]]
        inside[at] = np.all(pts[at] @ np.asarray(reg.H, float).T <= np.asarray(reg.h, float) + 1e-9, axis=1)
    targets = np.where(inside, nxt, w).tolist()
    plan = []
    k = 0  # index into path of the current region; it moves on by at most one per step
    for target in targets:
        k = min(k + 1, max(k, target))
        plan.append(path[k])
    return tuple(plan)


def _entry_fraction(region: Region, a: np.ndarray, b: np.ndarray, length: float, samples: int = 256) -> float:
    """The route fraction at which the segment a -> b (of route fraction ``length``)
    first enters ``region`` (sampled; ``length`` when it never does)."""
    s = np.arange(samples + 1) / samples
    pts = a[None, :] + s[:, None] * (b - a)[None, :]
    inside = np.all(pts @ np.asarray(region.H, float).T <= np.asarray(region.h, float) + 1e-9, axis=1)
    j = np.flatnonzero(inside)
    return length * float(s[j[0]]) if j.size else length


def reference_plans(
    problem: ReachProblem,
    abstraction: Abstraction,
    path: Sequence[int] | None = None,
    first_leg: Callable[[int], int] | None = None,
) -> Callable[[int], Sequence[int] | None] | None:
    """DIS-PLAN's reference plan per horizon, for the lazy loop's ``guide``: the
    :func:`route` (or ``path``) at constant speed, its first leg held back to
    :func:`departure` of ``first_leg(path[1])``, the fewest steps the transit layer proves
    from the start into the route's second region (LPs, so computed on the first call,
    inside the loop and its budget). None when the goal is not reachable."""
    path = route(problem, abstraction) if path is None else list(path)
    if path is None:
        return None
    held = first_leg is not None and len(path) > 1
    depart: int | None = None

    def plan(L: int) -> Sequence[int] | None:
        nonlocal depart
        if held and depart is None:
            depart = departure(first_leg(path[1]))  # type: ignore[misc]
        return reference_plan(problem, abstraction, L, depart=depart, path=path)

    return plan

"""Separator chains: time windows and a horizon bound from the regions every plan must
pass through (beyond Shoukry et al., CDC 2016; sound for DIS-PLAN's plans, Section IV).

The displacement-box sweep of the time windows (:mod:`~plansynth.reach.lazy.bounds.windows`)
grows by the one-step bound, which is far above the long-run speed of a robot with
stable internal dynamics (random dynamics at n = 50: 16 m in one step, 0.75 m per step
in the long run), so its windows and horizon bound were a fraction of the true ones
(maze-3 at n = 4: horizon bound 17, no plan below 108). A chain adds a multi-step gap
per pair of separators instead (:func:`separator_bounds`, :func:`chain_gaps`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.dynamics import displacement_reach
from plansynth.reach.lazy.bounds.step import MULTISTEP_TABLE, box_of, box_steps, shape_box, step_reach
from plansynth.reach.lazy.regiongraph import reachable
from plansynth.reach.problem import ReachProblem

__all__ = ["SEPARATOR_MAX_REGIONS", "START_NODE", "GOAL_NODE", "ChainBounds", "separator_bounds", "chain_gaps"]


#: beyond this many regions the separator chains are skipped (one BFS per region)
SEPARATOR_MAX_REGIONS = 300
START_NODE, GOAL_NODE = -1, -2  # the pseudo-regions of the gap function (as in transit.py)


@dataclass(frozen=True)
class ChainBounds:
    """Bounds of :func:`separator_bounds`: ``earliest[j]`` (no plan is in region j
    before this step), ``to_go[j]`` (region j at least this many steps before the
    horizon), ``horizon`` (no plan reaches the goal in fewer steps); ``math.inf``:
    never."""

    earliest: tuple[float, ...]
    to_go: tuple[float, ...]
    horizon: float
    critical: tuple[int, ...] = ()  # the chain START, c_1, .., GOAL that gives ``horizon``


def _unreached(adjacency: Sequence[Sequence[int]], sources: Sequence[int], removed: int) -> set[int]:
    """The regions that no walk from ``sources`` reaches once ``removed`` is taken out."""
    seen = reachable(sources, adjacency, blocked=removed)
    return {j for j in range(len(adjacency)) if not seen[j] and j != removed}


def separator_bounds(
    adjacency: Sequence[Sequence[int]], start_regions: Sequence[int], goal_regions: Sequence[int], gap: Any
) -> ChainBounds:
    """Time windows and a horizon bound from chains of *separators* (beyond the paper).

    Plans are walks in the region graph ``adjacency`` (one region per step, each step
    to the same or an adjacent region: DIS-PLAN's semantics, Section IV), from a start
    region at time 0 to a goal region at the horizon N. ``gap(a, b)`` must be a lower
    bound on the steps between a sample in region a and any later sample in region b
    (a or b may be :data:`START_NODE`, the start at time 0, or :data:`GOAL_NODE`, the
    goal at time N), for instance the transit layer's
    :meth:`~plansynth.reach.lazy.transit.TransitCheck.first_gap`, or the multi-step
    displacement table of :func:`~plansynth.reach.dynamics.displacement_reach`.

    Region c *separates* the start from region j when no walk from a start region
    reaches j without passing through c. Soundness: a plan in region j at time t has
    visited every such c at some time t' < t (c != j, one region per step), so
    ``t >= earliest[c] + gap(c, j)``, by induction along the separators (acyclic: a
    separator of j is nearer to the start than j), and ``t >= gap(START, j)``; so
    ``earliest[j] = max(gap(START, j), max_c earliest[c] + gap(c, j))``. Backwards, c
    separates j from the goal when no walk from j reaches a goal region without c:
    after a visit to j at t the plan visits c at some t' > t, so ``N - t >= gap(j, c)
    + to_go[c]``, and ``N - t >= gap(j, GOAL)``. The horizon is at least
    ``gap(START, GOAL)``, ``earliest[c] + gap(c, GOAL)`` for every c that separates
    the start from all goal regions, and the least ``earliest`` of a goal region.
    Where the sweep adds one-step bounds region by region, a chain adds a gap per pair
    of separators: on a maze, gap to gap along a corridor, where a multi-step bound
    is close to the true transit time.

    >>> adj = ((1,), (0, 2), (1, 3), (2,))          # a corridor of four regions
    >>> gaps = {(1, 3): 5, (3, GOAL_NODE): 0}          # region 1 to region 3: 5 steps
    >>> b = separator_bounds(adj, (0,), (3,), lambda a, c: gaps.get((a, c), 1))
    >>> b.earliest, b.to_go, b.horizon, b.critical     # the chain START, 1, 3, GOAL
    ((0, 1, 2, 6), (3, 2, 1, 0), 6, (-1, 1, 3, -2))
    """
    k = len(adjacency)
    starts, goals = tuple(start_regions), tuple(goal_regions)
    inf = math.inf

    # BFS distances: a separator is strictly nearer (to the start, resp. the goal)
    def bfs(sources: Sequence[int]) -> list[float]:
        dist = [inf] * k
        frontier = list(sources)
        for s in frontier:
            dist[s] = 0
        while frontier:
            nxt = []
            for i in frontier:
                for j in adjacency[i]:
                    if dist[j] == inf:
                        dist[j] = dist[i] + 1
                        nxt.append(j)
            frontier = nxt
        return dist

    d_start, d_goal = bfs(starts), bfs(goals)
    sep_start: list[list[int]] = [[] for _ in range(k)]  # c separates the start from j
    sep_goal: list[list[int]] = [[] for _ in range(k)]  # c separates j from the goal
    all_goals: list[int] = []  # c separates the start from every goal region
    for c in range(k):
        checkpoint()
        if c not in starts and d_start[c] < inf:
            cut = _unreached(adjacency, starts, c)
            for j in cut:
                if d_start[j] < inf:
                    sep_start[j].append(c)
            if goals and c not in goals and all(g in cut for g in goals):
                all_goals.append(c)
        if c not in goals and d_goal[c] < inf:
            for j in _unreached(adjacency, goals, c):
                if d_goal[j] < inf:
                    sep_goal[j].append(c)
    earliest = [inf] * k
    via: list[int] = [START_NODE] * k  # the separator before j on its longest chain
    for j in sorted((j for j in range(k) if d_start[j] < inf), key=lambda j: d_start[j]):
        e = 0 if j in starts else max(1, gap(START_NODE, j))
        for c in sep_start[j]:
            if earliest[c] + max(1, gap(c, j)) > e:
                e, via[j] = earliest[c] + max(1, gap(c, j)), c
        earliest[j] = e
    to_go = [inf] * k
    for j in sorted((j for j in range(k) if d_goal[j] < inf), key=lambda j: d_goal[j]):
        r = 0 if j in goals else max(0, gap(j, GOAL_NODE))  # (a goal region can hold the end itself)
        for c in sep_goal[j]:
            r = max(r, max(1, gap(j, c)) + to_go[c])
        to_go[j] = r
    reachable_goals = [g for g in goals if earliest[g] < inf]
    if not reachable_goals:
        return ChainBounds(tuple(earliest), tuple(to_go), inf)
    horizon, last = gap(START_NODE, GOAL_NODE), START_NODE
    g = min(reachable_goals, key=lambda g: earliest[g])
    if earliest[g] > horizon:
        horizon, last = earliest[g], g
    for c in all_goals:
        if earliest[c] + max(1, gap(c, GOAL_NODE)) > horizon:
            horizon, last = earliest[c] + max(1, gap(c, GOAL_NODE)), c
    chain = [GOAL_NODE]
    while last != START_NODE:
        chain.append(last)
        last = via[last] if last not in starts else START_NODE
    chain.append(START_NODE)
    return ChainBounds(
        tuple(int(e) if e < inf else inf for e in earliest),
        tuple(int(r) if r < inf else inf for r in to_go),
        int(horizon),
        tuple(chain[::-1]),
    )


def chain_gaps(problem: ReachProblem, abstraction: Abstraction) -> Any | None:
    """The gap function of :func:`separator_bounds` from displacement bounds alone (no
    LP): the fewest steps between the bounding boxes of two regions (the start point,
    the goal box) by :func:`box_steps` with the one-step bounds of :func:`step_reach`
    and the multi-step table of :func:`~plansynth.reach.dynamics.displacement_reach`
    (sound for any two samples of a trajectory from rest: the table bounds the move of
    any k consecutive steps). None when that table does not exist (not at rest, or no
    stable internal block: integrator chains, where the chains would only repeat the
    one-step bounds of :func:`time_windows`)."""
    if not problem.starts_at_rest:
        return None
    table = displacement_reach(problem.dynamics, problem.input_bound, MULTISTEP_TABLE)
    if table is None:
        return None
    down, up = step_reach(problem)
    boxes = {i: box_of(r.vertices) for i, r in enumerate(abstraction.regions)}
    s = np.asarray(problem.start_position, dtype=float)
    boxes[START_NODE] = (s, s)
    boxes[GOAL_NODE] = shape_box(problem.goal)

    def gap(a: int, b: int) -> int:
        return box_steps(boxes[a], boxes[b], down, up, table)

    return gap

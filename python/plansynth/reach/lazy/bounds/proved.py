"""The proved horizon bound: a lower bound on the horizon of *every* trajectory of the
problem (the spec's semantics), whatever the decomposition (beyond Shoukry et al., CDC
2016); the only bound that may prove ``infeasible``.

DIS-PLAN moves one region per step (Section IV), so the region-graph distance, the
time windows (:mod:`~plansynth.reach.lazy.bounds.windows`) and every horizon the loop
refutes speak about plans through *this* decomposition: a real segment-safe trajectory
may cross several regions in one step (thousands of sliver regions around a finely
sampled circle, say). The bounds here hold for the problem itself.
"""

from __future__ import annotations

import math

import numpy as np

from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.bounds.adjacency import touching
from plansynth.reach.lazy.bounds.step import box_steps, shape_box, step_reach
from plansynth.reach.problem import ReachProblem

__all__ = ["proved_horizon_bound", "SWEEP_MAX_REGIONS", "SWEEP_MAX_WORK"]

SWEEP_MAX_REGIONS = 1000  # beyond this the proved sweep is skipped (the distance bound remains)
SWEEP_MAX_WORK = 2_000_000  # region visits; the sweep stops early (its bound so far holds)


def _proved_sweep(
    problem: ReachProblem, abstraction: Abstraction, limit: int, down: np.ndarray, up: np.ndarray
) -> float:
    """The displacement-box sweep with any number of regions per step (segment-safe
    trajectories): the first step at which the goal may be reached, ``limit + 1`` if
    not within ``limit`` steps, ``inf`` if the sweep closes without reaching it.

    Invariant: ``reach[j]`` is a box holding every position in region j at any time
    <= t. A step from ``p`` in ``reach[i]`` ends in ``G = reach[i] + [-down, up]`` and
    its segment lies in G (a box is convex) and in the closed free space, so it crosses
    a chain of regions that pairwise touch (:func:`touching`) and all meet G; the end
    point lies in ``box(j) & G`` for a region j of that chain. Growing ``reach`` by
    ``box(j) & G`` for every region j reachable from i through touching regions whose
    boxes meet G keeps the invariant; the goal is not reached before some goal region's
    box meets the goal.
    """
    regions = abstraction.regions
    k = len(regions)
    blo = np.array([r.vertices.min(axis=0) for r in regions])
    bhi = np.array([r.vertices.max(axis=0) for r in regions])
    contact = touching(abstraction)
    scale = 1.0 + np.abs(np.array(problem.workspace.hi)) + np.abs(np.array(problem.workspace.lo))
    pad = 1e-9 * scale
    grow_lo = np.where(np.isfinite(down), down, 1e300) + pad
    grow_hi = np.where(np.isfinite(up), up, 1e300) + pad
    s = np.asarray(problem.start_position, dtype=float)
    g_lo, g_hi = shape_box(problem.goal)
    reach_lo = np.full(blo.shape, np.inf)
    reach_hi = np.full(bhi.shape, -np.inf)
    starts = [j for j in range(k) if np.all(blo[j] - pad <= s) and np.all(s <= bhi[j] + pad)]
    for j in starts:
        reach_lo[j], reach_hi[j] = np.maximum(s - pad, blo[j]), np.minimum(s + pad, bhi[j])
    goal_regions = [j for j in range(k) if np.all(np.maximum(blo[j], g_lo) <= np.minimum(bhi[j], g_hi) + pad)]
    if not starts or not goal_regions:  # regions that do not cover start and goal prove nothing
        return 0

    def hit() -> bool:
        for j in goal_regions:
            if np.all(reach_lo[j] <= reach_hi[j]) and np.all(
                np.maximum(reach_lo[j], g_lo) <= np.minimum(reach_hi[j], g_hi) + pad
            ):
                return True
        return False

    if hit():
        return 0
    contact_lists = [list(c) for c in contact]
    work = 0
    for t in range(1, limit + 1):
        new_lo, new_hi = reach_lo.copy(), reach_hi.copy()
        for i in np.nonzero(np.all(reach_lo <= reach_hi, axis=1))[0].tolist():
            G_lo, G_hi = reach_lo[i] - grow_lo, reach_hi[i] + grow_hi
            meets = (np.all(blo <= G_hi, axis=1) & np.all(bhi >= G_lo, axis=1)).tolist()
            seen = {i}
            stack = [i]
            while stack:
                j = stack.pop()
                for q in contact_lists[j]:
                    if q not in seen and meets[q]:
                        seen.add(q)
                        stack.append(q)
                work += len(contact_lists[j])
            idx = np.fromiter(seen, dtype=np.int64, count=len(seen))
            new_lo[idx] = np.minimum(new_lo[idx], np.maximum(blo[idx], G_lo))
            new_hi[idx] = np.maximum(new_hi[idx], np.minimum(bhi[idx], G_hi))
            work += k
            if work > SWEEP_MAX_WORK:
                return t  # steps before t were swept completely without reaching the goal
        changed = not (np.array_equal(new_lo, reach_lo) and np.array_equal(new_hi, reach_hi))
        reach_lo, reach_hi = new_lo, new_hi
        if hit():
            return t
        if not changed:
            return math.inf
    return limit + 1


def proved_horizon_bound(
    problem: ReachProblem, abstraction: Abstraction, limit: int, *, segment_safe: bool = True
) -> float:
    """A lower bound on the horizon of *every* trajectory of ``problem`` (the spec's
    semantics), whatever the decomposition: ``inf`` when no trajectory reaches the goal
    at all, ``limit + 1`` when none does within ``limit`` steps.

    The distance bound (:func:`physical_lower_bound`) always; for segment-safe
    trajectories also the sweep of :func:`_proved_sweep`, which lets a step cross any
    number of touching regions (an ``exact`` abstraction of at most
    :data:`SWEEP_MAX_REGIONS` regions: it needs regions that cover the free space). Samples-only
    trajectories may jump over obstacles, so for them only the distance bound holds.
    This is what may prove ``infeasible`` (the region-hop bounds may not; see above).

    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.abstraction import abstract
    >>> proved_horizon_bound(maze(1), abstract(maze(1)), 200)   # the region-hop bounds say 50
    38
    >>> proved_horizon_bound(maze(1), abstract(maze(1)), 200, segment_safe=False)
    26
    """
    down, up = step_reach(problem)
    s = np.asarray(problem.start_position, dtype=float)
    phys = box_steps((s, s), shape_box(problem.goal), down, up)
    bound: float = min(phys, limit + 1) if phys < (1 << 30) else math.inf
    if segment_safe and abstraction.exact and 0 < len(abstraction.regions) <= SWEEP_MAX_REGIONS and bound <= limit:
        bound = max(bound, _proved_sweep(problem, abstraction, limit, down, up))
    return bound

"""Time windows for DIS-PLAN from the displacement-box relaxation of CON-PLAN (beyond
Shoukry et al., CDC 2016, whose DIS-PLAN, Section IV, walks the region graph one region
per step): reach boxes swept along the region graph from the start and back from the
goal give the first step at which each region can be reached, how many steps the goal
is at least away from each region, and a horizon bound for plans through the
abstraction.

:func:`_sweep` (numpy over the graph's edges) and :func:`_sweep_reference` (region by
region, the oracle the tests compare it with) compute the same sweep.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.bounds.step import box_of, shape_box, step_reach
from plansynth.reach.problem import ReachProblem

__all__ = ["TimeWindows", "time_windows"]


@dataclass(frozen=True)
class TimeWindows:
    """Time windows of the displacement-box relaxation (see :func:`time_windows`).

    ``earliest[j]``: no trajectory is in region j before this step (``math.inf``:
    never); ``to_go[j]``: from region j the goal is at least this many steps away
    (``math.inf``: never); ``horizon``: no trajectory reaches the goal in fewer steps.
    """

    earliest: tuple[float, ...]
    to_go: tuple[float, ...]
    horizon: float
    step_down: tuple[float, ...]
    step_up: tuple[float, ...]


def _sweep(
    seeds: dict[int, tuple[np.ndarray, np.ndarray]],
    boxes: Sequence[tuple[np.ndarray, np.ndarray]],
    adjacency: Sequence[Sequence[int]],
    grow_lo: np.ndarray,
    grow_hi: np.ndarray,
    limit: int,
    targets: dict[int, tuple[np.ndarray, np.ndarray]] | None = None,
) -> tuple[list[float], float]:
    """:func:`_sweep_reference`, one step over every region at once (numpy over the
    edges of the region graph, self-loops included): the same boxes, the same answer
    (a hypothesis test compares them), in ~0.5 ms a step where the region-by-region loop
    took ~1,500 regions x their neighbours of small numpy calls (the GCS paper's 50 x 50
    maze: about 20 s for the two sweeps)."""
    k = len(boxes)
    if k == 0:
        return [], math.inf
    d = len(grow_lo)
    blo = np.array([b[0] for b in boxes], dtype=float).reshape(k, d)
    bhi = np.array([b[1] for b in boxes], dtype=float).reshape(k, d)
    src = np.array([j for j in range(k)] + [i for j in range(k) for i in adjacency[j]], dtype=np.int64)
    dst = np.array([j for j in range(k)] + [j for j in range(k) for _ in adjacency[j]], dtype=np.int64)
    inf = np.inf
    rlo = np.full((k, d), inf)
    rhi = np.full((k, d), -inf)
    have = np.zeros(k, dtype=bool)
    first = np.full(k, inf)
    for j, (lo, hi) in seeds.items():
        rlo[j], rhi[j], have[j], first[j] = lo, hi, True, 0
    tj = np.array(sorted((targets or {}).keys()), dtype=np.int64)
    tlo = np.array([targets[j][0] for j in tj.tolist()], dtype=float).reshape(len(tj), d) if len(tj) else None
    thi = np.array([targets[j][1] for j in tj.tolist()], dtype=float).reshape(len(tj), d) if len(tj) else None

    def hits() -> bool:
        if tlo is None:
            return False
        ok = have[tj] & np.all(np.maximum(rlo[tj], tlo) <= np.minimum(rhi[tj], thi), axis=1)
        return bool(ok.any())

    hit = 0 if hits() else math.inf
    for t in range(1, limit + 1):
        checkpoint()
        live = have[src]
        s_, d_ = src[live], dst[live]
        clo = np.maximum(rlo[s_] - grow_lo, blo[d_])
        chi = np.minimum(rhi[s_] + grow_hi, bhi[d_])
        ok = np.all(clo <= chi, axis=1)
        s_, d_, clo, chi = s_[ok], d_[ok], clo[ok], chi[ok]
        nlo, nhi = rlo.copy(), rhi.copy()
        np.minimum.at(nlo, d_, clo)
        np.maximum.at(nhi, d_, chi)
        reached = np.zeros(k, dtype=bool)
        reached[d_] = True
        grew = reached & (~have | np.any(nlo < rlo, axis=1) | np.any(nhi > rhi, axis=1))
        first[grew & ~have] = t
        changed = bool(grew.any())
        rlo, rhi = np.where(grew[:, None], nlo, rlo), np.where(grew[:, None], nhi, rhi)
        have = have | grew
        if hit == math.inf and hits():
            hit = t
        if not changed:
            break
    return [math.inf if math.isinf(f) else int(f) for f in first.tolist()], hit


def _sweep_reference(
    seeds: dict[int, tuple[np.ndarray, np.ndarray]],
    boxes: Sequence[tuple[np.ndarray, np.ndarray]],
    adjacency: Sequence[Sequence[int]],
    grow_lo: np.ndarray,
    grow_hi: np.ndarray,
    limit: int,
    targets: dict[int, tuple[np.ndarray, np.ndarray]] | None = None,
) -> tuple[list[float], float]:
    """Grow reach boxes from ``seeds`` by [-grow_lo, grow_hi] per step along region
    adjacency, clipped to the region boxes, for at most ``limit`` steps (boxes only
    grow: 0 is a displacement, so a step may stay put). Returns the first step at
    which each region's box is non-empty, and the first step at which some region's
    box meets its ``targets`` box (inf: not within ``limit``, or never)."""
    k = len(boxes)
    reach: list[tuple[np.ndarray, np.ndarray] | None] = [None] * k
    first = [math.inf] * k
    for j, b in seeds.items():
        reach[j] = b
        first[j] = 0

    def hits() -> bool:
        for j, (tlo, thi) in (targets or {}).items():
            r = reach[j]
            if r is not None and np.all(np.maximum(r[0], tlo) <= np.minimum(r[1], thi)):
                return True
        return False

    hit = 0 if hits() else math.inf
    for t in range(1, limit + 1):
        new = list(reach)
        changed = False
        for j in range(k):
            checkpoint()  # thousands of regions: within the budget phase, if any
            blo, bhi = boxes[j]
            lo, hi = None, None
            for i in (j, *adjacency[j]):
                r = reach[i]
                if r is None:
                    continue
                clo = np.maximum(r[0] - grow_lo, blo)
                chi = np.minimum(r[1] + grow_hi, bhi)
                if np.any(clo > chi):
                    continue
                lo = clo if lo is None else np.minimum(lo, clo)
                hi = chi if hi is None else np.maximum(hi, chi)
            if lo is None:
                continue
            old = reach[j]
            if old is None or np.any(lo < old[0]) or np.any(hi > old[1]):
                new[j] = (lo, hi) if old is None else (np.minimum(lo, old[0]), np.maximum(hi, old[1]))
                changed = True
                if first[j] == math.inf:
                    first[j] = t
        reach = new
        if hit == math.inf and hits():
            hit = t
        if not changed:
            break
    return first, hit


def time_windows(
    problem: ReachProblem, abstraction: Abstraction, limit: int, *, adjacency: Sequence[Sequence[int]] | None = None
) -> TimeWindows:
    """Reach times of the displacement-box relaxation (beyond the paper).

    Forget the dynamics except that a position moves by at most
    ``[-step_down, step_up]`` per step (:func:`step_reach`), over-approximate every
    region by its bounding box and every reachable set by a box: the reach boxes grow
    along the region graph from the start (``earliest``) and backwards from the goal
    (``to_go``). Each is an over-approximation of what any trajectory (sampled or
    segment-safe) can do, so "region j before step ``earliest[j]``" and "region j
    fewer than ``to_go[j]`` steps before the end" are impossible, and the first step at
    which a goal region's reach box meets the goal is a lower bound on the horizon.

    The boxes grow along ``adjacency`` (default: the decomposition's, one region per
    step, which holds for plans through the abstraction); with
    :func:`step_adjacency` (every pair of regions one step can connect) the windows
    hold for every samples-only trajectory of the problem.

    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.abstraction import abstract
    >>> w = time_windows(maze(1), abstract(maze(1)), 200)
    >>> w.earliest, w.to_go, w.horizon
    ((0, 26, 27), (25, 24, 0), 50)
    """
    down, up = step_reach(problem)
    boxes = [box_of(r.vertices) for r in abstraction.regions]
    adjacency = abstraction.adjacency if adjacency is None else adjacency
    s = np.asarray(problem.start_position, dtype=float)
    g_lo, g_hi = shape_box(problem.goal)
    down_f = np.where(np.isfinite(down), down, 1e300)
    up_f = np.where(np.isfinite(up), up, 1e300)
    # tolerance: the LP of step_reach and the region boxes are floating point
    pad = 1e-9 * (1.0 + np.abs(np.array(problem.workspace.hi)) + np.abs(np.array(problem.workspace.lo)))
    seeds = {j: (s - pad, s + pad) for j in abstraction.start_regions}
    goal_boxes = {}
    for j in abstraction.goal_regions:
        lo, hi = np.maximum(boxes[j][0], g_lo), np.minimum(boxes[j][1], g_hi)
        if np.all(lo <= hi):
            goal_boxes[j] = (lo, hi)
    earliest, horizon = _sweep(seeds, boxes, adjacency, down_f + pad, up_f + pad, limit, goal_boxes)
    to_go, _ = _sweep(goal_boxes, boxes, adjacency, up_f + pad, down_f + pad, limit)
    return TimeWindows(tuple(earliest), tuple(to_go), horizon, tuple(down), tuple(up))

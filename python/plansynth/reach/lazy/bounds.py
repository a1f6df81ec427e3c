"""Relaxations of CON-PLAN that hold for every region sequence: horizon lower bounds
and time windows for DIS-PLAN (beyond Shoukry et al., CDC 2016; every bound is sound).

* :func:`step_reach` and :func:`physical_lower_bound`: how far the robot can move per
  step along each axis (one small LP per axis and direction), and the distance to the
  goal divided by it;
* :func:`time_windows`: the displacement-box relaxation swept along the region graph,
  the first step at which each region (and the goal) can be reached, and how many
  steps the goal is at least away from each region;
* :func:`proved_horizon_bound`: a lower bound on the horizon of *every* trajectory of
  the problem, whatever the decomposition, which is what may prove ``infeasible``.

The lazy loop (:mod:`plansynth.reach.lazy.loop`), the transit layer, the region MILP
and the mission planners use them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import highspy
import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.highs import new_highs
from plansynth.reach.dynamics import displacement_reach, reach_steps
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = [
    "step_reach",
    "physical_lower_bound",
    "shape_box",
    "box_steps",
    "TimeWindows",
    "time_windows",
    "touching",
    "step_adjacency",
    "proved_horizon_bound",
    "SWEEP_MAX_REGIONS",
    "SWEEP_MAX_WORK",
]


def step_reach(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
    """(down, up): the largest position change per step along each workspace axis in
    the negative and the positive direction that dynamics, input bounds, state bounds
    and the workspace allow (inf when unbounded). One LP per axis and direction:
    maximise ``+-(p_{t+1} - p_t)_a`` over ``x_t, u_t`` with ``x_t`` and ``A x_t + B u_t``
    within the bounds.
    """
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    pos = list(dyn.position)
    A, B = np.asarray(dyn.A), np.asarray(dyn.B)
    inf = highspy.kHighsInf
    lo, hi = problem.state_box
    # variables [x (n), u (m)]; rows: A x + B u within [lo, hi]
    M = np.hstack([A, B])
    lp = highspy.HighsLp()
    lp.num_col_ = n + m
    lp.num_row_ = n
    lp.col_lower_ = np.concatenate([lo, np.full(m, -problem.input_bound)])
    lp.col_upper_ = np.concatenate([hi, np.full(m, problem.input_bound)])
    lp.row_lower_ = lo
    lp.row_upper_ = hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kRowwise
    nz = np.nonzero(M)
    lp.a_matrix_.start_ = np.concatenate([[0], np.cumsum(np.bincount(nz[0], minlength=n))]).astype(np.int32)
    lp.a_matrix_.index_ = nz[1].astype(np.int32)
    lp.a_matrix_.value_ = M[nz]
    h = new_highs()
    down, up = np.zeros(len(pos)), np.zeros(len(pos))
    for a, i in enumerate(pos):
        for sign, out in ((1.0, up), (-1.0, down)):
            cost = sign * (M[i] - np.eye(n + m)[i])  # (A x + B u)_i - x_i
            lp.col_cost_ = -cost  # HiGHS minimises
            h.passModel(lp)
            h.run()
            status = h.getModelStatus()
            if status == highspy.HighsModelStatus.kOptimal:
                out[a] = max(0.0, -h.getInfo().objective_function_value)
            else:
                out[a] = math.inf
    return down, up


def _once_per_problem(f):  # (problems are immutable values with identity hashes)
    import functools
    import weakref

    memo: "weakref.WeakKeyDictionary[ReachProblem, tuple[np.ndarray, np.ndarray]]" = weakref.WeakKeyDictionary()

    @functools.wraps(f)
    def cached(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
        if problem not in memo:
            memo[problem] = f(problem)
        down, up = memo[problem]
        return down.copy(), up.copy()

    return cached


#: computed once per problem (four callers per plan: the bounds, the windows, the
#: proved bound and the transit layer; eight LPs each time)
step_reach = _once_per_problem(step_reach)


#: steps covered by the multi-step displacement table (random dynamics; issue 13)
MULTISTEP_TABLE = 1000


def physical_lower_bound(problem: ReachProblem) -> int:
    """A horizon below which no trajectory reaches the goal, obstacles ignored: along
    every axis, the distance from the start to the goal's bounding box divided by the
    largest displacement per step (see :func:`step_reach`).

    >>> from plansynth.reach.families import maze
    >>> physical_lower_bound(maze(1))   # 26 m up at most 1 m (2 m/s x 0.5 s) per step
    26
    """
    down, up = step_reach(problem)
    s = np.asarray(problem.start_position, dtype=float)
    table = (
        displacement_reach(problem.dynamics, problem.input_bound, MULTISTEP_TABLE) if problem.starts_at_rest else None
    )
    return box_steps((s, s), shape_box(problem.goal), down, up, table)


def shape_box(shape: Any) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box (lo, hi) of a :class:`Box` or a polygon."""
    if isinstance(shape, Box):
        return np.asarray(shape.lo, dtype=float), np.asarray(shape.hi, dtype=float)
    return _box_of(np.asarray(shape.vertices))


def box_steps(
    a: tuple[np.ndarray, np.ndarray],
    b: tuple[np.ndarray, np.ndarray],
    down: Sequence[float],
    up: Sequence[float],
    table: np.ndarray | None = None,
) -> int:
    """The fewest steps from a position in box ``a`` to one in box ``b`` when a step moves
    at most ``down[i]``/``up[i]`` along axis i (1 << 30: some axis cannot move that way),
    and (``table``, :func:`plansynth.reach.dynamics.displacement_reach`) k steps move at
    most ``table[k, i]`` either way.

    >>> box_steps((np.zeros(2), np.zeros(2)), (np.array([3.0, -1.0]), np.array([4.0, 1.0])), [1, 1], [1.5, 1])
    2
    """
    (alo, ahi), (blo, bhi) = a, b
    need = 0
    for ax in range(len(alo)):
        for dist, reach in ((blo[ax] - ahi[ax], up[ax]), (alo[ax] - bhi[ax], down[ax])):
            if dist > 0:
                if not reach > 0:
                    return 1 << 30  # cannot move that way at all
                if math.isfinite(reach):
                    # shave the LP's tolerance off before rounding up
                    need = max(need, math.ceil(dist / reach * (1 - 1e-9) - 1e-9))
                if table is not None:
                    need = max(need, reach_steps(table, dist, ax))
    return need


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


def _box_of(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    v = np.asarray(vertices, dtype=float)
    return v.min(axis=0), v.max(axis=0)


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
    boxes = [_box_of(r.vertices) for r in abstraction.regions]
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


# ---------------------------------------------------------------------------------
# Lower bounds that hold for the problem itself (the spec's semantics), not only for
# plans through the abstraction. DIS-PLAN moves one region per step, so the bounds
# above (region-graph distance, the displacement-box sweep along the region graph) and
# every horizon the loop refutes speak about plans through *this* decomposition: a real
# segment-safe trajectory may cross several regions in one step (thousands of sliver
# regions around a finely sampled circle, say). Only the bounds below may prove
# ``infeasible``.

SWEEP_MAX_REGIONS = 1000  # beyond this the proved sweep is skipped (the distance bound remains)
SWEEP_MAX_WORK = 2_000_000  # region visits; the sweep stops early (its bound so far holds)


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
    """The regions one step can connect, for samples-only trajectories (issue 13, item 7;
    beyond Shoukry et al., CDC 2016, whose DIS-PLAN, Section IV, moves to adjacent
    regions only): j is listed for i when some p in region i and q in region j have
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
        grown = [
            shapely.convex_hull(
                shapely.multipoints((np.asarray(g.vertices)[:, None, :] + corners[None]).reshape(-1, 2))
            )
            for g in regions
        ]
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


# ---------------------------------------------------------------------------------
# Separator chains (issue 13, item 4: random dynamics). The displacement-box sweep
# above grows by the one-step bound, which is far above the long-run speed of a robot
# with stable internal dynamics (n = 50 random dynamics: 16 m in one step, 0.75 m per
# step in the long run), so its windows and horizon bound were a fraction of the true
# ones (maze-3, n = 4: horizon bound 17, no plan below 108).

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
    k = len(adjacency)
    seen = [False] * k
    seen[removed] = True
    stack = [s for s in sources if s != removed]
    for s in stack:
        seen[s] = True
    while stack:
        i = stack.pop()
        for j in adjacency[i]:
            if not seen[j]:
                seen[j] = True
                stack.append(j)
    return {j for j in range(k) if not seen[j] and j != removed}


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
    boxes = {i: _box_of(r.vertices) for i, r in enumerate(abstraction.regions)}
    s = np.asarray(problem.start_position, dtype=float)
    boxes[START_NODE] = (s, s)
    boxes[GOAL_NODE] = shape_box(problem.goal)

    def gap(a: int, b: int) -> int:
        return box_steps(boxes[a], boxes[b], down, up, table)

    return gap

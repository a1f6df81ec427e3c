"""Which region pairs one straight segment through the free space connects, decided per
pair (beyond Shoukry et al., CDC 2016): the exact transition relation of a segment-safe
step, up to a tolerance, for DIS-PLAN's samples
(:class:`~plansynth.reach.lazy.segments.SegmentDisPlan`).

:func:`~plansynth.reach.lazy.bounds.segment_adjacency` over-approximates the relation
with bounding boxes: in a maze whose corridors are long regions, a pair on the two
sides of a thin wall stays in it whenever a doorway lies within a step of the regions'
boxes, and DIS-PLAN then proposes steps through the wall that the theory must refute.
:func:`connected_pairs` keeps a candidate pair (i, j) only when a segment from region i
to region j, its displacement within the step's box, may avoid every obstacle:

* a small MILP (HiGHS) over the two end points a, b: a in region i, b in region j,
  b - a in the box, and points at fixed fractions of [a, b] each in one of the regions
  that meet the box W of :func:`~plansynth.reach.lazy.bounds.segment_adjacency` (big-M
  rows, one binary per point and region). Infeasible: no segment-safe step connects
  the pair (the points of such a step are free, and the regions cover the free space),
  so the pair goes;
* a solution whose segment avoids every obstacle (the depth of
  :func:`~plansynth.reach.lazy.bounds.depth.segment_depth`) keeps the pair; one that cuts
  an obstacle gets its deepest point as one more point, and the MILP runs again (at
  most :data:`ROUNDS` times; undecided pairs are kept, which is sound).

Sound (a pair is dropped only when a MILP proves no segment-safe step joins it), and
exact up to the rounds' cap.
"""

from __future__ import annotations

import highspy
import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import convex_pieces
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.bounds.depth import segment_depth
from plansynth.reach.lazy.bounds.step import step_boxes
from plansynth.reach.problem import ReachProblem

__all__ = ["connected_pairs", "pair_boxes", "ROUNDS", "START_FRACTIONS"]

#: MILP rounds per pair before it is kept undecided.
ROUNDS = 8
#: The points of the segment kept in regions at first.
START_FRACTIONS = (0.25, 0.5, 0.75)
#: A segment entering an obstacle no deeper than this touches it.
TOUCH = 1e-7


def connected_pairs(
    problem: ReachProblem,
    abstraction: Abstraction,
    candidates: tuple[tuple[int, ...], ...],
    *,
    reach: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[tuple[int, ...], ...]:
    """``candidates`` (a symmetric relation over the regions that contains every pair one
    segment-safe step connects, :func:`~plansynth.reach.lazy.bounds.segment_adjacency`)
    without the pairs no such step connects (module docstring). The decomposition's own
    adjacency stays without a MILP (a segment across the shared face joins them)."""
    regions = abstraction.regions
    k = len(regions)
    if k == 0:
        return ()
    lo, hi, _, r = step_boxes(problem, regions, reach)
    ws_lo, ws_hi = np.asarray(problem.workspace.lo, float), np.asarray(problem.workspace.hi, float)
    pieces = []
    for o in problem.obstacles:
        for H, h in convex_pieces(o):
            top = np.sum(np.maximum(H * ws_lo, H * ws_hi), axis=1)
            keep = h < top - 1e-12  # (a face flush with the boundary leaves a slit at most)
            pieces.append((H[keep], h[keep]))
    own = [set(a) for a in abstraction.adjacency]
    out: list[set[int]] = [set() for _ in range(k)]
    hs = new_highs()
    for i in range(k):
        for j in candidates[i]:
            if j < i:
                continue
            checkpoint()
            if j in own[i] or _connected(regions, lo, hi, r, i, j, pieces, hs):
                out[i].add(j)
                out[j].add(i)
    return tuple(tuple(sorted(n)) for n in out)


def _connected(regions, lo, hi, r, i, j, pieces, hs) -> bool:
    w_lo = np.maximum(lo[i], lo[j]) - r
    w_hi = np.minimum(hi[i], hi[j]) + r
    near = np.nonzero(np.all(lo <= w_hi, axis=1) & np.all(hi >= w_lo, axis=1))[0].tolist()
    box_lo, box_hi = np.minimum(lo[i], lo[j]), np.maximum(hi[i], hi[j])
    fractions = list(START_FRACTIONS)
    for _ in range(ROUNDS):
        ab = _milp(regions, i, j, near, fractions, r, box_lo, box_hi, hs)
        if ab is None:
            return False
        if isinstance(ab, str):
            return True  # (undecided: kept)
        a, b = ab
        worst, at = 0.0, None
        for H, h in pieces:
            if not len(h):
                continue
            d, s = segment_depth(a[None, :], b[None, :], H, h)
            if d[0] > worst:
                worst, at = float(d[0]), float(s[0])
        if worst <= TOUCH:
            return True
        fractions.append(at)
    return True


def _milp(regions, i, j, near, fractions, r, box_lo, box_hi, hs, cost=None):
    """The pair's MILP: columns a, b (d each), binaries z[k, q] (point k in region q);
    the end points (a, b), or None (infeasible), or "undecided". ``cost`` (2 d
    entries): minimise ``cost . (a, b)``, and return the optimum's bound instead (a
    lower bound on it: HiGHS's dual bound), or None when infeasible."""
    d = len(r)
    rows = Rows()

    p_lo, p_hi = box_lo - 1.0, box_hi + 1.0  # (the columns' bounds: every point of [a, b] lies within)

    def region_rows(rid: int, wa: float, wb: float, z: int | None) -> None:
        H, h = np.asarray(regions[rid].H, float), np.asarray(regions[rid].h, float)
        m = H.shape[0]
        R = [np.repeat(np.arange(m), d), np.repeat(np.arange(m), d)]
        C = [np.tile(np.arange(d), m), np.tile(d + np.arange(d), m)]
        V = [wa * H.ravel(), wb * H.ravel()]
        up = h.copy()
        if z is not None:  # H p <= h + M (1 - z), M the largest H p - h over the columns' box
            big = np.maximum(np.sum(np.maximum(H * p_lo, H * p_hi), axis=1) - h, 0.0) + 1.0
            R.append(np.arange(m))
            C.append(np.full(m, z))
            V.append(big)
            up = h + big
        rows.add(np.concatenate(R), np.concatenate(C), np.concatenate(V), np.full(m, -np.inf), up)

    n_bin = len(fractions) * len(near)
    col = 2 * d
    for f in fractions:
        zs = list(range(col, col + len(near)))
        col += len(near)
        for z, q in zip(zs, near):
            region_rows(q, 1.0 - f, f, z)
        rows.add(np.zeros(len(zs), dtype=np.int64), np.array(zs), np.ones(len(zs)), np.ones(1), np.full(1, np.inf))
    region_rows(i, 1.0, 0.0, None)
    region_rows(j, 0.0, 1.0, None)
    # b - a within the box [-r, r]
    rows.add(
        np.repeat(np.arange(d), 2),
        np.ravel(np.column_stack([d + np.arange(d), np.arange(d)])),
        np.tile([1.0, -1.0], d),
        -r,
        r,
    )
    n_col = 2 * d + n_bin
    col_lo = np.concatenate([p_lo, p_lo, np.zeros(n_bin)])
    col_hi = np.concatenate([p_hi, p_hi, np.ones(n_bin)])
    obj = np.zeros(n_col)
    if cost is not None:
        obj[: 2 * d] = cost
    lp = csc_lp(
        n_col,
        rows.n_row,
        *rows.coo(),
        obj,
        col_lo,
        col_hi,
        *rows.bounds(),
        integrality=[highspy.HighsVarType.kContinuous] * (2 * d) + [highspy.HighsVarType.kInteger] * n_bin,
    )
    hs.passModel(lp)
    hs.setOptionValue("time_limit", 5.0)
    hs.run()
    status = hs.getModelStatus()
    S = highspy.HighsModelStatus
    if cost is not None:
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        return float(hs.getInfo().mip_dual_bound)
    if status == S.kOptimal:
        x = np.asarray(hs.getSolution().col_value)
        return x[:d], x[d : 2 * d]
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return None
    return "undecided"


def pair_boxes(
    problem: ReachProblem,
    abstraction: Abstraction,
    pairs: tuple[tuple[int, ...], ...],
    *,
    reach: tuple[np.ndarray, np.ndarray] | None = None,
) -> dict[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """For each pair (i, j) of ``pairs`` whose regions do not touch (a step between them
    passes through other regions): boxes that hold the two ends of every segment-safe
    step from region i to region j, (a_lo, a_hi, b_lo, b_hi), a in region i and b in
    region j. Each bound is the dual bound of the pair's MILP (module docstring, with
    the points at :data:`START_FRACTIONS`) minimising or maximising that coordinate: a
    relaxation's bound, so the boxes hold every such step (in a maze, the ends of a step
    between two corridors that meet at a doorway lie near the doorway, not anywhere in
    the corridors). Both (i, j) and (j, i) are keyed."""
    from plansynth.reach.lazy.bounds.adjacency import touching

    regions = abstraction.regions
    k = len(regions)
    out: dict[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = {}
    if k == 0:
        return out
    lo, hi, _, r = step_boxes(problem, regions, reach)
    d = len(r)
    near_pairs = [set(a) for a in touching(abstraction)]
    hs = new_highs()
    for i in range(k):
        for j in pairs[i]:
            if j < i or j in near_pairs[i]:
                continue
            checkpoint()
            w_lo = np.maximum(lo[i], lo[j]) - r
            w_hi = np.minimum(hi[i], hi[j]) + r
            near = np.nonzero(np.all(lo <= w_hi, axis=1) & np.all(hi >= w_lo, axis=1))[0].tolist()
            box_lo, box_hi = np.minimum(lo[i], lo[j]), np.maximum(hi[i], hi[j])
            bound = np.concatenate([box_lo, box_lo, box_hi, box_hi])  # a_lo, b_lo, a_hi, b_hi
            for c in range(2 * d):
                for sign in (1.0, -1.0):
                    cost = np.zeros(2 * d)
                    cost[c] = sign
                    v = _milp(regions, i, j, near, list(START_FRACTIONS), r, box_lo, box_hi, hs, cost=cost)
                    if v is None:  # (no such step at all)
                        break
                    if sign > 0:
                        bound[c] = max(bound[c], v)
                    else:
                        bound[2 * d + c] = min(bound[2 * d + c], -v)
            a_lo, b_lo, a_hi, b_hi = bound[:d], bound[d : 2 * d], bound[2 * d : 3 * d], bound[3 * d :]
            out[(i, j)] = (a_lo, a_hi, b_lo, b_hi)
            out[(j, i)] = (b_lo, b_hi, a_lo, a_hi)
    return out

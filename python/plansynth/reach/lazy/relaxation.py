"""Proofs for segment-safe claims by a relaxation of segment safety (beyond
Shoukry et al., CDC 2016).

The lazy loop's segment-safe search keeps each segment inside one convex region, which
is sufficient for safety but not necessary, so the horizons it refutes are refuted only
for plans through the decomposition (see :mod:`plansynth.reach.lazy.loop`). This module
refutes horizons for the problem itself. A segment that avoids every obstacle's interior
has *every* point free, in particular the ``k - 1`` points that divide it into ``k``
equal parts; those points are linear in the two states, so

    the samples p_0..p_N and the points p_t + j/k (p_{t+1} - p_t), j = 1..k-1,
    all outside every obstacle's interior

is a *necessary* condition for a segment-safe trajectory, and a mixed-integer program:
per point and convex obstacle piece, binaries choose a face whose closed outer
half-space holds the point (big-M with the largest violation over the workspace box).
When HiGHS proves it infeasible at horizon N, no segment-safe trajectory of horizon N
exists. The relaxation tightens as ``k`` grows (``k = 1``: samples only).

Conventions, the same as the decomposition's: the free space is the workspace minus the
obstacles *without zero-width slits* (a face flush with the workspace's boundary offers
no room; see the loop's docstring). A non-convex polygon is split into triangles, whose
shared edges the relaxation counts as free (looser, so still sound).

When the robot starts at rest (``A x_0 = x_0``), a trajectory of horizon N - 1 can wait
one step and become one of horizon N, so one infeasible MILP at h - 1 proves that no
horizon below h is feasible (:func:`refute_below`).

>>> from plansynth.reach.families import maze
>>> refute_below(maze(1), 57, seconds=60)   # the lazy planner's 57 on maze-1 is minimal
True
"""

from __future__ import annotations

import math
import time

import highspy
import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.geometry import convex_pieces, halfspaces
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.problem import ReachProblem

__all__ = ["relaxation_feasible", "refute_below", "SUBDIVISIONS"]

#: Points per segment the relaxation keeps free (the samples and k - 1 between them).
SUBDIVISIONS = 4


def _pieces(problem: ReachProblem) -> list[tuple[np.ndarray, np.ndarray]]:
    out = []
    for o in problem.obstacles:
        out += convex_pieces(o)
    return out


def relaxation_feasible(
    problem: ReachProblem, horizon: int, *, subdivisions: int = SUBDIVISIONS, seconds: float = math.inf
) -> bool | None:
    """Does the relaxation (see the module docstring) have a solution of exactly
    ``horizon`` steps? True, False (then no segment-safe trajectory of this horizon
    exists), or None (HiGHS's time limit, or a status it did not decide)."""
    deadline = time.perf_counter() + seconds
    if problem.robot_shape is not None and not problem.robot_shape.is_point:
        from plansynth.reach.robot import configuration_space

        problem = configuration_space(problem)
    k = max(1, int(subdivisions))
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = np.array(dyn.position)
    d = len(pos)
    N = int(horizon)
    T = N + 1
    n_x, n_u = T * n, N * m
    ws_lo, ws_hi = np.asarray(problem.workspace.lo, float), np.asarray(problem.workspace.hi, float)
    rows = Rows(on_add=checkpoint)
    ai, aj = np.nonzero(A)
    bi, bj = np.nonzero(B)
    for t in range(N):  # x_{t+1} - A x_t - B u_t = 0
        rows.add(
            np.concatenate([np.arange(n), ai, bi]),
            np.concatenate([(t + 1) * n + np.arange(n), t * n + aj, n_x + t * m + bj]),
            np.concatenate([np.ones(n), -A[ai, aj], -B[bi, bj]]),
            np.zeros(n),
            np.zeros(n),
        )
    Hg, hg = (np.asarray(a, float) for a in halfspaces(problem.goal))
    kg = Hg.shape[0]
    rows.add(np.repeat(np.arange(kg), d), np.tile(N * n + pos, kg), Hg.ravel(), np.full(kg, -np.inf), hg)
    # the points kept free: (t, j) is p_t + j/k (p_{t+1} - p_t)
    points = [(t, j) for t in range(N + 1) for j in range(k if t < N else 1)]
    n_bin = 0
    for H, h in _pieces(problem):
        lo_side = (np.minimum(H * ws_lo, H * ws_hi)).sum(axis=1)  # min over the workspace of H_f p
        hi_side = (np.maximum(H * ws_lo, H * ws_hi)).sum(axis=1)
        # outside the piece's interior: -H_f p <= -h_f for some face f ("beyond face f")
        faces = [f for f in range(len(h)) if h[f] < hi_side[f] - 1e-12]  # (a flush face leaves a slit only)
        if any(h[f] <= lo_side[f] for f in range(len(h))):
            continue  # the whole workspace lies beyond some face: never in the way
        for t, j in points:
            lam = j / k
            zs = n_x + n_u + n_bin + np.arange(len(faces))
            n_bin += len(faces)
            for z, f in zip(zs, faces):
                M = h[f] - lo_side[f]
                # H_f ((1 - lam) p_t + lam p_{t+1}) - M z >= h_f - M
                cols = [t * n + pos] + ([(t + 1) * n + pos] if lam > 0 else [])
                vals = [(1 - lam) * H[f]] + ([lam * H[f]] if lam > 0 else [])
                rows.add(
                    np.zeros(d * len(cols) + 1, dtype=np.int64),
                    np.concatenate(cols + [[z]]),
                    np.concatenate(vals + [[-M]]),
                    np.array([h[f] - M]),
                    np.array([np.inf]),
                )
            rows.add(np.zeros(len(faces), dtype=np.int64), zs, np.ones(len(faces)), np.ones(1), np.full(1, np.inf))
    n_col = n_x + n_u + n_bin
    s_lo, s_hi = problem.state_box
    col_lo = np.concatenate([np.tile(s_lo, T), np.full(n_u, -problem.input_bound), np.zeros(n_bin)])
    col_hi = np.concatenate([np.tile(s_hi, T), np.full(n_u, problem.input_bound), np.ones(n_bin)])
    col_lo[:n] = col_hi[:n] = problem.start
    lp = csc_lp(
        n_col,
        rows.n_row,
        *rows.coo(),
        np.zeros(n_col),
        col_lo,
        col_hi,
        *rows.bounds(),
        integrality=[highspy.HighsVarType.kContinuous] * (n_x + n_u) + [highspy.HighsVarType.kInteger] * n_bin,
    )
    hs = new_highs()
    hs.passModel(lp)
    left = deadline - time.perf_counter()
    if left <= 0:
        return None
    if math.isfinite(left):
        hs.setOptionValue("time_limit", max(1e-3, float(left)))
    hs.run()
    status = hs.getModelStatus()
    S = highspy.HighsModelStatus
    if status == S.kOptimal:
        return True
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return False
    return None


def refute_below(
    problem: ReachProblem, horizon: int, *, lowest: int = 0, subdivisions: int = SUBDIVISIONS, seconds: float = math.inf
) -> bool:
    """Is it proved that no segment-safe trajectory has a horizon below ``horizon``?
    With a start at rest one relaxation MILP at ``horizon - 1`` decides it (waiting at
    the start turns a shorter trajectory into one of that horizon); otherwise one MILP
    per horizon ``lowest..horizon-1`` (``lowest``: a proved lower bound). False when
    some relaxation has a solution or the time runs out."""
    deadline = time.perf_counter() + seconds
    if horizon <= lowest:
        return True
    tops = [horizon - 1] if problem.starts_at_rest else range(max(0, lowest), horizon)
    for N in tops:
        if (
            relaxation_feasible(problem, N, subdivisions=subdivisions, seconds=deadline - time.perf_counter())
            is not False
        ):
            return False
    return True

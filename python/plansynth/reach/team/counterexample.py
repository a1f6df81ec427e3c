"""The counterexample of an infeasible component LP of a team plan (Shoukry et al.,
CDC 2016, Section V; the SMC encoding of separation, CDC 2017, Section IV): the
certificate checked, its literals and flags, and a deletion filter that shrinks it.

**Counterexamples.** An infeasible component LP gives a Farkas certificate (HiGHS's dual
ray), checked here in floating point: with ``d = A^T y``, the values ``y^T (A x)`` allows
by the row bounds and ``d^T x`` allows by the column bounds must be disjoint intervals
(coefficients below 1e-10 of the scale count as rounding). Its rows give the literals of
the :class:`~plansynth.reach.team.plans.TeamConflict` (region rows: the robot, step and
region; side rows: the pair, step and side) and its flags (goal and end-state rows:
``goal``; moving-obstacle rows: ``timed``; the start columns, when the certificate fails
without them: ``start``). Without a checked certificate the conflict is the whole
component's plan at this horizon, marked uncertified (the planner then claims no
infeasibility).
"""

from __future__ import annotations

import math

import numpy as np

from plansynth.reach.team.component_lp import GOAL, INF, MOVE, ComponentLp
from plansynth.reach.team.plans import TeamConflict

__all__ = ["component_conflict"]

#: the deletion filter runs on conflicts of at most this many literals
MINIMIZE_MAX_LITERALS = 24


def certifies(lp: ComponentLp, y: np.ndarray, rb: tuple, cb: tuple) -> bool:
    """Does the ray ``y`` prove the LP with row bounds ``rb`` and column bounds ``cb``
    infeasible? (the interval test of the module docstring)"""
    R, C, V = lp.coo
    rlo, rhi = rb
    clo, chi = cb
    d = np.bincount(C, weights=V * y[R], minlength=lp.ncol)
    scale = float(np.sum(np.abs(y) * np.bincount(R, weights=np.abs(V), minlength=len(y)))) or 1.0
    d[np.abs(d) <= 1e-10 * scale] = 0.0
    nz = y != 0
    yr, lo_r, hi_r = y[nz], rlo[nz], rhi[nz]
    with np.errstate(invalid="ignore"):
        row_min = float(np.sum(np.where(yr > 0, yr * lo_r, yr * hi_r)))
        row_max = float(np.sum(np.where(yr > 0, yr * hi_r, yr * lo_r)))
        dn = d != 0
        dc, lo_c, hi_c = d[dn], clo[dn], chi[dn]
        col_min = float(np.sum(np.where(dc > 0, dc * lo_c, dc * hi_c)))
        col_max = float(np.sum(np.where(dc > 0, dc * hi_c, dc * lo_c)))
    vals = (row_min, row_max, col_min, col_max)
    if any(math.isnan(v) for v in vals):
        return False
    margin = 1e-7 * (1.0 + max((abs(v) for v in vals if math.isfinite(v)), default=0.0))
    return col_max + margin < row_min or row_max + margin < col_min


def ray_support(lp: ComponentLp, ray: np.ndarray | None, rb: tuple, cb: tuple) -> np.ndarray | None:
    """The ray, its negligible entries dropped when it still certifies, or None
    when it does not certify."""
    if ray is None or len(ray) != lp.rows.n_row:
        return None
    big = float(np.max(np.abs(ray))) if ray.size else 0.0
    if big == 0.0:
        return None
    y = np.where(np.abs(ray) <= 1e-9 * big, 0.0, ray)
    if certifies(lp, y, rb, cb):
        return y
    return ray if certifies(lp, ray, rb, cb) else None


def component_conflict(lp: ComponentLp, ray: np.ndarray | None) -> TeamConflict:
    """The counterexample of the infeasible LP (see the module docstring): the
    literals and flags of the certificate's support, shrunk by a deletion filter
    (each literal, the goal rows and the start dropped in turn when the LP stays
    infeasible without them), and the final certificate checked."""
    kind = np.concatenate(lp.kind)
    lit = np.concatenate(lp.lit)
    t_lo, t_hi = np.concatenate(lp.t_lo), np.concatenate(lp.t_hi)
    y = ray_support(lp, ray, lp.rb, lp.cb)
    if y is None:
        return trivial(lp)
    groups: dict[tuple, list[int]] = {}
    for row in np.flatnonzero(lit >= 0):
        groups.setdefault(lp.literals[lit[row]], []).append(int(row))
    goal_rows = np.flatnonzero(kind == GOAL)
    sup = np.flatnonzero(y)
    keep = {lp.literals[i] for i in lit[sup] if i >= 0}
    use_goal = bool(np.any(kind[sup] == GOAL))
    # the LP with only the support's literals (and the goal rows when used)
    rlo, rhi = lp.rb[0].copy(), lp.rb[1].copy()
    free = [r for key, rows in groups.items() if key not in keep for r in rows]
    if not use_goal:
        free += goal_rows.tolist()
    rlo[free], rhi[free] = -INF, INF
    clo, chi = lp.cb[0].copy(), lp.cb[1].copy()
    order = sorted(keep, key=lambda k: (k[0] != "at", k))
    # a conflict of one or two literals is small already: only its anchors are tried
    candidates: list = (["goal"] if use_goal else []) + (order if len(keep) > 2 else []) + ["start"]
    if len(keep) <= MINIMIZE_MAX_LITERALS:
        lp.set_bounds(rlo, rhi, clo, chi)
        for c in candidates:
            if (c == "goal" and not use_goal) or (c not in ("goal", "start") and c not in keep):
                continue
            if c == "start":
                cols = lp.start_columns()
                relaxed = lp.col_bounds(start=False)
                c2, h2 = clo.copy(), chi.copy()
                c2[cols], h2[cols] = relaxed[0][cols], relaxed[1][cols]
                if certifies(lp, y, (rlo, rhi), (c2, h2)):
                    clo, chi = c2, h2
                    continue
            trial = (rlo.copy(), rhi.copy(), clo.copy(), chi.copy())
            rows = goal_rows if c == "goal" else None if c == "start" else np.asarray(groups[c])
            if rows is not None:
                trial[0][rows], trial[1][rows] = -INF, INF
            else:
                cols = lp.start_columns()
                relaxed = lp.col_bounds(start=False)
                trial[2][cols], trial[3][cols] = relaxed[0][cols], relaxed[1][cols]
            lp.set_bounds(*trial)
            status, _, trial_ray = lp.run()
            if status == "infeasible":
                rlo, rhi, clo, chi = trial
                if c == "goal":
                    use_goal = False
                elif c != "start":
                    keep.discard(c)
                y_new = ray_support(lp, trial_ray, (rlo, rhi), (clo, chi))
                if y_new is not None:  # what the new certificate does not use goes too
                    y = y_new
                    used = {lp.literals[i] for i in lit[np.flatnonzero(y)] if i >= 0}
                    for gone in keep - used:
                        rows = np.asarray(groups[gone])
                        rlo[rows], rhi[rows] = -INF, INF
                    keep &= used
                    if use_goal and not np.any(kind[np.flatnonzero(y)] == GOAL):
                        rlo[goal_rows], rhi[goal_rows] = -INF, INF
                        use_goal = False
        lp.set_bounds(rlo, rhi, clo, chi)
    final = ray_support(lp, y, (rlo, rhi), (clo, chi))
    if final is None:  # the filtered LP's last ray did not check: keep the first certificate
        final = ray_support(lp, ray, lp.rb, lp.cb)
        if final is None:
            return trivial(lp)
        rlo, rhi = lp.rb
        clo, chi = lp.cb
    sup = np.flatnonzero(final)
    lits = {lp.literals[i] for i in lit[sup] if i >= 0}
    start_cols = lp.start_columns()
    relaxed = lp.col_bounds(start=False)
    clo2, chi2 = clo.copy(), chi.copy()
    clo2[start_cols], chi2[start_cols] = relaxed[0][start_cols], relaxed[1][start_cols]
    return TeamConflict(
        tuple(lits),
        start=not certifies(lp, final, (rlo, rhi), (clo2, chi2)),
        goal=bool(np.any(kind[sup] == GOAL)),
        timed=bool(np.any(kind[sup] == MOVE)),
        horizon=lp.L,
        first_time=int(t_lo[sup].min()),
        last_time=int(t_hi[sup].max()),
    )


def trivial(lp: ComponentLp) -> TeamConflict:
    """No checked certificate: the whole plan of the component at this horizon."""
    return TeamConflict(tuple(set(lp.literals)), start=True, goal=True, timed=True, horizon=lp.L, certified=False)

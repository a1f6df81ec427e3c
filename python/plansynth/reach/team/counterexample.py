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

**Shrinking.** The deletion filter (:func:`shrink`) does not rerun the component LP: it
runs on a :class:`RowSubset`, the rows of the certificate's literals and the
literal-free rows within the steps its support spans, a small LP next to the component's
over the whole horizon. Each of its LPs is a relaxation of the component LP with the
literals kept, so an infeasible one refutes them, and each of its certificates, zero on
the other rows, is one of the component LP (its rows touch no other column); the final
certificate is checked on the component LP itself.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from plansynth.reach.highs import pass_csc
from plansynth.reach.team.component_lp import GOAL, INF, MOVE, ComponentLp, load_bounds, run_lp
from plansynth.reach.team.plans import TeamConflict

__all__ = ["component_conflict", "shrink", "RowSubset", "certifies", "ray_support"]

#: the deletion filter runs on conflicts of at most this many literals
MINIMIZE_MAX_LITERALS = 24
#: the deletion filter tries dropping literals only from conflicts of more than this many
SHRINK_LITERALS_ABOVE = 2


def certifies(lp: Any, y: np.ndarray, rb: tuple, cb: tuple) -> bool:
    """Does the ray ``y`` prove the LP (``lp.coo``, ``lp.ncol``) with row bounds ``rb``
    and column bounds ``cb`` infeasible? (the interval test of the module docstring)"""
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


def ray_support(lp: Any, ray: np.ndarray | None, rb: tuple, cb: tuple) -> np.ndarray | None:
    """The ray, its negligible entries dropped when it still certifies, or None
    when it does not certify."""
    if ray is None or len(ray) != lp.n_row:
        return None
    big = float(np.max(np.abs(ray))) if ray.size else 0.0
    if big == 0.0:
        return None
    y = np.where(np.abs(ray) <= 1e-9 * big, 0.0, ray)
    if certifies(lp, y, rb, cb):
        return y
    return ray if certifies(lp, ray, rb, cb) else None


class RowSubset:
    """The component LP restricted to the rows ``rows`` and the columns they touch,
    with its own HiGHS model (no objective): every LP of it is a relaxation of the
    component LP, so an infeasible one refutes the literals of its rows, and its
    certificate, zero elsewhere, is one of the component LP (its rows touch no
    other column)."""

    def __init__(self, lp: ComponentLp, rows: np.ndarray) -> None:
        R, C, V = lp.coo
        new_row = np.full(lp.n_row, -1)
        new_row[rows] = np.arange(len(rows))
        entries = new_row[R] >= 0
        self.cols = np.flatnonzero(np.bincount(C[entries], minlength=lp.ncol))  # (np.unique, without numpy.ma)
        new_col = np.full(lp.ncol, -1)
        new_col[self.cols] = np.arange(len(self.cols))
        self.rows = rows
        self.n_row, self.ncol = len(rows), len(self.cols)
        self.coo = (new_row[R[entries]], new_col[C[entries]], V[entries])
        self.rb = (lp.rb[0][rows], lp.rb[1][rows])
        self.cb = (lp.cb[0][self.cols], lp.cb[1][self.cols])
        self.clock, self.stats = lp.clock, lp.owner.stats
        self.h = lp.owner.highs("subset")
        pass_csc(self.h, self.ncol, self.n_row, *self.coo, np.zeros(self.ncol), *self.cb, *self.rb)

    def run(self) -> tuple[str, np.ndarray | None, np.ndarray | None]:
        return run_lp(self.h, self.clock, self.stats)

    def set_bounds(self, rlo: np.ndarray, rhi: np.ndarray, clo: np.ndarray, chi: np.ndarray) -> None:
        load_bounds(self.h, rlo, rhi, clo, chi)

    def full(self, y: np.ndarray, n_row: int) -> np.ndarray:
        """A ray of this LP as one of the component LP (``n_row`` rows)."""
        out = np.zeros(n_row)
        out[self.rows] = y
        return out


def component_conflict(lp: ComponentLp, ray: np.ndarray | None) -> TeamConflict:
    """The counterexample of the infeasible LP (see the module docstring): the
    literals and flags of the certificate's support, shrunk by a deletion filter
    (:func:`shrink`), and the final certificate checked on the component LP."""
    kind = np.concatenate(lp.kind)
    lit = np.concatenate(lp.lit)
    t_lo, t_hi = np.concatenate(lp.t_lo), np.concatenate(lp.t_hi)
    first = ray_support(lp, ray, lp.rb, lp.cb)
    if first is None:
        return trivial(lp)
    sup = np.flatnonzero(first)
    n_lits = len({lp.literals[i] for i in lit[sup] if i >= 0})
    y = first
    if n_lits <= MINIMIZE_MAX_LITERALS:
        y = shrink(lp, first, kind, lit, t_lo, t_hi)
    final = ray_support(lp, y, lp.rb, lp.cb)
    if final is None:  # the filter's last ray did not check: keep the first certificate
        final = first
    sup = np.flatnonzero(final)
    lits = {lp.literals[i] for i in lit[sup] if i >= 0}
    start_cols = lp.start_columns()
    relaxed = lp.col_bounds(start=False)
    clo2, chi2 = lp.cb[0].copy(), lp.cb[1].copy()
    clo2[start_cols], chi2[start_cols] = relaxed[0][start_cols], relaxed[1][start_cols]
    return TeamConflict(
        tuple(lits),
        start=not certifies(lp, final, lp.rb, (clo2, chi2)),
        goal=bool(np.any(kind[sup] == GOAL)),
        timed=bool(np.any(kind[sup] == MOVE)),
        horizon=lp.L,
        first_time=int(t_lo[sup].min()),
        last_time=int(t_hi[sup].max()),
    )


def shrink(
    lp: ComponentLp, y: np.ndarray, kind: np.ndarray, lit: np.ndarray, t_lo: np.ndarray, t_hi: np.ndarray
) -> np.ndarray:
    """The deletion filter: the goal rows, each literal (of a conflict of more than
    :data:`SHRINK_LITERALS_ABOVE`) and the start dropped in turn when the LP stays
    infeasible without them. It runs on the :class:`RowSubset` of the certificate
    ``y``: the rows of its literals (and the goal rows when it uses them) and the
    literal-free rows, within the steps its support spans. Returns a certificate of
    the component LP (the last one found; the caller checks it)."""
    sup = np.flatnonzero(y)
    keep = {lp.literals[i] for i in lit[sup] if i >= 0}
    use_goal = bool(np.any(kind[sup] == GOAL))
    # each literal index's key among those kept (-1: another literal; the last entry: index -1, none)
    key_id = {key: k for k, key in enumerate(keep)}
    kept_as = np.array([key_id.get(key, -1) for key in lp.literals] + [-1], dtype=np.int64)
    wanted = kept_as >= 0
    wanted[-1] = True  # index -1: no literal
    inside = (t_lo >= t_lo[sup].min()) & (t_hi <= t_hi[sup].max())
    rows = np.flatnonzero(inside & wanted[lit] & ((kind != GOAL) | use_goal))
    sub = RowSubset(lp, rows)
    ys = y[rows]
    sub_lit, sub_kind = lit[rows], kind[rows]
    sub_key = kept_as[sub_lit]
    groups = {key: np.flatnonzero(sub_key == k) for key, k in key_id.items()}
    goal_rows = np.flatnonzero(sub_kind == GOAL)
    is_start = np.zeros(lp.ncol, dtype=bool)
    is_start[lp.start_columns()] = True
    start_cols = np.flatnonzero(is_start[sub.cols])
    relaxed = lp.col_bounds(start=False)
    relaxed_lo, relaxed_hi = relaxed[0][sub.cols[start_cols]], relaxed[1][sub.cols[start_cols]]
    rlo, rhi = sub.rb[0].copy(), sub.rb[1].copy()
    clo, chi = sub.cb[0].copy(), sub.cb[1].copy()
    order = sorted(keep, key=lambda k: (k[0] != "at", k))
    # a conflict of one or two literals is small already: only its anchors are tried
    candidates: list = (["goal"] if use_goal else []) + (order if len(keep) > SHRINK_LITERALS_ABOVE else [])
    candidates += ["start"] if len(start_cols) else []
    for c in candidates:
        if (c == "goal" and not use_goal) or (c not in ("goal", "start") and c not in keep):
            continue
        trial = (rlo.copy(), rhi.copy(), clo.copy(), chi.copy())
        if c == "start":
            trial[2][start_cols], trial[3][start_cols] = relaxed_lo, relaxed_hi
            if certifies(sub, ys, trial[:2], trial[2:]):
                clo, chi = trial[2], trial[3]
                continue
        else:
            rows_c = goal_rows if c == "goal" else groups[c]
            trial[0][rows_c], trial[1][rows_c] = -INF, INF
        sub.set_bounds(*trial)
        status, _, trial_ray = sub.run()
        if status != "infeasible":
            continue
        rlo, rhi, clo, chi = trial
        if c == "goal":
            use_goal = False
        elif c != "start":
            keep.discard(c)
        y_new = ray_support(sub, trial_ray, (rlo, rhi), (clo, chi))
        if y_new is None:
            continue
        ys = y_new  # what the new certificate does not use goes too
        nz = np.flatnonzero(ys)
        used = {lp.literals[i] for i in sub_lit[nz] if i >= 0}
        for gone in keep - used:
            rlo[groups[gone]], rhi[groups[gone]] = -INF, INF
        keep &= used
        if use_goal and not np.any(sub_kind[nz] == GOAL):
            rlo[goal_rows], rhi[goal_rows] = -INF, INF
            use_goal = False
    return sub.full(ys, lp.n_row)


def trivial(lp: ComponentLp) -> TeamConflict:
    """No checked certificate: the whole plan of the component at this horizon."""
    return TeamConflict(tuple(set(lp.literals)), start=True, goal=True, timed=True, horizon=lp.L, certified=False)

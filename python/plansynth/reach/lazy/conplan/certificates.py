"""CON-PLAN's certificates (see :mod:`plansynth.reach.lazy.conplan`): conflicts from
Farkas rays (dual rays of infeasible LPs, checked in floating point), shrunk to the
rows the proof needs, a deletion filter over the region literals, and the start state
dropped when the proof does not need it."""

from __future__ import annotations

import math
from collections.abc import Sequence

import highspy
import numpy as np

from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.conplan.lp import DYN, GOAL, INF, _Bounds, _Layout, _Slot

MINIMIZE_MAX_LITERALS = 16


def _farkas_certifies(b: _Bounds, y: np.ndarray, d: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> bool:
    """Does ``y`` (zero outside ``rows``) prove that those rows, with the bounds of the
    columns ``cols`` (the other columns free), have no solution?

    With ``d = A^T y``, every solution has ``y^T (A x) = d^T x``; the row bounds confine
    the left side to an interval, the column bounds the right side to another, and
    disjoint intervals (by a safety margin) prove infeasibility. The tiny coefficients
    of ``d`` outside ``cols`` are charged to the margin with their columns' bounds.
    """
    yr = y[rows]
    lo_r, hi_r = b.row_lo[rows], b.row_hi[rows]
    with np.errstate(invalid="ignore"):
        row_min = float(np.where(yr > 0, yr * lo_r, yr * hi_r).sum())
        row_max = float(np.where(yr > 0, yr * hi_r, yr * lo_r).sum())
        dc = d[cols]
        col_min = float(np.where(dc > 0, dc * b.col_lo[cols], dc * b.col_hi[cols]).sum())
        col_max = float(np.where(dc > 0, dc * b.col_hi[cols], dc * b.col_lo[cols]).sum())
    if any(math.isnan(v) for v in (row_min, row_max, col_min, col_max)):
        return False
    rest = np.setdiff1d(np.nonzero(d)[0], cols)
    bound = np.maximum(np.abs(b.col_lo[rest]), np.abs(b.col_hi[rest]))
    if np.any(~np.isfinite(bound)):
        return False
    slop = float(np.sum(np.abs(d[rest]) * bound))
    finite = [abs(v) for v in (row_min, row_max, col_min, col_max) if math.isfinite(v)]
    margin = 1e-7 * (1.0 + max(finite, default=0.0)) + slop
    return col_max + margin < row_min or row_max + margin < col_min


class _Certificates:
    """The certificate methods of :class:`~plansynth.reach.lazy.conplan.check.ConPlan`."""

    def _from_ray(self, regions: Sequence[int], fallback: Conflict, slot: _Slot | None = None) -> Conflict:
        """Shrink ``fallback``, whose infeasible LP ``slot`` (default: the plan model)
        holds, to the support of its Farkas certificate (dual ray): the rows with nonzero
        multipliers and the bounds of the columns whose combined coefficient is nonzero
        are infeasible on their own."""
        slot = self.slot if slot is None else slot
        lay, b = slot.layout, slot.bounds
        assert lay is not None and b is not None
        support = self._ray_support(slot)
        if support is None:
            self.stats.rejected += 1
            return fallback
        rows, cols, certified = support
        return self._shrunk(lay, b, regions, rows, cols, fallback, certified=certified)

    def _ray_support(self, slot: _Slot) -> tuple[np.ndarray, np.ndarray, bool] | None:
        """The rows and columns of the Farkas certificate (dual ray) of the infeasible
        LP ``slot`` holds, and whether it checks (:func:`_farkas_certifies`); None when
        HiGHS has no ray."""
        lay, b = slot.layout, slot.bounds
        assert lay is not None and b is not None
        coo = self._slot_coo(slot)
        self._ray_part = None
        if self._no_ray:  # the LP was decided by the fallback method
            return None
        if slot.parts is None:
            status, has_ray, ray = slot.highs.getDualRay()
            y = np.asarray(ray, dtype=float)
        else:  # the ray of the infeasible part, zero on the other parts' rows
            self._ray_part = slot.infeasible_part
            part = slot.parts[slot.infeasible_part]
            status, has_ray, ray = part.highs.getDualRay()
            y = np.zeros(lay.n_row)
            if has_ray:
                y[part.rows] = np.asarray(ray, dtype=float)
        self.stats.ray_calls += 1
        scale = float(np.max(np.abs(y))) if (has_ray and y.size) else 0.0
        if status != highspy.HighsStatus.kOk or not scale > 0:
            return None
        y = y / scale
        # free rows (outside the LP's window, or not applying) take no part in a
        # certificate; HiGHS may leave round-off on them: drop it (the check below decides)
        y[(b.row_lo <= -INF) & (b.row_hi >= INF)] = 0.0
        rows = np.nonzero(np.abs(y) > 1e-9)[0]
        R, C, V = coo
        dcol = np.bincount(C, weights=V * y[R], minlength=lay.n_col)
        cols = np.nonzero(np.abs(dcol) > 1e-9)[0]
        return rows, cols, _farkas_certifies(b, y, dcol, rows, cols)

    def _certified_prefix(self) -> int | None:
        """For the infeasible LP the plan model holds: the latest region literal its
        checked Farkas certificate needs, when that certificate uses no goal row (so
        the prefix up to that time is infeasible as well), else None."""
        support = self._ray_support(self.slot)
        if support is None or not support[2]:
            return None
        kind, lit, _ = self.slot.layout.meta  # type: ignore[union-attr]
        rows = support[0]
        if np.any(kind[rows] == GOAL):
            return None
        times = lit[rows]
        return int(times.max()) if times.size and times.max() >= 0 else None

    def _minimize(self, regions: Sequence[int], c: Conflict) -> Conflict:
        """Deletion filter: drop each literal whose region rows the conflict does not
        need (the LP without them is still infeasible), so that no literal can be
        dropped from the result; then shrink by the last infeasible LP's certificate.
        The LPs span only the conflict's time steps (``c.first_time..c.last_time``)."""
        if not 1 < len(c.literals) <= MINIMIZE_MAX_LITERALS:
            return c  # long ones (no Farkas ray to shrink them first) would cost an LP each
        N = len(regions) - 1
        span = (c.first_time, c.last_time)
        # in a split model only the part of c's certificate: a literal it does not need
        # leaves that part infeasible (another part's infeasibility is not looked for)
        part = self._ray_part
        keep = list(c.literals)
        last_infeasible = False
        for lit in list(keep):
            trial = [x for x in keep if x != lit]
            col = self._solve_model(
                N, dict(trial), "minimize", goal=c.anchored_goal, anchored_start=c.anchored_start, span=span, part=part
            )
            last_infeasible = col is None
            if last_infeasible:
                keep = trial
        if len(keep) == len(c.literals):
            return c
        if not last_infeasible:  # HiGHS must hold the kept set's (infeasible) LP
            if (
                self._solve_model(
                    N,
                    dict(keep),
                    "minimize",
                    goal=c.anchored_goal,
                    anchored_start=c.anchored_start,
                    span=span,
                    part=part,
                )
                is not None
            ):  # pragma: no cover
                return c
        smaller = Conflict(
            tuple(keep),
            anchored_start=c.anchored_start,
            anchored_goal=c.anchored_goal,
            horizon=c.horizon,
            first_time=span[0],
            last_time=span[1],
        )
        return self._from_ray(regions, smaller, self.span_slot)

    def _unanchor(self, regions: Sequence[int], c: Conflict) -> Conflict:
        """Try to drop the start from a start-anchored conflict: if the LP of its claims
        with x_0 free (within the state bounds) is infeasible too, shrink that one; a
        conflict that uses neither the start nor the goal holds at every time shift."""
        if not c.anchored_start or not c.literals:
            return c
        N = len(regions) - 1
        span = (c.first_time, c.last_time)
        col = self._solve_model(
            N, dict(c.literals), "unanchor", goal=c.anchored_goal, anchored_start=False, span=span, part=self._ray_part
        )
        if col is not None:
            return c
        free = Conflict(
            c.literals,
            anchored_start=False,
            anchored_goal=c.anchored_goal,
            horizon=c.horizon,
            first_time=span[0],
            last_time=span[1],
        )
        return self._from_ray(regions, free, self.span_slot)

    def _shrunk(
        self,
        lay: _Layout,
        b: _Bounds,
        regions: Sequence[int],
        rows: np.ndarray,
        cols: np.ndarray,
        fallback: Conflict,
        *,
        certified: bool,
    ) -> Conflict:
        """The conflict of an infeasible subsystem (``rows`` and the bounds of ``cols``):
        the regions at the times of its region rows, anchored at the start when it uses
        x_0's fixed bounds, at the goal when it uses a goal row, spanning the states it
        touches. Returned when ``certified`` (a checked Farkas certificate of exactly
        these rows and bounds) or when an LP over exactly these claims is infeasible."""
        kind, lit, state = lay.meta
        n, m = lay.n, lay.m
        kinds = kind[rows]
        lit_times = sorted({int(t) for t in lit[rows] if t >= 0})
        uses_goal = bool(np.any(kinds == GOAL))
        x_cols = cols[cols < lay.n_x]
        u_cols = cols[(cols >= lay.n_x) & (cols < lay.n_x + lay.n_u)]
        x_start = lay.x(lay.t0)
        uses_start = b.anchored_start and bool(np.any((x_cols >= x_start) & (x_cols < x_start + n)))
        touched = [int(t) for t in state[rows] if t >= 0] + lit_times
        touched += [int(t) - 1 for t in state[rows[kinds == DYN]]]
        touched += [int(c) // n + lay.first for c in x_cols]
        touched += [(int(c) - lay.n_x) // m + lay.first for c in u_cols]
        conflict = Conflict(
            tuple((t, regions[t]) for t in lit_times),
            anchored_start=uses_start,
            anchored_goal=uses_goal,
            horizon=len(regions) - 1,
            first_time=0 if uses_start else min(touched, default=0),
            last_time=lay.t1 if uses_goal else max(touched, default=0),
        )
        if conflict == fallback:
            return conflict
        if self.tube is not None and not uses_start and conflict.first_time != b.origin:
            return self._placed(conflict, fallback, certified)
        if certified:
            self.stats.certified += 1
            return conflict
        if self.refutes(conflict):
            return conflict
        self.stats.rejected += 1
        return fallback

    def _placed(self, conflict: Conflict, fallback: Conflict, certified: bool) -> Conflict:
        """A problem with a tube, whose margins grow with time: a conflict without the
        start, shrunk from an LP that placed E_0 earlier than its first step, holds where
        that LP placed it, not necessarily at every time shift DIS-PLAN adds it at. It is
        kept shift-free when an LP refutes it at its earliest placement (the loosest);
        else anchored at the start, at its times (there the LP that proved it had
        margins no larger than the plan's: sound with the certificate, or when an LP
        refutes it); else the fallback."""
        if self.refutes(conflict):
            self.stats.certified += 1
            return conflict
        anchored = Conflict(
            conflict.literals,
            anchored_start=True,
            anchored_goal=conflict.anchored_goal,
            horizon=conflict.horizon,
            last_time=conflict.last_time,
        )
        if anchored != fallback and (certified or self.refutes(anchored)):
            self.stats.certified += 1
            return anchored
        self.stats.rejected += 1
        return fallback

    def refutes(self, c: Conflict, *, cold: bool = False, part: int | None = None) -> bool:
        """Is the LP of exactly what ``c`` claims infeasible? (states c.first_time ..
        c.last_time, the literals' region and segment rows, the goal and the start as
        anchored). By default in a persistent model (a window of its frame, split when
        the LPs split, warm-started); ``cold``: a fresh LP of exactly that layout.
        ``part`` (split LPs, see :meth:`span_parts`): only that part's LP, so the answer
        "infeasible" holds for the whole LP and "feasible" only for that part."""
        assign = dict(c.literals)
        if part is not None and self.span_parts() is None:
            raise ValueError("refutes(part=...) needs split LPs")
        if not cold or part is not None:
            # the span model, shared with the deletion filter: warm from the LPs that
            # just shrank this conflict
            col = self._solve_model(
                c.last_time,
                assign,
                "verify",
                goal=c.anchored_goal,
                anchored_start=c.anchored_start,
                span=(c.first_time, c.last_time),
                part=part,
            )
            return col is None
        lay = self.layout(c.first_time, c.last_time)
        self._pass_cold(lay, assign, goal=c.anchored_goal, anchored_start=c.anchored_start)
        self._cap_cold(lay)
        return self._run(self.cold, "verify") is None

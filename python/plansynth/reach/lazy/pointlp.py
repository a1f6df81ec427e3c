"""The point LP of the exact segment theory (:mod:`plansynth.reach.lazy.segtheory`,
whose docstring states its three LPs; beyond Shoukry et al., CDC 2016, Section V): every
sample in its region and every point ``p_t + (f / DENOM)(p_{t+1} - p_t)`` of a plan in
its region, over the states (start, dynamics, input and state bounds, workspace, goal),
in HiGHS; an infeasible one gives the support of its Farkas certificate (dual ray),
with some literals switched off as the deletion filter asks.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence

import highspy
import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.conplan.runs import LpBudgetExhausted
from plansynth.reach.lazy.segments import DENOM
from plansynth.reach.problem import ReachProblem

__all__ = ["PointLP", "Vias"]

Vias = Mapping[tuple[int, int], int]


class PointLP:
    """The feasibility LP of the samples and the points along the segments (see the
    module docstring), over the states lo..hi, in HiGHS (presolve off: the dual ray of an
    infeasible LP is the Farkas certificate). :meth:`load` builds it, :meth:`run` solves
    it with some literals switched off (their rows free: warm-started from the last
    basis, as the deletion filter needs). Counters: ``lp_calls``, ``seconds``."""

    def __init__(
        self,
        problem: ReachProblem,
        abstraction: Abstraction,
        clock: Clock | None = None,
        boxes: Mapping[tuple[int, int], tuple[np.ndarray, ...]] | None = None,
    ) -> None:
        from plansynth.reach.geometry import halfspaces

        self.problem = problem
        self.clock = clock
        self.boxes = {} if boxes is None else dict(boxes)
        dyn = problem.dynamics
        self.n, self.m = dyn.n_states, dyn.n_inputs
        self.pos = np.array(dyn.position, dtype=np.int64)
        self.A, self.B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        self.Hs = [np.asarray(r.H, float) for r in abstraction.regions]
        self.hs = [np.asarray(r.h, float) for r in abstraction.regions]
        self.Hg, self.hg = (np.asarray(a, float) for a in halfspaces(problem.goal))
        self.state_lo, self.state_hi = problem.state_box
        self.start = np.asarray(problem.start, float)
        self.highs = new_highs(presolve="off")
        self.tags: list[tuple] = []
        self.span = (0, 0)
        self._rows: dict[tuple, np.ndarray] = {}  # a literal's tag -> its rows
        self._hi: np.ndarray = np.zeros(0)  # the rows' upper bounds as loaded
        self._lo: np.ndarray = np.zeros(0)
        self._off: set[tuple] = set()
        self.lp_calls = 0
        self.seconds = 0.0

    def solve(
        self,
        samples: Mapping[int, int],
        vias: Vias,
        lo: int,
        hi: int,
        *,
        start: bool,
        goal: bool,
        extra: Sequence[tuple[int, int, np.ndarray, float]] = (),
        closure: tuple | None = None,
        soft: float | None = None,
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """:meth:`load`, then :meth:`run`."""
        self.load(samples, vias, lo, hi, start=start, goal=goal, extra=extra, closure=closure, soft=soft)
        return self.run()

    def load(
        self,
        samples: Mapping[int, int],
        vias: Vias,
        lo: int,
        hi: int,
        *,
        start: bool,
        goal: bool,
        extra: Sequence[tuple[int, int, np.ndarray, float]] = (),
        closure: tuple | None = None,
        soft: float | None = None,
    ) -> None:
        """Put the LP into HiGHS: the states lo..hi (x_lo = start when ``start``, p_hi in
        the goal when ``goal``), the samples (t -> region) and points ((t, f) -> region)
        within them, and ``extra`` rows ``n . p(t, f) >= c`` as (t, f, n, c) (f over
        DENOM, 0..DENOM). ``closure`` (a mission's plan): ``("loop", k)``, x_hi = x_k (a
        lasso); ``("rest",)``, some admissible input keeps x_hi where it is (a finite
        plan ending at rest: one more input column u with x_hi = A x_hi + B u); its rows
        belong to the literal ``("closure",)``. ``soft``: the extra rows and the goal's
        get a slack column each (nonnegative), and the LP minimises ``soft`` times the
        extra rows' slacks plus the goal's (a feasibility LP otherwise)."""
        n, m, pos, d = self.n, self.m, self.pos, len(self.pos)
        T = hi - lo + 1
        n_x, n_u = T * n, (T - 1) * m
        rest = closure is not None and closure[0] == "rest"
        rows = Rows()
        tags: list[tuple] = []
        ai, aj = np.nonzero(self.A)
        bi, bj = np.nonzero(self.B)
        if T > 1:  # x_{t+1} - A x_t - B u_t = 0, every step at once
            k = np.arange(T - 1)[:, None]
            r1 = np.concatenate([np.arange(n), ai, bi])
            rows.add(
                (k * n + r1[None, :]).ravel(),
                np.concatenate(
                    [(k + 1) * n + np.arange(n)[None, :], k * n + aj[None, :], n_x + k * m + bj[None, :]], axis=1
                ).ravel(),
                np.tile(np.concatenate([np.ones(n), -self.A[ai, aj], -self.B[bi, bj]]), T - 1),
                np.zeros((T - 1) * n),
                np.zeros((T - 1) * n),
            )
            tags += [("dyn",)] * ((T - 1) * n)
        points: list[tuple[int, int, np.ndarray, np.ndarray, np.ndarray, tuple]] = []
        for t, r in samples.items():
            if lo <= t <= hi:
                points.append((t, 0, self.Hs[r], np.full(len(self.hs[r]), -np.inf), self.hs[r], ("s", t, r)))
        for (t, f), r in vias.items():
            if lo <= t and t + 1 <= hi:
                points.append((t, f, self.Hs[r], np.full(len(self.hs[r]), -np.inf), self.hs[r], ("v", t, f, r)))
        for j, (t, f, nrm, c) in enumerate(extra):
            points.append((t, f, nrm[None, :], np.array([c]), np.array([np.inf]), ("x", j)))
        eye = np.eye(d)
        for t, r in samples.items():  # a step between regions that do not touch: its ends' boxes
            box = self.boxes.get((r, samples.get(t + 1, -1)))
            if box is not None and lo <= t and t + 1 <= hi:
                a_lo, a_hi, b_lo, b_hi = box
                pair = ("pair", t, r, samples[t + 1])
                points.append((t, 0, eye, a_lo, a_hi, pair))
                points.append((t + 1, 0, eye, b_lo, b_hi, pair))
        if points:
            R, C, V, L, U = [], [], [], [], []
            row = 0
            for t, f, H, lo_b, hi_b, tag in points:
                kk = H.shape[0]
                lam = f / DENOM
                for w, tt in ((1.0 - lam, t), (lam, t + 1)):
                    if w != 0.0:
                        R.append(row + np.repeat(np.arange(kk), d))
                        C.append(np.tile((tt - lo) * n + pos, kk))
                        V.append(w * H.ravel())
                L.append(lo_b)
                U.append(hi_b)
                tags.extend([tag] * kk)
                row += kk
            rows.add(np.concatenate(R), np.concatenate(C), np.concatenate(V), np.concatenate(L), np.concatenate(U))
        if goal:
            kg = len(self.hg)
            rows.add(
                np.repeat(np.arange(kg), d),
                np.tile((hi - lo) * n + pos, kg),
                self.Hg.ravel(),
                np.full(kg, -np.inf),
                self.hg,
            )
            tags += [("goal",)] * kg
        if closure is not None and closure[0] == "loop":  # x_hi - x_k = 0
            k = int(closure[1])
            assert lo <= k <= hi
            rows.add(
                np.concatenate([np.arange(n), np.arange(n)]),
                np.concatenate([(hi - lo) * n + np.arange(n), (k - lo) * n + np.arange(n)]),
                np.concatenate([np.ones(n), -np.ones(n)]),
                np.zeros(n),
                np.zeros(n),
            )
            tags += [("closure",)] * n
        elif rest:  # (A - I) x_hi + B u = 0, u the extra input columns
            M = self.A - np.eye(n)
            mi, mj = np.nonzero(M)
            rows.add(
                np.concatenate([mi, bi]),
                np.concatenate([(hi - lo) * n + mj, n_x + n_u + bj]),
                np.concatenate([M[mi, mj], self.B[bi, bj]]),
                np.zeros(n),
                np.zeros(n),
            )
            tags += [("closure",)] * n
        extra_u = m if rest else 0
        col_lo = np.concatenate([np.tile(self.state_lo, T), np.full(n_u + extra_u, -self.problem.input_bound)])
        col_hi = np.concatenate([np.tile(self.state_hi, T), np.full(n_u + extra_u, self.problem.input_bound)])
        if start:
            assert lo == 0
            col_lo[:n] = col_hi[:n] = self.start
        n_col = n_x + n_u + extra_u
        row_lo, row_hi = rows.bounds()
        R, C, V = rows.coo()
        cost = np.zeros(n_col)
        if soft is not None:  # a slack column per extra and goal row: n.p + s >= c, Hg p - s <= hg
            kind = np.array([tag[0] for tag in tags], dtype=object)
            slack = np.nonzero((kind == "x") | (kind == "goal"))[0]
            sign = np.where(kind[slack] == "x", 1.0, -1.0)
            R = np.concatenate([R, slack])
            C = np.concatenate([C, n_col + np.arange(len(slack))])
            V = np.concatenate([V, sign])
            cost = np.concatenate([cost, np.where(kind[slack] == "x", float(soft), 1.0)])
            col_lo = np.concatenate([col_lo, np.zeros(len(slack))])
            col_hi = np.concatenate([col_hi, np.full(len(slack), np.inf)])
            n_col += len(slack)
        lp = csc_lp(n_col, rows.n_row, R, C, V, cost, col_lo, col_hi, row_lo, row_hi)
        self.highs.passModel(lp)
        self.tags = tags
        self.span = (lo, hi)
        self._T = T
        self._lo, self._hi = row_lo.copy(), row_hi.copy()
        by: dict[tuple, list[int]] = {}
        for i, tag in enumerate(tags):
            for lit in _literals_of(tag):
                by.setdefault(lit, []).append(i)
        self._rows = {tag: np.array(ix, dtype=np.int32) for tag, ix in by.items()}
        self._off = set()

    def run(self, off: set[tuple] | None = None) -> tuple[np.ndarray, np.ndarray] | None:
        """Solve the loaded LP with the literals whose tags are in ``off`` switched off
        (the others as loaded): states and inputs of a solution, or None when
        infeasible. Raises LpBudgetExhausted when the budget runs out, or when HiGHS
        decides nothing."""
        off = set() if off is None else set(off)
        h = self.highs
        changed = off ^ self._off
        if changed:
            # a row is free when any literal it belongs to is off (a pair row has two)
            ix = np.unique(np.concatenate([self._rows[g] for g in changed]))
            free = np.array([any(g in off for g in _literals_of(self.tags[i])) for i in ix.tolist()])
            lo_b = np.where(free, -np.inf, self._lo[ix])
            hi_b = np.where(free, np.inf, self._hi[ix])
            h.changeRowsBounds(len(ix), ix.astype(np.int32), lo_b, hi_b)
        self._off = off
        if self.clock is not None:
            left = self.clock.remaining()
            if left <= 0:
                raise LpBudgetExhausted("budget ran out in the segment theory's LP")
            # HiGHS compares time_limit with the instance's run time summed over its runs
            h.setOptionValue("time_limit", float(h.getRunTime() + min(left, 1e9)))
        t0 = time.perf_counter()
        h.run()
        self.seconds += time.perf_counter() - t0
        self.lp_calls += 1
        status = h.getModelStatus()
        S = highspy.HighsModelStatus
        n, m, T = self.n, self.m, self._T
        if status == S.kOptimal:
            col = np.asarray(h.getSolution().col_value)
            return col[: T * n].reshape(T, n), col[T * n : T * n + (T - 1) * m].reshape(T - 1, m)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        raise LpBudgetExhausted(f"the segment theory's LP ended with HiGHS status {h.modelStatusToString(status)}")

    def support(self) -> set[tuple] | None:
        """The tags of the rows of the Farkas certificate (dual ray) of the infeasible LP
        just solved, or None when HiGHS has none."""
        status, has_ray, ray = self.highs.getDualRay()
        y = np.asarray(ray, dtype=float)
        if status != highspy.HighsStatus.kOk or not has_ray or not y.size or not np.max(np.abs(y)) > 0:
            return None
        y = y / np.max(np.abs(y))
        y[[i for i, tag in enumerate(self.tags) if any(g in self._off for g in _literals_of(tag))]] = 0.0
        return {g for i in np.nonzero(np.abs(y) > 1e-9)[0] for g in (*_literals_of(self.tags[i]), self.tags[i])}


def _literals_of(tag: tuple) -> tuple[tuple, ...]:
    """The literals (sample and point tags, and a mission plan's closure) a row of the
    point LP belongs to: a pair row belongs to both samples of its step."""
    if tag[0] in ("s", "v", "closure"):
        return (tag,)
    if tag[0] == "pair":
        _, t, i, j = tag
        return (("s", t, i), ("s", t + 1, j))
    return ()

"""The feasibility LP of a mission plan with its loop (Shoukry et al., CDC 2016,
Section V, with the loop closure missions add).

CON-PLAN's constraints over a region sequence r_0..r_L (start, dynamics, input and
state bounds, workspace, p_t in r_t and, with segment safety, p_{t+1} in r_t) plus the
closure ``x_L = x_k`` of a lasso whose loop starts at k (Biere et al.'s loop: the robot
repeats x_k..x_L forever), or, for a finite plan, the rest at x_L the finite reading
needs (the lasso of one more step in r_L closed at L). :class:`LoopLP` solves it in
HiGHS and, when it is infeasible, explains why with (time, region) literals: the loop
alone first (a refuted loop holds at every horizon and rotation), then the whole plan,
shrunk by the Farkas certificate and a deletion filter. The mission planner's theory
(:mod:`plansynth.reach.mission.theory`) and the MILP baseline's polish
(:mod:`plansynth.reach.mission.milp`) use it.
"""

from __future__ import annotations

import math
import time

import highspy
import numpy as np

from plansynth.reach.abstraction import Abstraction
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.lazy.conplan import LpBudgetExhausted, LpFailure
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["LoopLP"]


class LoopLP:
    """The feasibility LP of a region sequence (CON-PLAN's constraints: start,
    dynamics, input and state bounds, workspace, p_t in r_t and, with segment safety,
    p_{t+1} in r_t) plus the loop closure ``x_L = x_k``, in HiGHS."""

    def __init__(self, problem: ReachProblem, abstraction: Abstraction, *, segment_safe: bool = True) -> None:
        self.problem = problem
        self.regions = abstraction.regions
        self.segment_safe = segment_safe
        self.lp_calls = 0
        self.seconds = 0.0
        dyn = problem.dynamics
        self.n, self.m = dyn.n_states, dyn.n_inputs
        self.pos = np.array(dyn.position, dtype=np.int64)
        A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        ai, aj = np.nonzero(A)
        bi, bj = np.nonzero(B)
        self.dyn_nz = (ai, aj, A[ai, aj], bi, bj, B[bi, bj])
        self.Hs = [np.asarray(r.H, float) for r in abstraction.regions]
        self.hs = [np.asarray(r.h, float) for r in abstraction.regions]
        # the regions' rows as flat templates for _load: per region its rows' entries
        # (row offset, position column within a state, coefficient) and right-hand sides
        npos = len(self.pos)
        self._n_rows = np.array([H.shape[0] for H in self.Hs], dtype=np.int64)
        self._row_off = np.concatenate([[0], np.cumsum(self._n_rows)[:-1]]).astype(np.int64)
        self._ent_off = self._row_off * npos
        self._tr = np.concatenate([np.repeat(np.arange(H.shape[0]), npos) for H in self.Hs]).astype(np.int64)
        self._tc = np.concatenate([np.tile(self.pos, H.shape[0]) for H in self.Hs]).astype(np.int64)
        self._tv = np.concatenate([H.ravel() for H in self.Hs])
        self._th = np.concatenate(self.hs)
        self.state_lo, self.state_hi = problem.state_box
        self.highs = new_highs(presolve="off")  # presolve off keeps the dual ray of an infeasible LP
        self.ray_times: set[int] | None = None
        self.certified = 0
        self.warm = 0  # LPs re-solved from the last basis with literals switched off (see _lp)
        self._loaded: tuple | None = None
        # verdicts of loop-alone LPs (see loop_infeasible): (period, literals relative to
        # the loop start) -> (infeasible, the Farkas certificate's relative times or None)
        self._loop_memo: dict[tuple, tuple[bool, tuple[int, ...] | None]] = {}
        self.memo_hits = 0
        self._last_loop: tuple | None = None  # (k, L, literals) of the last loop_infeasible call
        # resting (see rests): every state with zero non-position components is an
        # equilibrium of x+ = A x (u = 0) and satisfies the state bounds, for positions
        # in the state box
        other = self._other = np.setdiff1d(np.arange(self.n), self.pos)
        eye = np.eye(self.n)
        self._rest_ok = bool(
            np.array_equal(A[:, self.pos], eye[:, self.pos])
            and np.all(self.state_lo[other] <= 0)
            and np.all(self.state_hi[other] >= 0)
            and problem.input_bound >= 0
        )
        start = np.asarray(problem.start, float)
        self._start_rests = self._rest_ok and bool(np.all(start[other] == 0))
        self._start_pos = start[self.pos]
        ws = problem.workspace
        self._rest_tol = 1e-9 * max(1.0, max(h - l for l, h in zip(ws.lo, ws.hi)))
        self.rest_answers = 0

    def solve(self, regions: tuple[int, ...], loop_start: int | None, seconds: float = math.inf) -> Trajectory | None:
        """A trajectory from the start through ``regions`` with x_L = x_loop_start, or None."""
        L = len(regions) - 1
        col = self._lp(dict(enumerate(regions)), 0, L, True, loop_start, seconds)
        if col is None:
            return None
        n, m = self.problem.dynamics.n_states, self.problem.dynamics.n_inputs
        xs = col[: (L + 1) * n].reshape(L + 1, n).copy()
        us = col[(L + 1) * n :].reshape(L, m)
        if loop_start is not None:
            xs[L] = xs[loop_start]  # the closure holds to tolerance; make it exact
        return Trajectory(states=xs, inputs=us)

    def solve_finite(self, regions: tuple[int, ...], seconds: float = math.inf) -> Trajectory | None:
        """A trajectory from the start through ``regions`` that ends at rest: some
        admissible input keeps x_L where it is (x_L = A x_L + B u, |u| <= the bound, in
        r_L), as the finite reading (the robot stays at its last state forever) needs.
        It is the lasso of one more step in r_L with the loop closed at L; the trajectory
        returned stops at x_L, or None."""
        L = len(regions) - 1
        lasso = self.solve(tuple(regions) + (regions[-1],), L, seconds)
        if lasso is None:
            return None
        return Trajectory(states=lasso.states[: L + 1], inputs=lasso.inputs[:L])

    def ends_at_rest(self, trajectory: Trajectory) -> bool:
        """x_L rests with u = 0 (every state with zero non-position components does,
        when A keeps positions and the bounds allow 0; see :meth:`rests`)."""
        return self._rest_ok and not np.any(np.asarray(trajectory.states[-1], float)[self._other])

    def rest_conflict(self, regions: tuple[int, ...], seconds: float = math.inf) -> tuple[tuple[int, int], ...]:
        """Why the finite plan ``regions`` cannot end at rest: (time, region) literals,
        a subset of the plan's, whose LP with the start and rest at x_L is infeasible
        (:meth:`conflict` on the lasso of :meth:`solve_finite`; its extra step, in r_L,
        maps back to step L)."""
        L = len(regions) - 1
        lits, _ = self.conflict(tuple(regions) + (regions[-1],), L, seconds)
        return tuple(sorted({(min(t, L), r) for t, r in lits}))

    def conflict(
        self, regions: tuple[int, ...], loop_start: int, seconds: float = math.inf, *, loop_refuted: bool = False
    ) -> tuple[tuple[tuple[int, int], ...], bool]:
        """Why the lasso has no trajectory: (literals, shifted). First the loop alone
        (states k..L, any x_k): if it is infeasible, the literals are among its steps and
        hold at every shift (``shifted``); else the whole plan from the start. Then a
        deletion filter drops every literal whose region rows the infeasibility does not
        need (each drop proved by an LP). Sound: the returned literals with the loop
        closure have an infeasible LP. ``loop_refuted``: the caller's last LP was the loop
        alone, infeasible (its model and dual ray are the loaded ones), so it is not
        solved again."""
        L, k = len(regions) - 1, loop_start
        assign = {t: regions[t] for t in range(k, L + 1)}
        first, anchored = k, False
        if loop_refuted:
            assert self._last_loop == (k, L, assign), "loop_refuted: the last loop-alone LP was another one"
        if not loop_refuted and not self.loop_infeasible(assign, k, L, seconds):
            assign, first, anchored = dict(enumerate(regions)), 0, True
            if self._lp(assign, 0, L, True, k, seconds) is not None:  # pragma: no cover - solve() said infeasible
                raise LpFailure("the loop LP is feasible on a second solve (numerically borderline)")

        def lp_infeasible(trial: dict[int, int]) -> bool:
            if anchored:
                return not self.rests(trial, True) and self._lp(trial, first, L, anchored, k, seconds) is None
            return self.loop_infeasible(trial, k, L, seconds)

        # shrink to the Farkas certificate's literals first, if that LP is still infeasible
        if self.ray_times is not None and len(self.ray_times) < len(assign):
            shrunk = {t: r for t, r in assign.items() if t in self.ray_times}
            if lp_infeasible(shrunk):
                assign = shrunk
                self.certified += 1
        keep: dict[int, int] = {}

        def infeasible(without: list[int], rest: list[int]) -> bool:
            trial = {**keep, **{t: assign[t] for t in rest}}
            return lp_infeasible(trial)

        def drop(cands: list[int], rest: list[int]) -> None:
            # keep a subset of cands that, with keep and rest, stays infeasible
            # (halves first: a conflict of a few literals costs O(k log n) LPs)
            if not cands or infeasible(cands, rest):
                return
            if len(cands) == 1:
                keep[cands[0]] = assign[cands[0]]
                return
            half = len(cands) // 2
            a, b = cands[:half], cands[half:]
            drop(a, rest + b)
            drop(b, rest)

        drop(sorted(assign), [])
        return tuple(sorted(keep.items())), not anchored

    def rests(self, assign: dict[int, int], anchored: bool) -> bool:
        """Is there a trajectory that rests at one point p, in every literal's region
        (the start's position when ``anchored``)? Then the LP of ``assign`` is feasible
        (x_t = (p, 0) for all t, u = 0: the dynamics, every sample and segment row and
        the closure x_L = x_k hold), and the deletion filter of :meth:`conflict` needs
        no LP to keep a literal. p: the start's position, or the mean of the first
        region's vertices that lie in all the others (within a tolerance far below
        HiGHS's). Only ever answers "feasible", and a "feasible" only keeps literals in
        a conflict (it never drops one, nor blocks a plan), so a wrong one on a borderline
        point costs generality, never soundness."""
        if not self._rest_ok or (anchored and not self._start_rests):
            return False
        regs = sorted(set(assign.values()))
        tol = self._rest_tol
        if anchored:
            p = self._start_pos
            ok = all(np.all(self.Hs[r] @ p <= self.hs[r] + tol) for r in regs)
        else:
            if not self.regions:
                return False
            V = np.asarray(self.regions[regs[0] if regs else 0].vertices, float)  # no literal: any region's point
            inside = np.ones(len(V), dtype=bool)
            for r in regs[1:]:
                inside &= np.all(V @ self.Hs[r].T <= self.hs[r] + tol, axis=1)
            if not inside.any():
                return False
            p = V[inside].mean(axis=0)
            ok = all(np.all(self.Hs[r] @ p <= self.hs[r] + tol) for r in regs)
        if ok:
            ok = bool(np.all(p >= self.state_lo[self.pos] - tol) and np.all(p <= self.state_hi[self.pos] + tol))
        self.rest_answers += ok
        return ok

    def loop_infeasible(self, assign: dict[int, int], k: int, L: int, seconds: float = math.inf) -> bool:
        """Is the loop alone infeasible: states k..L with x_L = x_k (any x_k, no start)
        and p_t in region assign[t] (and p_{t+1}, segments)? Sets :attr:`ray_times` (the
        literals of the Farkas certificate, when HiGHS gives one) on an infeasible answer.

        Memoised by (period L - k, the literals' times relative to k): that LP is the same
        LP at every loop start and horizon (time-invariant dynamics and constraints, the
        columns outside k..L unused), so its verdict, and its certificate's literals
        moved by the same shift, are those of the first solve. The deletion filter of
        :meth:`conflict` asks for the same small subsets (the empty one, single
        literals) again and again, and DIS-PLAN proposes the same loop behind
        different prefixes."""
        key = (L - k, tuple(sorted((t - k, r) for t, r in assign.items())))
        self._last_loop = (k, L, dict(assign))
        if self.rests(assign, False):
            return False
        hit = self._loop_memo.get(key)
        if hit is not None:
            self.memo_hits += 1
            infeasible, ray = hit
            if infeasible:
                self.ray_times = None if ray is None else {t + k for t in ray}
            return infeasible
        infeasible = self._lp(assign, k, L, False, k, seconds, solution=False) is None
        ray = None if not infeasible or self.ray_times is None else tuple(sorted(t - k for t in self.ray_times))
        self._loop_memo[key] = (infeasible, ray)
        return infeasible

    def _lp(
        self,
        assign: dict[int, int],
        first: int,
        last: int,
        anchored: bool,
        loop_start: int | None,
        seconds: float,
        *,
        solution: bool = True,
    ) -> np.ndarray | None:
        """Feasibility LP over the states first..last (columns of every state and input,
        those outside unused): p_t in region assign[t] (and p_{t+1}, segments), the start
        when ``anchored``, the closure x_last = x_loop_start.

        The deletion filter of :meth:`conflict` asks for many subsets of one assignment:
        when the model in HiGHS has the same frame (first, last, start, closure) and a
        superset of the literals, the literals left out are switched off (their rows'
        upper bounds set to +inf) and HiGHS re-solves from its last basis, instead of a
        new model solved from scratch."""
        key = (first, last, anchored, loop_start)
        loaded = self._loaded
        if loaded is not None and loaded[0] == key and all(loaded[1].get(t) == r for t, r in assign.items()):
            owner, hi = loaded[2], loaded[3]
            mask = np.zeros(last + 1, dtype=bool)
            mask[np.fromiter(assign, dtype=np.int64, count=len(assign))] = True
            on = mask[owner]
            self.highs.changeRowsBounds(len(owner), loaded[4], np.full(len(owner), -np.inf), np.where(on, hi, np.inf))
            self.warm += 1
        else:
            self._load(assign, first, last, anchored, loop_start)
        return self._run(assign, seconds, solution)

    def _load(self, assign: dict[int, int], first: int, last: int, anchored: bool, loop_start: int | None) -> None:
        """Pass the LP of :meth:`_lp` to HiGHS (rows: dynamics, then the literals' region
        rows, then the closure), assembled in a few array operations."""
        p = self.problem
        L = last
        n, m, pos = self.n, self.m, self.pos
        nx = (L + 1) * n
        ncol = nx + L * m
        ai, aj, av, bi, bj, bv = self.dyn_nz
        R: list[np.ndarray] = []
        C: list[np.ndarray] = []
        V: list[np.ndarray] = []
        T = np.arange(first, L)
        if len(T):  # x_{t+1} - A x_t - B u_t = 0, all steps at once
            base_r = np.concatenate([np.arange(n), ai, bi])
            R.append(((T - first)[:, None] * n + base_r[None, :]).ravel())
            C.append(
                np.concatenate(
                    [
                        ((T + 1)[:, None] * n + np.arange(n)[None, :]),
                        T[:, None] * n + aj[None, :],
                        nx + T[:, None] * m + bj[None, :],
                    ],
                    axis=1,
                ).ravel()
            )
            V.append(np.tile(np.concatenate([np.ones(n), -av, -bv]), len(T)))
        row = len(T) * n
        lit_from = row
        # the literals' region rows: one block per (literal, sample), each its region's
        # template (row offsets, position columns, coefficients) moved to its rows and
        # sample, gathered for all blocks at once
        bt, br, bs = [], [], []
        for t, r in assign.items():
            for s_ in (t, t + 1) if (self.segment_safe and t < L) else (t,):
                bt.append(t)
                br.append(r)
                bs.append(s_)
        br_ = np.asarray(br, dtype=np.int64)
        k_of = self._n_rows[br_]  # rows per block
        row_start = row + np.concatenate([[0], np.cumsum(k_of)[:-1]]) if len(br) else np.zeros(0, np.int64)
        ent = _gather(self._ent_off[br_], k_of * len(pos))
        R.append(self._tr[ent] + np.repeat(row_start, k_of * len(pos)))
        C.append(self._tc[ent] + np.repeat(np.asarray(bs, dtype=np.int64) * n, k_of * len(pos)))
        V.append(self._tv[ent])
        his = [self._th[_gather(self._row_off[br_], k_of)]]
        owner = [np.repeat(np.asarray(bt, dtype=np.int64), k_of)]
        row += int(k_of.sum())
        lit_to = row
        if loop_start is not None:
            R.append(row + np.concatenate([np.arange(n), np.arange(n)]))
            C.append(np.concatenate([L * n + np.arange(n), loop_start * n + np.arange(n)]))
            V.append(np.concatenate([np.ones(n), -np.ones(n)]))
            row += n
        n_dyn = len(T) * n
        lit_hi = np.concatenate(his) if his else np.zeros(0)
        row_lo = np.concatenate([np.zeros(n_dyn), np.full(lit_to - lit_from, -np.inf), np.zeros(row - lit_to)])
        row_hi = np.concatenate([np.zeros(n_dyn), lit_hi, np.zeros(row - lit_to)])
        col_lo = np.concatenate([np.tile(self.state_lo, L + 1), np.full(L * m, -p.input_bound)])
        col_hi = np.concatenate([np.tile(self.state_hi, L + 1), np.full(L * m, p.input_bound)])
        if anchored:
            col_lo[first * n : (first + 1) * n] = col_hi[first * n : (first + 1) * n] = p.start
        coo = (
            (np.concatenate(R).astype(np.int64), np.concatenate(C).astype(np.int64), np.concatenate(V))
            if R
            else (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))
        )
        lp = csc_lp(ncol, row, *coo, np.zeros(ncol), col_lo, col_hi, row_lo, row_hi)
        self.highs.passModel(lp)
        lit_owner = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        self._loaded = (
            (first, last, anchored, loop_start),
            dict(assign),
            lit_owner,
            lit_hi.copy(),
            np.arange(lit_from, lit_to, dtype=np.int32),
            row,
        )

    def _run(self, assign: dict[int, int], seconds: float, solution: bool = True) -> np.ndarray | None:
        h = self.highs
        if math.isfinite(seconds):
            h.setOptionValue("time_limit", float(h.getRunTime() + max(1e-3, float(seconds))))
        t0 = time.perf_counter()
        h.run()
        self.seconds += time.perf_counter() - t0
        self.lp_calls += 1
        status = h.getModelStatus()
        S = highspy.HighsModelStatus
        if status == S.kOptimal:
            return np.asarray(h.getSolution().col_value) if solution else np.zeros(0)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            # the literals whose rows carry the Farkas certificate (dual ray), if any
            self.ray_times = None
            try:
                _, has_ray, ray = h.getDualRay()
            except Exception:  # pragma: no cover - depends on the HiGHS build
                has_ray, ray = False, None
            _, _, lit_owner, _, lit_rows, r0 = self._loaded
            if has_ray and ray is not None and len(ray) == r0:
                used = np.abs(np.asarray(ray)[lit_rows]) > 1e-9
                self.ray_times = set(int(t) for t in lit_owner[used] if int(t) in assign)
            return None
        if status == S.kTimeLimit:
            raise LpBudgetExhausted()
        raise LpFailure(f"HiGHS gave no answer on the loop LP ({h.modelStatusToString(status)})")


def _gather(starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """The indices starts[0]..starts[0]+lengths[0]-1, starts[1].., concatenated."""
    total = int(lengths.sum())
    if not total:
        return np.zeros(0, dtype=np.int64)
    first = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    return np.repeat(starts - first, lengths) + np.arange(total)

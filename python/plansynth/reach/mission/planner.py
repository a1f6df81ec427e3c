"""The lazy SMT planner for LTL missions (issue 14; Shoukry et al., CDC 2016,
Algorithm 1 with DIS-PLAN replaced by the BMC encoding of the mission).

::

    abstraction <- convex decomposition refined by the labels          (labels.py)
    no word over the labels' geometry satisfies the mission -> infeasible (proof.py)
    L0 <- the product graph's lower bound on the horizon                  (horizon.py)
    for L = L0 .. max_horizon:                   (one horizon at a time: L is minimal)
        loop:
            r_0..r_L, loop <- DIS-PLAN(L)          (bmc.py; UNSAT -> next L)
            lasso, loop start k: no periodic trajectory through r_k..r_L -> block the loop, loop
            CON-PLAN(r_0..r_L) -> conflict: learn it, loop             (conplan.py, unchanged)
            finite plan: the LP that also keeps x_L at rest -> trajectory: done
                                                    -> block this finite plan (stay), loop
            lasso, loop start k: the LP with x_L = x_k -> trajectory: done
                                                    -> block this lasso, loop

CON-PLAN runs unchanged on the problem with the whole workspace as its goal
(:func:`~plansynth.reach.mission.labels.planning_problem`); its conflicts are sound
for the mission planner because the mission adds constraints only through the region
sequence and the loop. The loop closure x_L = x_k is the one CON-PLAN constraint
missions add; it is checked by :class:`LoopLP` (CON-PLAN's rows plus the closure):
the loop alone before CON-PLAN (a refuted one holds at every horizon and rotation), the
whole lasso for sequences CON-PLAN realised; a refuted loop blocks its literals with its
loop selector. Every plan goes through the validator and the independent mission
checker (:mod:`plansynth.reach.mission.check`) before it is reported.

**What ``infeasible`` means** (as in :mod:`plansynth.reach.lazy.loop`). DIS-PLAN moves one
region per step, so refuting every horizon proves only that no plan *through the
label-refined decomposition* exists; a real trajectory may cross several regions in one
step. The answer is ``infeasible`` only when :func:`~plansynth.reach.mission.proof.label_proof`
holds: no infinite word over the letters the labels' geometry allows satisfies the
mission, so no trajectory does at any horizon (``counters["label_proof"]``). When the loop
refutes every horizon without it, the answer is ``unknown`` and says "not a proof"
(``counters["abstraction_refuted"]``).

>>> from plansynth.reach.mission.families import mission_problem
>>> r = solve_mission(mission_problem("maze-1", "avoid-until"))
>>> r.status.value, r.horizon, r.mission["semantics"], r.mission["ok"], r.validated
('found', 31, 'finite', True, True)
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget, Clock
from plansynth.errors import InvalidOption
from plansynth.reach.lazy.bounds import time_windows
from plansynth.reach.lazy.conflict import Feasible
from plansynth.reach.lazy.conplan import ConPlan, LpBudgetExhausted, LpFailure
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.displan import RegionGraph, SatOutcome
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.mission.ltl import parse
from plansynth.reach.mission.bmc import SEMANTICS, MissionDisPlan, MissionPlan
from plansynth.reach.mission.labels import LabelledAbstraction, label_abstraction, planning_problem
from plansynth.reach.mission.proof import timed_label_proof
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.lazy.transit import GOAL, TransitCheck

__all__ = ["plan_mission", "LoopLP", "MissionTransit", "solve_mission", "validate_mission_result", "MISSION_PLANNERS"]

ProgressFn = Callable[[int, int], None]

#: what a refutation through the abstraction is not (see :mod:`plansynth.reach.mission.proof`)
NOT_A_PROOF = "not a proof of infeasibility (a step may cross several regions)"


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
        self._rest_ok = bool(np.array_equal(A[:, self.pos], eye[:, self.pos])
                             and np.all(self.state_lo[other] <= 0) and np.all(self.state_hi[other] >= 0)
                             and problem.input_bound >= 0)
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
        us = col[(L + 1) * n:].reshape(L, m)
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

    def conflict(self, regions: tuple[int, ...], loop_start: int, seconds: float = math.inf, *,
                 loop_refuted: bool = False) -> tuple[tuple[tuple[int, int], ...], bool]:
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

    def _lp(self, assign: dict[int, int], first: int, last: int, anchored: bool, loop_start: int | None,
            seconds: float, *, solution: bool = True) -> np.ndarray | None:
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
            self.highs.changeRowsBounds(len(owner), loaded[4], np.full(len(owner), -np.inf),
                                        np.where(on, hi, np.inf))
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
            C.append(np.concatenate([((T + 1)[:, None] * n + np.arange(n)[None, :]), T[:, None] * n + aj[None, :],
                                     nx + T[:, None] * m + bj[None, :]], axis=1).ravel())
            V.append(np.tile(np.concatenate([np.ones(n), -av, -bv]), len(T)))
        row = len(T) * n
        lit_from = row
        # the literals' region rows: one block per (literal, sample), each its region's
        # template (row offsets, position columns, coefficients) moved to its rows and
        # sample, gathered for all blocks at once
        bt, br, bs = [], [], []
        for t, r in assign.items():
            for s_ in ((t, t + 1) if (self.segment_safe and t < L) else (t,)):
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
            col_lo[first * n:(first + 1) * n] = col_hi[first * n:(first + 1) * n] = p.start
        coo = (np.concatenate(R).astype(np.int64), np.concatenate(C).astype(np.int64), np.concatenate(V)) if R else \
            (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))
        lp = csc_lp(ncol, row, *coo, np.zeros(ncol), col_lo, col_hi, row_lo, row_hi)
        self.highs.passModel(lp)
        lit_owner = np.concatenate(owner) if owner else np.zeros(0, np.int64)
        self._loaded = ((first, last, anchored, loop_start), dict(assign), lit_owner, lit_hi.copy(),
                        np.arange(lit_from, lit_to, dtype=np.int32), row)

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


class MissionTransit(TransitCheck):
    """The transit-time layer (:class:`~plansynth.reach.lazy.transit.TransitCheck`) as the
    mission planner uses it: a leg's gaps are decided by LPs only when the plan's gap
    is the leg's box bound (the fewest steps the displacement bounds allow), and legs
    to the goal are never checked (a mission's goal is the whole workspace).

    On the mazes most legs a plan's infeasibility brings up have their first feasible
    gap at or just above the box bound, and a plan's gap far above it is almost never
    the reason: scanning every leg (one LP per gap from the box bound up) cost the visit
    missions twice the LPs of CON-PLAN and the mission loop together. A leg whose plan
    gap lies above its box bound is decided as soon as another plan puts it at the
    bound, or by CON-PLAN. This only drops conflicts: every one reported is still proved
    (by the box bound or an LP), so the loop's clauses stay sound."""

    def box_gap(self, a: int, b: int) -> int:
        """:meth:`TransitCheck.box_gap`, once per leg (a pure function of the two boxes
        and the step bounds; the mission loop asks for every leg of every plan, ~10,000
        times on a patrol)."""
        memo = self.__dict__.setdefault("_box_gaps", {})
        g = memo.get((a, b))
        if g is None:
            g = memo[(a, b)] = super().box_gap(a, b)
        return g

    def _skip(self, a: int, b: int, gap: int) -> bool:
        return b == GOAL or ((a, b) not in self._first and gap > self.box_gap(a, b))

    def impossible(self, a: int, b: int, gap: int) -> bool:
        return False if self._skip(a, b, gap) else super().impossible(a, b, gap)

    def violations(self, regions, span=None, *, known_only: bool = False):
        """:meth:`TransitCheck.violations` over every leg of the plan, also when CON-PLAN's
        conflict covers only part of it (``span`` is ignored). The reach-avoid planner
        restricts the legs to the conflict's span because deciding every leg of a plan
        through a 1,500-region maze took thousands of LPs; here a leg above its box bound
        is never decided by an LP (:meth:`_skip`), and the legs outside the span, reported
        together with CON-PLAN's conflict, spare DIS-PLAN the plans it would otherwise
        propose one by one: visit 21 -> 10 SAT calls and 84 -> 58 LPs, avoid-until 8 -> 6
        SAT calls, patrol unchanged. Sound as before: every reported leg is proved
        impossible (box bound or LP)."""
        return super().violations(regions, None, known_only=known_only)

    def known(self, a: int, b: int, gap: int) -> bool | None:
        return False if self._skip(a, b, gap) else super().known(a, b, gap)


def mission_horizon_bound(problem: ReachProblem, labelled: LabelledAbstraction, graph: RegionGraph,
                          earliest, L_max: int, timings: dict, counters: dict, clock: Clock | None = None) -> int:
    """:func:`~plansynth.reach.mission.horizon.horizon_lower_bound` as both mission
    planners run it: its time goes to ``timings["horizon_bound"]``, the bound to
    ``counters["horizon_bound"]``."""
    from plansynth.reach.mission.horizon import horizon_lower_bound

    t0 = time.perf_counter()
    bound = horizon_lower_bound(graph, labelled.labels_of, parse(problem.mission), earliest, L_max, clock=clock)
    timings["horizon_bound"] = time.perf_counter() - t0
    counters["horizon_bound"] = bound
    return bound


def wrap_violation(transit: TransitCheck, regions: tuple[int, ...], loop_start: int
                   ) -> tuple[tuple[int, int], tuple[int, int]] | None:
    """Two loop positions i >= j whose wrap-around leg is too short: with x_L = x_k
    the robot repeats the loop, so it is in r_i at step i and in r_j at step
    L + (j - k), and if the transit layer proves r_i -> r_j impossible in that many
    steps, no periodic trajectory realises the two literals (at any horizon or
    rotation: :meth:`MissionDisPlan.learn_loop` with ``shifted``)."""
    k, L = loop_start, len(regions) - 1
    for i in range(L - 1, k - 1, -1):
        for j in range(k, i):
            if regions[i] != regions[j] and transit.impossible(regions[i], regions[j], (L - i) + (j - k)):
                return ((j, regions[j]), (i, regions[i]))
    return None


def plan_mission(
    problem: ReachProblem,
    budget: Budget = Budget(),
    *,
    labelled: LabelledAbstraction | None = None,
    max_horizon: int | None = None,
    semantics: str = "any",
    segment_safe: bool = True,
    lower_bound: bool = True,
    transit: bool = True,
    wait_shifts: bool = True,
    loop_first: bool = True,
    horizon_bound: bool = True,
    progress: ProgressFn | None = None,
) -> ReachResult:
    """The lazy loop for the problem's mission within ``budget`` (not yet validated:
    :func:`solve_mission` does that). ``semantics``: ``any`` (finite or lasso plans,
    finite ones first), ``finite`` or ``lasso``. ``lower_bound``: the earliest step of
    each region from the displacement-box relaxation
    (:func:`~plansynth.reach.lazy.bounds.time_windows`) as unit clauses. ``transit``: the
    transit-time layer (:class:`~plansynth.reach.lazy.transit.TransitCheck`) in front of
    CON-PLAN, as in the reach-avoid planner. ``wait_shifts``: start-anchored conflicts
    also shifted earlier when the robot starts at rest. ``loop_first``: a lasso's loop
    alone (states k..L with x_L = x_k, any x_k) is checked before CON-PLAN sees the
    plan: a loop that no periodic trajectory follows is refuted at every horizon and
    rotation (:meth:`MissionDisPlan.learn_loop`), which a conflict of the prefix is not.
    ``horizon_bound``: the horizons start at the proved lower bound of
    :func:`~plansynth.reach.mission.horizon.horizon_lower_bound` (no DIS-PLAN plan exists
    below it), not at 0."""
    if problem.mission is None:
        raise ValueError("the problem has no mission (plan it with the reach-avoid planners)")
    if semantics not in SEMANTICS:
        raise ValueError(f"unknown semantics {semantics!r} (known: {', '.join(SEMANTICS)})")
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if max_horizon is None else int(max_horizon)
    options = {"semantics": semantics, "segment_safe": segment_safe, "max_horizon": L_max, "lower_bound": lower_bound,
               "transit": transit, "wait_shifts": wait_shifts, "loop_first": loop_first,
               "horizon_bound": horizon_bound,
               "budget": {"seconds": budget.seconds, "iterations": budget.iterations}}
    timings = {"abstraction": 0.0, "bounds": 0.0, "sat": 0.0, "lp": 0.0}
    pp = planning_problem(problem)
    if labelled is None:
        t0 = time.perf_counter()
        labelled = label_abstraction(problem)
        timings["abstraction"] = time.perf_counter() - t0
    ab = labelled.abstraction
    graph = RegionGraph.from_abstraction(ab)
    t0 = time.perf_counter()
    earliest = time_windows(pp, ab, L_max).earliest if lower_bound else None
    timings["bounds"] = time.perf_counter() - t0
    displan = MissionDisPlan(graph, labelled.labels_of, parse(problem.mission), semantics=semantics, earliest=earliest,
                             waits_at_start=wait_shifts and problem.starts_at_rest)
    conplan = ConPlan(pp, ab, segment_safe=segment_safe, counterexample="trivial", generalize=True, minimize=True,
                      clock=clock)
    theory = MissionTransit(conplan, ab) if transit else conplan
    loop_lp = LoopLP(pp, ab, segment_safe=segment_safe)
    counters: dict[str, Any] = {"regions": graph.n_regions, "edges": ab.n_edges}
    guarantee = "segments" if segment_safe else "samples"

    def finish(status: ReachStatus, horizon: int | None, message: str, traj: Trajectory | None = None,
               plan: MissionPlan | None = None) -> ReachResult:
        st = conplan.stats
        counters.update(iterations=clock.iterations, sat_calls=displan.sat_calls, clauses=displan.clauses,
                        loop_clauses=displan.loop_clauses, lp_calls=st.lp_calls + loop_lp.lp_calls,
                        loop_lp_calls=loop_lp.lp_calls, loop_lp_memo_hits=loop_lp.memo_hits,
                        loop_lp_rest_answers=loop_lp.rest_answers, horizon=horizon, minimal=status is ReachStatus.FOUND,
                        # DIS-PLAN moves one region per step, and a real step may cross several: the
                        # shortest horizon is the shortest through the label-refined decomposition only
                        minimal_relative_to="decomposition" if status is ReachStatus.FOUND else None)
        timings["highs"] = st.seconds + loop_lp.seconds
        timings["encoding"] = displan.encode_seconds  # part of "sat"
        timings["loop_lp_highs"] = loop_lp.seconds  # part of "highs"
        timings["total"] = time.perf_counter() - t_start
        displan.delete()
        mission = {"formula": problem.mission, "semantics": None if plan is None else plan.semantics,
                   "loop_start": None if plan is None else plan.loop_start}
        return ReachResult(status=status, planner="lazy-smt", seconds=timings["total"], trajectory=traj,
                           regions=None if plan is None else plan.regions, horizon=horizon, counters=counters,
                           timings=timings, options=options, message=message, guarantee=guarantee, mission=mission)

    proved, why = timed_label_proof(problem, labelled, timings, counters)
    if proved:
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    if not ab.start_regions:
        counters["abstraction_refuted"] = L_max
        return finish(ReachStatus.UNKNOWN, L_max, f"the start lies in no region; {NOT_A_PROOF}")
    L0 = mission_horizon_bound(problem, labelled, graph, earliest, L_max, timings, counters, clock) if horizon_bound else 0
    if L0 > L_max:
        counters["abstraction_refuted"] = L_max
        return finish(ReachStatus.UNKNOWN, L_max, f"no plan through the label-refined abstraction at any horizon "
                      f"up to {L_max} (product graph); {NOT_A_PROOF} ({why})")
    L = L0
    try:
        for L in range(L0, L_max + 1):
            if progress is not None:
                progress(L, clock.iterations)
            while True:
                if clock.exhausted():
                    return finish(ReachStatus.UNKNOWN, L, f"budget ran out at horizon {L} after {clock.iterations} iterations")
                clock.tick()
                t0 = time.perf_counter()
                outcome, plan = displan.solve(L, clock)
                timings["sat"] += time.perf_counter() - t0
                if outcome is SatOutcome.INTERRUPTED:
                    return finish(ReachStatus.UNKNOWN, L, f"budget ran out in the SAT solver at horizon {L}")
                if outcome is SatOutcome.UNSAT:
                    displan.close(L)
                    break
                assert plan is not None
                t0 = time.perf_counter()
                if loop_first and plan.loop_start is not None:
                    k = plan.loop_start
                    if isinstance(theory, TransitCheck):
                        # cheap first: transit-time violations of the sequence, then of the
                        # loop's wrap-around legs (cached gaps, no horizon-long LP)
                        found = theory.violations(plan.regions)
                        if found:
                            timings["lp"] += time.perf_counter() - t0
                            for conflict in found:
                                displan.learn(conflict)
                            continue
                        wrap = wrap_violation(theory, plan.regions, k)
                        if wrap is not None:
                            timings["lp"] += time.perf_counter() - t0
                            counters["wrap_conflicts"] = counters.get("wrap_conflicts", 0) + 1
                            displan.learn_loop(wrap, k, L, shifted=True)
                            continue
                    if loop_lp.loop_infeasible({t: plan.regions[t] for t in range(k, L + 1)}, k, L, clock.remaining()):
                        lits, shifted = loop_lp.conflict(plan.regions, k, clock.remaining(), loop_refuted=True)
                        timings["lp"] += time.perf_counter() - t0
                        displan.learn_loop(lits, k, L, shifted=shifted)
                        continue
                answer = theory.check(plan.regions)
                if isinstance(answer, Feasible) and plan.loop_start is not None:
                    traj = loop_lp.solve(plan.regions, plan.loop_start, clock.remaining())
                    timings["lp"] += time.perf_counter() - t0
                    if traj is None:
                        t0 = time.perf_counter()
                        lits, shifted = loop_lp.conflict(plan.regions, plan.loop_start, clock.remaining())
                        timings["lp"] += time.perf_counter() - t0
                        displan.learn_loop(lits, plan.loop_start, L, shifted=shifted)
                        continue
                    return finish(ReachStatus.FOUND, L, f"found a lasso at horizon {L} (loop from step {plan.loop_start})",
                                  traj, plan)
                if isinstance(answer, Feasible):  # a finite plan: it must also end at rest
                    traj = answer.trajectory if loop_lp.ends_at_rest(answer.trajectory) else \
                        loop_lp.solve_finite(plan.regions, clock.remaining())
                    timings["lp"] += time.perf_counter() - t0
                    if traj is None:
                        t0 = time.perf_counter()
                        displan.learn_stay(loop_lp.rest_conflict(plan.regions, clock.remaining()), L)
                        timings["lp"] += time.perf_counter() - t0
                        continue
                    return finish(ReachStatus.FOUND, L, f"found a finite plan at horizon {L}", traj, plan)
                timings["lp"] += time.perf_counter() - t0
                for conflict in answer if isinstance(answer, tuple) else (answer,):
                    displan.learn(conflict)
    except LpBudgetExhausted:
        return finish(ReachStatus.UNKNOWN, L, f"budget ran out in the LP solver at horizon {L}")
    except LpFailure as exc:
        return finish(ReachStatus.UNKNOWN, L, f"{exc} at horizon {L}")
    # refuted through the label-refined decomposition only (one region per step): a real
    # trajectory may cross several regions in one step, so this is no proof (as in the
    # reach-avoid planner, plansynth.reach.lazy.loop); label_proof above is the proof
    counters["abstraction_refuted"] = L_max
    return finish(ReachStatus.UNKNOWN, L_max, f"every horizon up to {L_max} refuted for plans through the "
                  f"label-refined abstraction; {NOT_A_PROOF} ({why})")


def validate_mission_result(problem: ReachProblem, result: ReachResult, *, tol: float = 1e-6) -> ReachResult:
    """The validator (on the problem with the workspace as goal: a mission has no goal
    constraint) and the independent mission checker on a ``found`` result; a failure
    turns it into ``unknown``."""
    from plansynth.reach.mission.check import check_mission
    from plansynth.reach.solve import validate_result

    if result.status is not ReachStatus.FOUND:
        return result
    checked = validate_result(planning_problem(problem), result, tol=tol)
    if checked.status is not ReachStatus.FOUND:
        return checked
    t0 = time.perf_counter()
    report = check_mission(problem, checked.trajectory, (checked.mission or {}).get("loop_start"), tol=tol)
    seconds = time.perf_counter() - t0
    timings = {**checked.timings, "mission_check": seconds, "total": checked.seconds + seconds}
    mission = {**(checked.mission or {}), **report.to_json_dict()}
    if report.ok:
        return replace(checked, mission=mission, timings=timings, seconds=timings["total"])
    return replace(checked, status=ReachStatus.UNKNOWN, validated=False, mission=mission, timings=timings,
                   seconds=timings["total"],
                   message=f"the {checked.planner} plan fails the mission checker and is not reported as found: {report.summary()}")


def _milp_ltl(problem: ReachProblem, budget: Budget = Budget(), **options: Any) -> ReachResult:
    from plansynth.reach.mission.milp import plan_milp_ltl

    return plan_milp_ltl(problem, budget, **options)


def _milp_ltl_oneshot(problem: ReachProblem, budget: Budget = Budget(), **options: Any) -> ReachResult:
    return _milp_ltl(problem, budget, **{"one_shot": True, **options})


MISSION_PLANNERS: dict[str, Callable[..., ReachResult]] = {"lazy-smt": plan_mission, "milp-ltl": _milp_ltl,
                                                           "milp-ltl-oneshot": _milp_ltl_oneshot}


def solve_mission(problem: ReachProblem, planner: str = "lazy-smt", budget: Budget = Budget(), **options: Any) -> ReachResult:
    """Plan the problem's mission with ``lazy-smt``, ``milp-ltl`` or ``milp-ltl-oneshot``; every plan is
    validated and mission-checked before it is reported."""
    if planner not in MISSION_PLANNERS:
        raise InvalidOption(planner, "planner", f"does not plan LTL missions (mission planners: {', '.join(MISSION_PLANNERS)})")
    import inspect

    accepted = set(inspect.signature(plan_mission if planner == "lazy-smt" else _plan_milp_ltl()).parameters)
    accepted -= {"problem", "budget", "labelled"}
    for name in options:
        if name not in accepted:  # a reach-avoid option (counterexample strategy, windows, ...)
            raise InvalidOption(planner, name, f"does not apply to LTL missions (mission options: "
                                               f"{', '.join(sorted(accepted - {'progress'}))})")
    result = MISSION_PLANNERS[planner](problem, budget, **options)
    return validate_mission_result(problem, result)


def _plan_milp_ltl():
    from plansynth.reach.mission.milp import plan_milp_ltl

    return plan_milp_ltl

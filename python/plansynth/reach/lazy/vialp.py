"""The via LP: CON-PLAN's feasibility LP with the segment between two regions crossing
their common face anywhere along the step (beyond Shoukry et al., CDC 2016, Section V,
whose LP has one region per time step).

CON-PLAN keeps a segment that changes region, from p_t in r_t to p_{t+1} in r_{t+1},
inside r_t: the sample p_{t+1} lies in both regions, on their common face. A robot at
full speed rarely has a sample on each face it crosses, so every change of region can
cost up to a step (the GCS paper's 10 x 10 maze: 46 steps proved minimal that way,
where gcs's curve takes 39). Here the segment instead passes through a *via*, the point
``v_t = (1 - f_t) p_t + f_t p_{t+1}`` at a fixed fraction f_t of the step, required in
both regions: then [p_t, v_t] lies in r_t and [v_t, p_{t+1}] in r_{t+1} (each region is
convex), so the segment is in their union, free space, and the constraint stays linear
in the states (the fractions fixed, as the exact segment theory's points along a
segment, :mod:`plansynth.reach.lazy.pointlp`). f_t = 1 is CON-PLAN's row, so every plan
CON-PLAN realises is realised here with the same trajectory.

The fractions come from a trajectory (:func:`crossing_fractions`: the middle of the
stretch of its segment that lies in both regions), so a trajectory that realises a plan
keeps realising it with the fractions it gives. :meth:`ViaLP.solve` is elastic (a slack
s_t >= 0 on every row on p_t and on the via rows of the step into t, their sum
minimised, as :meth:`~plansynth.reach.lazy.conplan.ConPlan.violations`): zero slack
means a trajectory, else the slack says where the plan is too tight.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.abstraction import abstract
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> p = maze(1); a = abstract(p); r = plan_lazy(p)
>>> lp = ViaLP(p, a)
>>> f = crossing_fractions(lp, r.regions, np.asarray(r.trajectory.states)[:, lp.pos])
>>> slack, traj = lp.solve(r.regions, f)
>>> float(slack.max()) <= SLACK_TOL, traj is not None
(True, True)
"""

from __future__ import annotations

from collections.abc import Sequence

import highspy
import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import halfspaces
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.lazy.conplan.runs import LpBudgetExhausted
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["ViaLP", "crossing_fractions", "transitions", "SLACK_TOL"]

#: A slack above this marks a row the plan cannot meet.
SLACK_TOL = 1e-7


def transitions(plan: Sequence[int]) -> np.ndarray:
    """The steps t at which ``plan`` changes region (r_t != r_{t+1}).

    >>> transitions((4, 4, 5, 6, 6)).tolist()
    [1, 2]
    """
    p = np.asarray(plan, dtype=np.int64)
    return np.flatnonzero(p[1:] != p[:-1])


class ViaLP:
    """The via LP of ``problem`` over the regions of ``abstraction`` (module doc); one
    cold HiGHS solve per :meth:`solve`, within ``clock`` when given. Counters:
    ``lp_calls``."""

    def __init__(self, problem: ReachProblem, abstraction: Abstraction, clock: Clock | None = None) -> None:
        dyn = problem.dynamics
        self.problem, self.clock = problem, clock
        self.n, self.m, self.d = dyn.n_states, dyn.n_inputs, problem.dim
        self.pos = np.array(dyn.position, dtype=np.int64)
        self.A, self.B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        Hs = [np.asarray(r.H, float) for r in abstraction.regions]
        hs = [np.asarray(r.h, float) for r in abstraction.regions]
        self.K = max(H.shape[0] for H in Hs)
        self.H = np.zeros((len(Hs), self.K, self.d))
        self.h = np.full((len(Hs), self.K), np.inf)
        for i, (H, h) in enumerate(zip(Hs, hs)):
            self.H[i, : H.shape[0]], self.h[i, : H.shape[0]] = H, h
        Hg, hg = (np.asarray(x, float) for x in halfspaces(problem.goal))  # type: ignore[arg-type]
        self.Hg, self.hg = Hg, hg
        self.state_lo, self.state_hi = (np.asarray(b, float) for b in problem.state_box)
        self.start = np.asarray(problem.start, float)
        self.lp_calls = 0

    def solve(
        self, plan: Sequence[int], fractions: np.ndarray, *, strict: bool = False
    ) -> tuple[np.ndarray, Trajectory | None] | None:
        """The elastic LP of ``plan`` (r_0..r_N) with a via at ``fractions[i]`` of the
        step at ``transitions(plan)[i]``: the slacks s_0..s_N and, when none exceeds
        :data:`SLACK_TOL`, a trajectory realising the plan (``strict``: the slacks fixed
        at zero, so its rows hold to HiGHS's tolerance); None when even the slacks do
        not make it feasible. Raises LpBudgetExhausted when the budget runs out."""
        r = np.asarray(plan, dtype=np.int64)
        n, m, d, K = self.n, self.m, self.d, self.K
        N = len(r) - 1
        T = N + 1
        nx, nu = T * n, N * m
        s0 = nx + nu
        n_col = s0 + T
        R: list[np.ndarray] = []
        C: list[np.ndarray] = []
        V: list[np.ndarray] = []
        lo: list[np.ndarray] = []
        hi: list[np.ndarray] = []
        row = 0
        # dynamics x_{t+1} - A x_t - B u_t = 0
        ai, aj = np.nonzero(self.A)
        bi, bj = np.nonzero(self.B)
        tt = np.arange(N)[:, None]
        R.append(np.concatenate([(tt * n + np.arange(n)).ravel(), (tt * n + ai).ravel(), (tt * n + bi).ravel()]))
        C.append(
            np.concatenate([((tt + 1) * n + np.arange(n)).ravel(), (tt * n + aj).ravel(), (nx + tt * m + bj).ravel()])
        )
        V.append(np.concatenate([np.ones(N * n), np.tile(-self.A[ai, aj], N), np.tile(-self.B[bi, bj], N)]))
        lo.append(np.zeros(N * n))
        hi.append(np.zeros(N * n))
        row += N * n

        def block(times: np.ndarray, regs: np.ndarray, weights: list[tuple[np.ndarray, int]], slack_at: np.ndarray) -> None:
            """Rows H_R (sum_w w p_{t+dt}) - s <= h_R, one block of K per (time, region)."""
            nonlocal row
            nb = len(times)
            if not nb:
                return
            rows = row + np.arange(nb * K).reshape(nb, K)
            for w, dt in weights:
                coef = self.H[regs] * w[:, None, None]  # nb x K x d
                R.append(np.repeat(rows[:, :, None], d, axis=2).ravel())
                C.append((((times + dt) * n)[:, None, None] + self.pos[None, None, :]).repeat(K, axis=1).ravel())
                V.append(coef.ravel())
            R.append(rows.ravel())
            C.append(np.repeat(s0 + slack_at, K))
            V.append(-np.ones(nb * K))
            lo.append(np.full(nb * K, -np.inf))
            hi.append(self.h[regs].ravel())
            row += nb * K

        ts = np.arange(T)
        block(ts, r, [(np.ones(T), 0)], ts)
        tr = transitions(r)
        f = np.asarray(fractions, float)
        for regs in (r[tr], r[tr + 1]):
            block(tr, regs, [(1.0 - f, 0), (f, 1)], tr + 1)
        Kg = len(self.hg)
        R.append(np.repeat(row + np.arange(Kg), d))
        C.append(np.tile(N * n + self.pos, Kg))
        V.append(self.Hg.ravel())
        R.append(row + np.arange(Kg))
        C.append(np.full(Kg, s0 + N))
        V.append(-np.ones(Kg))
        lo.append(np.full(Kg, -np.inf))
        hi.append(self.hg)
        row += Kg
        Ra, Ca, Va = np.concatenate(R), np.concatenate(C), np.concatenate(V)
        keep = Va != 0.0
        col_lo = np.concatenate([np.tile(self.state_lo, T), np.full(nu, -self.problem.input_bound), np.zeros(T)])
        col_hi = np.concatenate(
            [np.tile(self.state_hi, T), np.full(nu, self.problem.input_bound), np.zeros(T) if strict else np.full(T, np.inf)]
        )
        col_lo[:n] = col_hi[:n] = self.start
        cost = np.zeros(n_col)
        cost[s0:] = 1.0
        row_lo, row_hi = np.concatenate(lo), np.concatenate(hi)
        finite = np.isfinite(row_hi) | np.isfinite(row_lo)  # (padding rows of smaller regions: free)
        row_hi = np.where(finite, row_hi, np.inf)
        lp = csc_lp(n_col, row, Ra[keep], Ca[keep], Va[keep], cost, col_lo, col_hi, row_lo, row_hi)
        h = new_highs()
        if self.clock is not None:
            left = self.clock.remaining()
            if left <= 0:
                raise LpBudgetExhausted("budget ran out in the via LP")
            h.setOptionValue("time_limit", float(min(left, 1e9)))  # (a fresh instance: its run time is 0)
        h.passModel(lp)
        h.run()
        self.lp_calls += 1
        status = h.getModelStatus()
        S = highspy.HighsModelStatus
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        if status != S.kOptimal:
            raise LpBudgetExhausted(f"the via LP ended with HiGHS status {h.modelStatusToString(status)}")
        col = np.asarray(h.getSolution().col_value)
        slack = np.maximum(col[s0:], 0.0)
        if slack.max(initial=0.0) > SLACK_TOL:
            return slack, None
        return slack, Trajectory(col[:nx].reshape(T, n), col[nx:s0].reshape(N, m))


def crossing_fractions(lp: ViaLP, plan: Sequence[int], positions: np.ndarray, old: np.ndarray | None = None) -> np.ndarray:
    """For each step at which ``plan`` changes region, the fraction of the step at the
    middle of the stretch of the segment between ``positions`` (T x d) that lies in
    both regions; where no such stretch exists (a segment of another plan's
    trajectory), ``old`` (default: 1, CON-PLAN's row).

    >>> crossing_fractions.__name__
    'crossing_fractions'
    """
    r = np.asarray(plan, dtype=np.int64)
    tr = transitions(r)
    P = np.asarray(positions, float)
    a, b = P[tr], P[tr + 1]
    dv = b - a

    def span(regs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The fractions [lo, hi] of each segment inside the regions ``regs``."""
        H, h = lp.H[regs], lp.h[regs]  # k x K x d, k x K
        Ha = np.einsum("ikd,id->ik", H, a)
        Hd = np.einsum("ikd,id->ik", H, dv)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = (h - Ha) / Hd
        up = np.where(Hd > 1e-12, ratio, np.inf).min(axis=1)
        down = np.where(Hd < -1e-12, ratio, -np.inf).max(axis=1)
        inside = np.all((np.abs(Hd) > 1e-12) | (Ha <= h + 1e-9), axis=1)
        return np.where(inside, np.maximum(down, 0.0), 1.0), np.where(inside, np.minimum(up, 1.0), 0.0)

    lo_a, hi_a = span(r[tr])
    lo_b, hi_b = span(r[tr + 1])
    lo, hi = np.maximum(lo_a, lo_b), np.minimum(hi_a, hi_b)
    fallback = np.ones(len(tr)) if old is None else np.asarray(old, float)
    return np.where(lo <= hi, (lo + hi) / 2, fallback)

"""The prism LP: CON-PLAN's feasibility LP in which a step between box regions may cross
their common faces anywhere, and skip a region whole (beyond Shoukry et al., CDC 2016,
Section V, whose LP has one region per time step).

CON-PLAN keeps a segment that changes region, from p_t in r_t to p_{t+1} in r_{t+1},
inside r_t: the sample p_{t+1} lies on their common face. A robot at full speed rarely
has a sample on each face it crosses, and it must have one *inside* every region on its
way, however thin: the GCS paper's mazes pass each doorway through a box 0.1 m deep,
so every doorway costs up to a step (10 x 10: 46 steps proved minimal that way, where
gcs's curve takes 39).

For box regions that follow each other across one axis k (each touching the next on a
face normal to k; a doorway between two cells), the *prism* is the box over their
common extent on the other axes, spanning all of them along k: every point of it lies
in the region whose k-range holds it, so it lies in their union, free space, and so
does every segment with both ends in it (a box is convex). A step whose two ends lie in
the prism of r_t, the regions skipped and r_{t+1} is therefore free; the constraint is
linear (two box rows per end), and it needs no sample on a face nor in a skipped region.

:meth:`PrismLP.solve` takes, for every change of region of a plan, either nothing
(CON-PLAN's row, p_{t+1} in r_t) or such a prism; it is elastic (a slack s_t >= 0 on
every row on p_t and on the prism rows of the step into t, their sum minimised, as
:meth:`~plansynth.reach.lazy.conplan.ConPlan.violations`): zero slack means a
trajectory, else the slack says where the plan is too tight.

>>> from plansynth.reach.families import gcs_maze
>>> from plansynth.reach.abstraction import abstract
>>> p = gcs_maze(10); a = abstract(p); lp = PrismLP(p, a)
>>> lo, hi = lp.prism([1, 3, 6])        # cell (1, 0), its doorway north, cell (1, 1)
>>> lo.tolist(), hi.tolist()
([1.05, 0.05], [1.95, 1.95])
>>> lp.prism([0, 1])[0] is None         # (0 and 1 touch across x, 1 and 3 across y)
False
>>> lp.prism([0, 1, 3])[0] is None
True
"""

from __future__ import annotations

from collections.abc import Sequence

import highspy
import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import halfspaces
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.lazy.conplan.runs import LpBudgetExhausted, LpFailure
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["PrismLP", "transitions", "SLACK_TOL"]

#: A slack above this marks a row the plan cannot meet.
SLACK_TOL = 1e-7
#: Two box faces closer than this are one face.
FACE_TOL = 1e-9


def transitions(plan: Sequence[int]) -> np.ndarray:
    """The steps t at which ``plan`` changes region (r_t != r_{t+1}).

    >>> transitions((4, 4, 5, 6, 6)).tolist()
    [1, 2]
    """
    p = np.asarray(plan, dtype=np.int64)
    return np.flatnonzero(p[1:] != p[:-1])


class PrismLP:
    """The prism LP of ``problem`` over the regions of ``abstraction`` (module doc); one
    cold HiGHS solve per :meth:`solve`, within ``clock`` when given. Counter:
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
        self.Hg, self.hg = (np.asarray(x, float) for x in halfspaces(problem.goal))  # type: ignore[arg-type]
        self.state_lo, self.state_hi = (np.asarray(b, float) for b in problem.state_box)
        self.start = np.asarray(problem.start, float)
        self.lp_calls = 0
        # the box regions' bounds (NaN: not a box; a region whose rows are +-e_j, one per side)
        unit = (np.abs(self.H).sum(axis=2) == 1.0) & (np.abs(self.H).max(axis=2) == 1.0)  # regions x K
        axis = np.abs(self.H).argmax(axis=2)
        sign = np.take_along_axis(self.H, axis[:, :, None], axis=2)[:, :, 0]
        self.box_lo = np.full((len(Hs), self.d), np.nan)
        self.box_hi = np.full((len(Hs), self.d), np.nan)
        rows = np.array([H.shape[0] for H in Hs])
        box = (rows == 2 * self.d) & np.all(unit | ~np.isfinite(self.h), axis=1)
        for j in range(self.d):
            up = (axis == j) & (sign > 0) & unit
            dn = (axis == j) & (sign < 0) & unit
            box &= (up.sum(axis=1) == 1) & (dn.sum(axis=1) == 1)
            self.box_hi[:, j] = np.where(up, self.h, np.inf).min(axis=1)
            self.box_lo[:, j] = -np.where(dn, self.h, np.inf).min(axis=1)
        self.box_lo[~box], self.box_hi[~box] = np.nan, np.nan

    def prism(self, chain: Sequence[int]) -> tuple[np.ndarray | None, np.ndarray | None]:
        """The prism of the box regions ``chain`` (module doc): lower and upper bounds,
        or (None, None) when they are not boxes each touching the next on a face normal
        to one common axis, or their common extent on the other axes is empty."""
        c = [int(r) for r in chain]
        lo, hi = self.box_lo[c], self.box_hi[c]
        if len(c) < 2 or np.isnan(lo).any() or np.isnan(hi).any():
            return None, None
        axis = None
        for a, b in zip(range(len(c) - 1), range(1, len(c))):
            olo, ohi = np.maximum(lo[a], lo[b]), np.minimum(hi[a], hi[b])
            flat = np.abs(ohi - olo) <= FACE_TOL
            if flat.sum() != 1 or np.any(~flat & (ohi - olo <= FACE_TOL)):
                return None, None
            k = int(np.argmax(flat))
            if axis is not None and k != axis:
                return None, None
            axis = k
        assert axis is not None
        plo, phi = lo.max(axis=0), hi.min(axis=0)
        plo[axis], phi[axis] = lo[:, axis].min(), hi[:, axis].max()
        if np.any(phi - plo <= FACE_TOL):
            return None, None
        return plo, phi

    def solve(
        self,
        plan: Sequence[int],
        prism_lo: np.ndarray | None = None,
        prism_hi: np.ndarray | None = None,
        *,
        strict: bool = False,
    ) -> tuple[np.ndarray, Trajectory | None] | None:
        """The elastic LP of ``plan`` (r_0..r_N): for the i-th change of region
        (``transitions(plan)[i]`` = t), both ends of the step in the box
        ``prism_lo[i]..prism_hi[i]`` where that row is finite, else p_{t+1} in r_t.
        Returns the slacks s_0..s_N and, when none exceeds :data:`SLACK_TOL`, a
        trajectory realising the plan (``strict``: the slacks fixed at zero, so its rows
        hold to HiGHS's tolerance); None when even the slacks do not make it feasible.
        Raises LpBudgetExhausted when the budget runs out, LpFailure when HiGHS gives no
        answer."""
        r = np.asarray(plan, dtype=np.int64)
        n, m, d = self.n, self.m, self.d
        N = len(r) - 1
        T = N + 1
        nx, nu = T * n, N * m
        s0 = nx + nu
        n_col = s0 + T
        R: list[np.ndarray] = []
        C: list[np.ndarray] = []
        V: list[np.ndarray] = []
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
        n_dyn = N * n
        row += n_dyn

        def block(times: np.ndarray, H: np.ndarray, hh: np.ndarray, slack_at: np.ndarray) -> None:
            """Rows H p_t - s <= hh, one block per time (H: nb x k x d, hh: nb x k)."""
            nonlocal row
            nb, k = H.shape[0], H.shape[1]
            if not nb:
                return
            rows = row + np.arange(nb * k).reshape(nb, k)
            R.append(np.repeat(rows[:, :, None], d, axis=2).ravel())
            C.append(((times * n)[:, None, None] + self.pos[None, None, :]).repeat(k, axis=1).ravel())
            V.append(H.ravel())
            R.append(rows.ravel())
            C.append(np.repeat(s0 + slack_at, k))
            V.append(-np.ones(nb * k))
            hi.append(hh.ravel())
            row += nb * k

        ts = np.arange(T)
        block(ts, self.H[r], self.h[r], ts)  # p_t in r_t
        tr = transitions(r)
        wide = np.zeros(len(tr), dtype=bool) if prism_lo is None else np.isfinite(prism_lo).all(axis=1)
        seg = tr[~wide]
        block(seg + 1, self.H[r[seg]], self.h[r[seg]], seg + 1)  # CON-PLAN's row: p_{t+1} in r_t
        pr = tr[wide]
        if len(pr):
            assert prism_lo is not None and prism_hi is not None
            Hb = np.concatenate([np.eye(d), -np.eye(d)])[None].repeat(len(pr), axis=0)
            hb = np.concatenate([prism_hi[wide], -prism_lo[wide]], axis=1)
            block(pr, Hb, hb, pr + 1)
            block(pr + 1, Hb, hb, pr + 1)
        Kg = len(self.hg)
        block(np.array([N]), self.Hg[None], self.hg[None], np.array([N]))
        del Kg
        Ra, Ca, Va = np.concatenate(R), np.concatenate(C), np.concatenate(V)
        keep = Va != 0.0
        row_hi = np.concatenate([np.zeros(n_dyn), *hi])
        row_lo = np.concatenate([np.zeros(n_dyn), np.full(row - n_dyn, -np.inf)])
        col_lo = np.concatenate([np.tile(self.state_lo, T), np.full(nu, -self.problem.input_bound), np.zeros(T)])
        col_hi = np.concatenate(
            [
                np.tile(self.state_hi, T),
                np.full(nu, self.problem.input_bound),
                np.zeros(T) if strict else np.full(T, np.inf),
            ]
        )
        col_lo[:n] = col_hi[:n] = self.start
        cost = np.zeros(n_col)
        cost[s0:] = 1.0
        lp = csc_lp(n_col, row, Ra[keep], Ca[keep], Va[keep], cost, col_lo, col_hi, row_lo, row_hi)
        # a cold dual simplex, without presolve and with Devex pricing: 4,000 steps 1.0 -> 0.7 s,
        # 400 steps 21 -> 17 ms
        h = new_highs(presolve="off", simplex_dual_edge_weight_strategy=1)
        if self.clock is not None:
            left = self.clock.remaining()
            if left <= 0:
                raise LpBudgetExhausted("budget ran out in the prism LP")
            h.setOptionValue("time_limit", float(min(left, 1e9)))  # (a fresh instance: its run time is 0)
        h.passModel(lp)
        h.run()
        self.lp_calls += 1
        status = h.getModelStatus()
        S = highspy.HighsModelStatus
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        if status == S.kTimeLimit:
            raise LpBudgetExhausted("budget ran out in the prism LP")
        if status != S.kOptimal:
            raise LpFailure(f"the prism LP ended with HiGHS status {h.modelStatusToString(status)}")
        col = np.asarray(h.getSolution().col_value)
        slack = np.maximum(col[s0:], 0.0)
        if slack.max(initial=0.0) > SLACK_TOL:
            return slack, None
        return slack, Trajectory(col[:nx].reshape(T, n), col[nx:s0].reshape(N, m))

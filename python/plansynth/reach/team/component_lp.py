"""The LP of one component of a team plan (Shoukry et al., CDC 2016, Section V, for the
robots; the SMC encoding of separation, CDC 2017, Section IV, for the pairs), its rows
labelled with the literals and flags a certificate maps back to
(:mod:`plansynth.reach.team.counterexample`).

For a :class:`~plansynth.reach.team.plans.TeamPlan` of horizon L the LP has, per robot,
its states x_0..x_L and inputs u_0..u_{L-1} (x_0 the start, the inputs within the
bound, the states within the state bounds and the robot's workspace), the dynamics, its
regions at every sample and along every segment (the region of step t holds x_{t+1}
too), its goal at L (a convex shape, or a point), and, when the robot must end where it
can stay (``stop``, or a mission read on a finite plan), ``x_L = A x_L + B w`` for an
admissible input w. Per engaged pair step (i, j, t) with side k:
``A_k (p_i - p_j) >= b_k`` at samples t and t + 1 (relative motion within a step is
linear, so the side holds along the step); per engaged robot-obstacle step, the same
with the obstacle's known position at t, at every waypoint time inside the step (the
robot's position there interpolated from its two samples) and at t + 1.

Under disturbances (:mod:`plansynth.reach.team.robust`) each bound, the goal rows and
each side's row are tightened by the margins of the step they constrain (the robots'
:class:`~plansynth.reach.team.robust.RobotMargins`, the owner's ``pair_margins`` and
``obstacle_margins``).
"""

from __future__ import annotations

import math
from typing import Any

import highspy
import numpy as np

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.highs import Rows, pass_csc
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.team.plans import TeamPlan
from plansynth.reach.team.problem import TeamProblem

__all__ = ["ComponentLp", "bend_fractions", "run_lp", "load_bounds"]

INF = highspy.kHighsInf
DYN, REG, GOAL, SIDE, MOVE = range(5)


def bend_fractions(problem: TeamProblem, o: int, t: int) -> tuple[float, ...]:
    """Where, as fractions of step t, moving obstacle o passes a waypoint."""
    t0, t1 = problem.time_of(t), problem.time_of(t + 1)
    return tuple((b - t0) / (t1 - t0) for b in problem.moving_obstacles[o].bends(t0, t1))


def run_lp(h: highspy.Highs, clock: Clock, stats: Any) -> tuple[str, np.ndarray | None, np.ndarray | None]:
    """Run the loaded LP within the clock: ``("feasible", x, None)`` or ``("infeasible",
    None, dual ray or None)``; ``stats.lp_calls`` counts it."""
    left = clock.remaining()
    if left <= 0:
        raise BudgetExhausted("the joint CON-PLAN", "time")
    # HiGHS compares time_limit with the instance's run time summed over its runs, and
    # instances are reused: the limit is the seconds left past that sum
    h.setOptionValue("time_limit", INF if math.isinf(left) else float(h.getRunTime() + max(left, 0.01)))
    h.run()
    stats.lp_calls += 1
    st = h.getModelStatus()
    if st == highspy.HighsModelStatus.kOptimal:
        return "feasible", np.asarray(h.getSolution().col_value, float), None
    if st == highspy.HighsModelStatus.kTimeLimit:
        raise BudgetExhausted("the joint CON-PLAN", "time")
    if st in (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnboundedOrInfeasible):
        _, has_ray, ray = h.getDualRay()
        return "infeasible", None, np.asarray(ray, float) if has_ray else None
    raise LpFailure(f"HiGHS answered {h.modelStatusToString(st)} on a joint CON-PLAN LP")


def load_bounds(h: highspy.Highs, rlo: np.ndarray, rhi: np.ndarray, clo: np.ndarray, chi: np.ndarray) -> None:
    """Every row's and column's bounds of the loaded LP replaced (the basis kept)."""
    n_row, n_col = len(rlo), len(clo)
    h.changeRowsBounds(n_row, np.arange(n_row, dtype=np.int32), rlo, rhi)
    h.changeColsBounds(n_col, np.arange(n_col, dtype=np.int32), clo, chi)


class ComponentLp:
    """The LP of one component (robots ``comp``) of a plan, its rows labelled with
    the literals and flags a certificate maps back to. ``owner`` is the
    :class:`~plansynth.reach.team.conplan.TeamConPlan` it checks a plan for (its robots'
    models, sides, objective, clock and counters)."""

    def __init__(self, owner: Any, plan: TeamPlan, comp: tuple[int, ...], sides: dict, msides: dict) -> None:
        self.owner, self.plan, self.comp = owner, plan, comp
        self.sides, self.msides = sides, msides
        L = plan.horizon
        self.L = L
        self.base: dict[int, int] = {}
        ncol = 0
        for r in comp:
            self.base[r] = ncol
            ncol += owner.models[r].columns(L)
        self.ncol = ncol
        self.rows = Rows()
        self.kind: list[np.ndarray] = []
        self.lit: list[np.ndarray] = []
        self.t_lo: list[np.ndarray] = []
        self.t_hi: list[np.ndarray] = []
        self.literals: list[tuple] = []
        self._bounds: dict[bool, tuple[np.ndarray, np.ndarray]] = {}  # col_bounds's, per flag
        for r in comp:
            self._robot(r)
        self._sides(sides)
        self._msides(msides)
        self.n_effort = 0
        if owner.objective == "effort":
            self._effort()

    # columns
    def x(self, r: int, t: int) -> int:
        return self.base[r] + t * self.owner.models[r].n

    def u(self, r: int, t: int) -> int:
        m = self.owner.models[r]
        return self.base[r] + (self.L + 1) * m.n + t * m.m

    def w(self, r: int) -> int:
        m = self.owner.models[r]
        return self.base[r] + (self.L + 1) * m.n + self.L * m.m

    def _meta(self, count: int, kind: int, lit: tuple | None, t_lo: int, t_hi: int) -> None:
        if lit is None:
            idx = -1
        else:
            idx = len(self.literals)
            self.literals.append(lit)
        self.kind.append(np.full(count, kind))
        self.lit.append(np.full(count, idx))
        self.t_lo.append(np.full(count, t_lo))
        self.t_hi.append(np.full(count, t_hi))

    def _add(self, R, C, V, lo, hi, kind, lit, t_lo, t_hi) -> None:  # noqa: ANN001 - arrays
        self.rows.add(R, C, V, lo, hi)
        self._meta(len(lo), kind, lit, t_lo, t_hi)

    def _block(self, R, C, V, lo, hi, kind, lits, t_lo, t_hi) -> None:  # noqa: ANN001 - arrays
        """Many rows at once: ``lits``, ``t_lo``, ``t_hi`` per row (``lits`` indices into
        :attr:`literals`, -1: none)."""
        self.rows.add(R, C, V, lo, hi)
        self.kind.append(np.full(len(lo), kind))
        self.lit.append(np.asarray(lits))
        self.t_lo.append(np.asarray(t_lo))
        self.t_hi.append(np.asarray(t_hi))

    def _robot(self, r: int) -> None:
        m, L = self.owner.models[r], self.L
        n = m.n
        rows = _robot_rows(self.owner, r, L)
        if L:  # x_{t+1} - A x_t - B u_t = 0, every step at once
            R, C, V, zeros, none, t_lo, t_hi = rows.dynamics
            self._block(R, C + self.x(r, 0), V, zeros, zeros, DYN, none, t_lo, t_hi)
        pos = np.asarray(m.pos)
        d = len(pos)
        regions = self.plan.regions[r]
        base_idx = len(self.literals)
        self.literals.extend(("at", r, t, regions[t]) for t in range(L + 1))
        # blocks: (t, sample) for every sample, and (t, t + 1) for every segment's end
        table = rows.table
        bt, btt = rows.bt, rows.btt
        reg = np.asarray(regions)[bt]
        K = table.K[reg]
        count = int(K.sum())
        first = np.cumsum(K) - K  # each block's first row
        facet = np.repeat(table.offset[reg] - first, K) + np.arange(count)  # its rows of the stacked H
        R = np.repeat(np.arange(count), d)
        C = np.repeat(self.x(r, 0) + btt * n, K * d) + np.tile(pos, count)
        V = table.H[facet].ravel()
        hi = table.h[facet]
        self._block(
            R, C, V, np.full(count, -INF), hi, REG, np.repeat(base_idx + bt, K), np.repeat(bt, K), np.repeat(btt, K)
        )
        ci, di = np.nonzero(m.B)
        cv = m.B[ci, di]
        if m.goal is not None:
            if m.goal[0] == "point":
                p = np.asarray(m.goal[1], float)
                self._add(np.arange(d), self.x(r, L) + pos, np.ones(d), p, p, GOAL, None, L, L)
            else:
                H, h = m.goal[1], m.goal[2]
                K = H.shape[0]
                if m.margins is not None and m.margins.goal is not None:  # the final tube inside the goal
                    h = h - m.margins.goal[L]
                self._add(
                    np.repeat(np.arange(K), d),
                    np.tile(self.x(r, L) + pos, K),
                    H.ravel(),
                    np.full(K, -INF),
                    h,
                    GOAL,
                    None,
                    L,
                    L,
                )
        if m.rest:  # (I - A) x_L - B w = 0
            I_A = np.eye(n) - m.A
            ei, ej = np.nonzero(I_A)
            R = np.concatenate([ei, ci])
            C = np.concatenate([self.x(r, L) + ej, self.w(r) + di])
            V = np.concatenate([I_A[ei, ej], -cv])
            self._add(R, C, V, np.zeros(n), np.zeros(n), GOAL, None, L, L)

    def _effort(self) -> None:
        """Columns e >= |u| (one per input and step), the LP minimising their sum."""
        first = self.ncol
        for r in self.comp:
            m = self.owner.models[r]
            for t in range(self.L):
                for j in range(m.m):
                    e, u = self.ncol, self.u(r, t) + j
                    self.ncol += 1
                    R = np.array([0, 0, 1, 1])
                    self._add(
                        R,
                        np.array([e, u, e, u]),
                        np.array([1.0, -1.0, 1.0, 1.0]),
                        np.zeros(2),
                        np.full(2, INF),
                        DYN,
                        None,
                        t,
                        t + 1,
                    )
        self.n_effort = self.ncol - first

    def _sides(self, sides: dict) -> None:
        """The rows of every engaged pair step: ``A_k (p_i - p_j) >= b_k`` at t and t + 1."""
        if not sides:
            return
        owner = self.owner
        keys = list(sides.items())
        facets = [owner.pair_facets[(i, j)] for (i, j, _), _ in keys]
        a = np.array([f.A[k] for f, (_, k) in zip(facets, keys)])  # one row per pair step
        b = np.array([f.b[k] for f, (_, k) in zip(facets, keys)])
        d = a.shape[1]
        first = len(self.literals)
        self.literals.extend(("side", i, j, t, k) for (i, j, t), k in keys)
        ci = np.array([[self.x(i, t), owner.models[i].n] for (i, _, t), _ in keys])
        cj = np.array([[self.x(j, t), owner.models[j].n] for (_, j, t), _ in keys])
        pi = np.array([owner.models[i].pos for (i, _, _), _ in keys])
        pj = np.array([owner.models[j].pos for (_, j, _), _ in keys])
        E = len(keys)
        # rows 2e (sample t) and 2e + 1 (sample t + 1), each a on p_i and -a on p_j
        C = np.empty((E, 2, 2 * d), dtype=np.int64)
        for s in (0, 1):
            C[:, s, :d] = ci[:, :1] + s * ci[:, 1:] + pi
            C[:, s, d:] = cj[:, :1] + s * cj[:, 1:] + pj
        V = np.broadcast_to(np.concatenate([a, -a], axis=1)[:, None, :], (E, 2, 2 * d))
        t = np.array([t for (_, _, t), _ in keys])
        lo = np.repeat(b, 2).astype(float).reshape(E, 2)
        for e, ((i, j, te), k) in enumerate(keys):  # under disturbances, the sides move out
            grow = owner.pair_margins.get((i, j))
            if grow is not None:
                lo[e] += grow[te : te + 2, k]
        self._block(
            np.repeat(np.arange(2 * E), 2 * d),
            C.ravel(),
            V.ravel(),
            lo.ravel(),
            np.full(2 * E, INF),
            SIDE,
            np.repeat(first + np.arange(E), 2),
            np.repeat(t, 2),
            np.repeat(t + 1, 2),
        )

    def _msides(self, msides: dict) -> None:
        """The rows of every engaged robot-obstacle step: ``A_k (p_r - c) >= b_k`` at t,
        at each of the obstacle's waypoint times inside the step (p_r there
        interpolated from its samples) and at t + 1."""
        if not msides:
            return
        owner = self.owner
        Rs, Cs, Vs, lo, lits, tl = [], [], [], [], [], []
        row = 0
        for (r, o, t), k in msides.items():
            R, C, V, lo_k = owner.mside_rows(r, o, t, k)
            q = len(lo_k)
            Rs.append(R + row)
            Cs.append(C + self.base[r])
            Vs.append(V)
            lo.append(lo_k)
            lits.append(np.full(q, len(self.literals)))
            self.literals.append(("mside", r, o, t, k))
            tl.append(np.full(q, t))
            row += q
        t_lo = np.concatenate(tl)
        self._block(
            np.concatenate(Rs),
            np.concatenate(Cs),
            np.concatenate(Vs),
            np.concatenate(lo),
            np.full(row, INF),
            MOVE,
            np.concatenate(lits),
            t_lo,
            t_lo + 1,
        )

    # bounds
    def col_bounds(self, *, start: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The columns' bounds (``start``: the start columns fixed at the start), built
        once per component, horizon and flag (they do not depend on the plan: every LP
        of the component at that horizon shares them, read-only)."""
        hit = self._bounds.get(start)
        if hit is None:
            key = ("bounds", self.comp, self.L, start, self.n_effort)
            hit = self.owner.row_cache.get(key)
            if hit is None:
                hit = self.owner.row_cache[key] = self._col_bounds(start)
                for a in hit:
                    a.setflags(write=False)
            self._bounds[start] = hit
        return hit

    def _col_bounds(self, start: bool) -> tuple[np.ndarray, np.ndarray]:
        lo = np.empty(self.ncol)
        hi = np.empty(self.ncol)
        L = self.L
        for r in self.comp:
            m = self.owner.models[r]
            b = self.base[r]
            lo[b : b + (L + 1) * m.n] = np.tile(m.x_lo, L + 1)
            hi[b : b + (L + 1) * m.n] = np.tile(m.x_hi, L + 1)
            if start:
                lo[b : b + m.n] = m.start
                hi[b : b + m.n] = m.start
            e = b + m.columns(L)
            lo[b + (L + 1) * m.n : e] = -m.u_bound
            hi[b + (L + 1) * m.n : e] = m.u_bound
            if m.margins is not None:  # under a disturbance: every bound tightened by the tube at its step
                g = m.margins
                lo[b : b + (L + 1) * m.n] += g.state_lo[: L + 1].ravel()
                hi[b : b + (L + 1) * m.n] -= g.state_hi[: L + 1].ravel()
                u0 = b + (L + 1) * m.n
                lo[u0 : u0 + L * m.m] += g.input_lo[:L].ravel()
                hi[u0 : u0 + L * m.m] -= g.input_hi[:L].ravel()
                if m.rest:  # the resting input keeps room for the feedback's largest share
                    lo[u0 + L * m.m : e] += g.rest_lo
                    hi[u0 + L * m.m : e] -= g.rest_hi
        if self.n_effort:
            lo[self.ncol - self.n_effort :] = 0.0
            hi[self.ncol - self.n_effort :] = INF
        return np.where(np.isfinite(lo), lo, -INF), np.where(np.isfinite(hi), hi, INF)

    def start_columns(self) -> np.ndarray:
        return np.concatenate([self.x(r, 0) + np.arange(self.owner.models[r].n) for r in self.comp])

    def solve(self, clock: Clock) -> tuple[str, np.ndarray | None, np.ndarray | None]:
        R, C, V = self.rows.coo()
        rlo, rhi = self.rows.bounds()
        clo, chi = self.col_bounds()
        self.coo = (R, C, V)
        self.rb = (rlo, rhi)
        self.cb = (clo, chi)
        cost = np.zeros(self.ncol)
        cost[self.ncol - self.n_effort :] = 1.0 if self.n_effort else 0.0
        self.clock = clock
        self.h = self.owner.highs("component")
        pass_csc(self.h, self.ncol, self.rows.n_row, R, C, V, cost, clo, chi, rlo, rhi)
        return self.run()

    @property
    def n_row(self) -> int:
        return self.rows.n_row

    def run(self) -> tuple[str, np.ndarray | None, np.ndarray | None]:
        return run_lp(self.h, self.clock, self.owner.stats)

    def split(self, x: np.ndarray) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        out = {}
        L = self.L
        for r in self.comp:
            m = self.owner.models[r]
            X = x[self.x(r, 0) : self.x(r, 0) + (L + 1) * m.n].reshape(L + 1, m.n)
            U = x[self.u(r, 0) : self.u(r, 0) + L * m.m].reshape(L, m.m)
            X = X.copy()
            X[0] = m.start  # exactly the start (the column is fixed)
            out[r] = (X, U)
        return out

    def elastic(self) -> dict[int, tuple[np.ndarray, np.ndarray]] | None:
        """The trajectories of the LP whose side rows may be broken at a cost (the sum
        of how far each is broken): a guess at the sides to try next, or None when the
        other rows alone are infeasible. It is solved in this LP's own model, after its
        infeasible run (a slack column per side row, warm-started from that basis): the
        model is not used for the component LP again."""
        kind = np.concatenate(self.kind)
        soft = np.flatnonzero((kind == SIDE) | (kind == MOVE)).astype(np.int32)
        k = len(soft)
        if self.n_effort:
            effort = np.arange(self.ncol - self.n_effort, self.ncol, dtype=np.int32)
            self.h.changeColsCost(len(effort), effort, np.zeros(len(effort)))
        self.h.addCols(k, np.ones(k), np.zeros(k), np.full(k, INF), k, np.arange(k, dtype=np.int32), soft, np.ones(k))
        status, x, _ = run_lp(self.h, self.clock, self.owner.stats)
        if status != "feasible" or x is None:
            return None
        return self.split(x[: self.ncol])


class RegionTable:
    """A robot's regions stacked once: ``H`` (every region's rows, region after region),
    ``h``, ``K`` (rows per region) and ``offset`` (each region's first row)."""

    def __init__(self, regions: tuple[tuple[np.ndarray, np.ndarray], ...]) -> None:
        self.K = np.array([H.shape[0] for H, _ in regions], dtype=np.int64)
        self.offset = np.cumsum(self.K) - self.K
        self.H = np.concatenate([H for H, _ in regions]) if regions else np.zeros((0, 0))
        self.h = np.concatenate([h for _, h in regions]) if regions else np.zeros(0)


class RobotRows:
    """What the rows of robot r at horizon L share in every plan, built once per
    (r, L) by :func:`_robot_rows`: the dynamics block (columns counted from the
    robot's first), the blocks' steps ``bt`` and ``btt`` (samples, then segment
    ends) and the robot's :class:`RegionTable`."""

    def __init__(self, m: Any, L: int, table: RegionTable) -> None:
        n = m.n
        ai, bi = np.nonzero(m.A)
        av = m.A[ai, bi]
        ci, di = np.nonzero(m.B)
        cv = m.B[ci, di]
        t = np.arange(L)
        R = np.concatenate(
            [np.add.outer(t * n, np.arange(n)), np.add.outer(t * n, ai), np.add.outer(t * n, ci)], axis=1
        )
        C = np.concatenate(
            [
                np.add.outer((t + 1) * n, np.arange(n)),
                np.add.outer(t * n, bi),
                np.add.outer((L + 1) * n + t * m.m, di),
            ],
            axis=1,
        )
        V = np.tile(np.concatenate([np.ones(n), -av, -cv]), L)
        rows = L * n
        self.dynamics = (
            R.ravel(),
            C.ravel(),
            V,
            np.zeros(rows),
            np.full(rows, -1),
            np.repeat(t, n),
            np.repeat(t + 1, n),
        )
        self.bt = np.concatenate([np.arange(L + 1), np.arange(L)])
        self.btt = np.concatenate([np.arange(L + 1), np.arange(1, L + 1)])
        self.table = table
        for a in (*self.dynamics, self.bt, self.btt):  # shared by every LP: never written
            a.setflags(write=False)


def _robot_rows(owner: Any, r: int, L: int) -> RobotRows:
    """Robot r's :class:`RobotRows` at horizon L, kept by ``owner`` (its ``row_cache``)."""
    cache = owner.row_cache
    hit = cache.get((r, L))
    if hit is None:
        m = owner.models[r]
        table = cache.get(("table", r))
        if table is None:
            table = cache[("table", r)] = RegionTable(m.regions)
        hit = cache[(r, L)] = RobotRows(m, L, table)
    return hit

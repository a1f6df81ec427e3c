"""The joint CON-PLAN: the LP of a team plan, its counterexamples, and the engagement of
pair steps (Shoukry et al., CDC 2016, Section V, for the robots; the SMC encoding of
separation, CDC 2017, Section IV, for the pairs).

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

**Components.** Robots that no engaged pair step links have independent LPs: the plan's
LP splits into one per component of the graph of engaged pairs, each solved on its own
(a singleton's LP is the single-robot CON-PLAN), and a counterexample names the robots
of its component only. Feasible component LPs are kept by their constraints, so that a
robot whose part of the plan did not change is not solved again.

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

**Engagement.** When every component is feasible, each pair step and robot-obstacle
step that DIS-PLAN did not decide is checked on the trajectories: if no side holds at
both samples (and at the obstacle's waypoint times), the step and its neighbours are
engaged (:class:`~plansynth.reach.team.plans.Engage`); otherwise the team's trajectory
is the answer (every step keeps a side: a plan of the full encoding).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import highspy
import numpy as np

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.lazy.conflict import Feasible
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.team.geometry import Facets
from plansynth.reach.team.plans import Engage, TeamConflict, TeamPlan
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["RobotModel", "TeamConPlan", "ENGAGE_AROUND"]

INF = highspy.kHighsInf
DYN, REG, GOAL, SIDE, MOVE = range(5)
#: steps engaged on each side of a step where a pair breaks the separation
ENGAGE_AROUND = 1
#: a side "holds" when its margin is at least -this times the workspace's size
HOLD_TOL = 1e-9
#: the deletion filter runs on conflicts of at most this many literals
MINIMIZE_MAX_LITERALS = 24


@dataclass(frozen=True, eq=False)
class RobotModel:
    """What CON-PLAN needs of one robot: dynamics, start, bounds of its states (its own
    workspace, a sized robot's shrunk one) and inputs, its regions ``(H, h)``, its goal
    (``("shape", H, h)``, ``("point", p)`` or None) and whether it must end where it
    can stay (``rest``)."""

    A: np.ndarray
    B: np.ndarray
    pos: tuple[int, ...]
    start: np.ndarray
    x_lo: np.ndarray
    x_hi: np.ndarray
    u_bound: float
    regions: tuple[tuple[np.ndarray, np.ndarray], ...]
    goal: tuple | None
    rest: bool

    @property
    def n(self) -> int:
        return self.A.shape[0]

    @property
    def m(self) -> int:
        return self.B.shape[1]

    def columns(self, L: int) -> int:
        return (L + 1) * self.n + L * self.m + (self.m if self.rest else 0)


@dataclass
class TeamLpStats:
    lp_calls: int = 0
    infeasible: int = 0
    certified: int = 0
    uncertified: int = 0
    cached: int = 0
    engagements: int = 0
    transit: int = 0
    seconds: float = 0.0
    largest_component: int = 0
    conflict_sizes: list[int] = field(default_factory=list)


class TeamConPlan:
    """The joint CON-PLAN (see the module docstring), a
    :class:`~plansynth.reach.lazy.loop.TheoryChecker` of team plans.

    ``pair_facets[(i, j)]``, ``obstacle_facets[(r, o)]``: the sides of each pair and
    robot-obstacle couple (absent: nothing forbidden). ``hints``: where the side each
    engaged step keeps best in the latest trajectories is written (DIS-PLAN's phases).
    """

    def __init__(
        self,
        problem: TeamProblem,
        models: Sequence[RobotModel],
        pair_facets: dict[tuple[int, int], Facets],
        obstacle_facets: dict[tuple[int, int], Facets],
        clock: Clock,
        hints: dict[tuple, int] | None = None,
        objective: str = "none",
        transit: Sequence[Any] | None = None,
    ) -> None:
        self.problem = problem
        self.transit = list(transit) if transit is not None else []
        self.objective = objective
        self.elastic = True
        self.models = list(models)
        self.pair_facets = pair_facets
        self.obstacle_facets = obstacle_facets
        self.clock = clock
        self.hints = hints if hints is not None else {}
        self.stats = TeamLpStats()
        self.plans_checked = 0  # plans with an infeasible LP (the lazy loop's deferral counts them)
        self._cache: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        ws = problem.workspace
        self.scale = max(1.0, max(abs(v) for v in ws.lo + ws.hi))

    # -- the TheoryChecker interface ---------------------------------------------------
    def check(self, plan: TeamPlan) -> Feasible | tuple:
        L = plan.horizon
        legs = self._transit(plan)
        if legs:
            self.plans_checked += 1
            self.stats.transit += len(legs)
            return legs
        comps = _components(len(self.models), plan)
        self.stats.largest_component = max(self.stats.largest_component, max(len(c) for c in comps))
        states: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        conflicts = []
        for comp in comps:
            out = self._component(plan, comp)
            if isinstance(out, TeamConflict):
                conflicts.append(out)
            else:
                states.update(out)
        if conflicts:
            self.plans_checked += 1
            return tuple(conflicts)
        engage = self._engagements(plan, states)
        if engage is not None:
            self.stats.engagements += 1
            return (engage,)
        X = np.hstack([states[r][0] for r in range(len(self.models))])
        U = (
            np.hstack([states[r][1] for r in range(len(self.models))])
            if L
            else np.zeros((0, sum(m.m for m in self.models)))
        )
        return Feasible(Trajectory(states=X, inputs=U))

    def _transit(self, plan: TeamPlan) -> tuple[TeamConflict, ...]:
        """Each robot's transit violations (the single-robot layer,
        :class:`~plansynth.reach.lazy.transit.TransitCheck`: legs between regions, or from
        the start or to the goal, in fewer steps than the robot can make them), as
        conflicts of the team."""
        out = []
        for r, tc in enumerate(self.transit):
            if tc is None:
                continue
            for c in tc.violations(plan.regions[r]):
                out.append(
                    TeamConflict(
                        tuple(("at", r, t, i) for t, i in c.literals),
                        start=c.anchored_start,
                        goal=c.anchored_goal,
                        timed=False,
                        horizon=c.horizon,
                        first_time=c.first_time,
                        last_time=c.last_time,
                    )
                )
        return tuple(out)

    # -- one component --------------------------------------------------------------
    def _component(
        self, plan: TeamPlan, comp: tuple[int, ...]
    ) -> dict[int, tuple[np.ndarray, np.ndarray]] | TeamConflict:
        L = plan.horizon
        robots = set(comp)
        sides = tuple(sorted((key, k) for key, k in plan.sides.items() if key[0] in robots))
        msides = tuple(sorted((key, k) for key, k in plan.msides.items() if key[0] in robots))
        key = (L, comp, tuple(plan.regions[r] for r in comp), sides, msides)
        hit = self._cache.get(key)
        if hit is not None:
            self.stats.cached += 1
            return dict(zip(comp, hit))  # type: ignore[arg-type]
        lp = _ComponentLp(self, plan, comp, dict(sides), dict(msides))
        t0 = time.perf_counter()
        try:
            status, x, ray = lp.solve(self.clock)
            if status == "feasible":
                out = lp.split(x)
                self._cache[key] = tuple(out[r] for r in comp)  # type: ignore[assignment]
                return out
            self.stats.infeasible += 1
            conflict = lp.conflict(ray)
            if self.elastic and (sides or msides):
                guess = lp.elastic()
                if guess is not None:
                    self._hint(plan, guess, comp)
        finally:
            self.stats.seconds += time.perf_counter() - t0
        if conflict.certified:
            self.stats.certified += 1
        else:
            self.stats.uncertified += 1
        self.stats.conflict_sizes.append(len(conflict.literals))
        return conflict

    def _hint(self, plan: TeamPlan, states: dict[int, tuple[np.ndarray, np.ndarray]], comp: tuple[int, ...]) -> None:
        """DIS-PLAN's phases for the component's engaged steps: the sides a trajectory
        that breaks the fewest of them keeps best."""
        robots = set(comp)
        pos = {r: states[r][0][:, list(self.problem.robots[r].dynamics.position)] for r in comp}
        for i, j, t in plan.sides:
            if i in robots:
                f = self.pair_facets[(i, j)]
                k, _ = f.best_side(pos[i][t] - pos[j][t], pos[i][t + 1] - pos[j][t + 1])
                self.hints[("side", i, j, t)] = k
        for r, o, t in plan.msides:
            if r in robots:
                S = self._obstacle_margins(pos[r][t : t + 2], o, self.obstacle_facets[(r, o)], 1, first=t)
                self.hints[("mside", r, o, t)] = int(S[0].argmax())

    # -- engagement -----------------------------------------------------------------
    def _engagements(self, plan: TeamPlan, states: dict[int, tuple[np.ndarray, np.ndarray]]) -> Engage | None:
        L = plan.horizon
        if L == 0:
            return None
        P = [self.problem.robots[r].dynamics for r in range(len(self.models))]
        pos = [states[r][0][:, list(P[r].position)] for r in range(len(self.models))]
        eps = HOLD_TOL * self.scale
        pairs: list[tuple[int, int, int]] = []
        for (i, j), f in self.pair_facets.items():
            M = f.margins(pos[i] - pos[j])
            S = np.minimum(M[:-1], M[1:])
            best = S.argmax(axis=1)
            ok = S[np.arange(L), best] >= -eps
            for t in range(L):
                if (i, j, t) in plan.sides:
                    self.hints[("side", i, j, t)] = int(best[t])
            for t in np.flatnonzero(~ok):
                for u in range(max(0, t - ENGAGE_AROUND), min(L, t + ENGAGE_AROUND + 1)):
                    if (i, j, u) not in plan.sides:
                        pairs.append((i, j, u))
                        self.hints[("side", i, j, u)] = int(best[u])
        obstacles: list[tuple[int, int, int]] = []
        for (r, o), f in self.obstacle_facets.items():
            S = self._obstacle_margins(pos[r], o, f, L)
            best = S.argmax(axis=1)
            ok = S[np.arange(L), best] >= -eps
            for t in range(L):
                if (r, o, t) in plan.msides:
                    self.hints[("mside", r, o, t)] = int(best[t])
            for t in np.flatnonzero(~ok):
                for u in range(max(0, t - ENGAGE_AROUND), min(L, t + ENGAGE_AROUND + 1)):
                    if (r, o, u) not in plan.msides:
                        obstacles.append((r, o, u))
                        self.hints[("mside", r, o, u)] = int(best[u])
        if not pairs and not obstacles:
            return None
        return Engage(tuple(sorted(set(pairs))), tuple(sorted(set(obstacles))))

    def _obstacle_margins(self, P: np.ndarray, o: int, f: Facets, L: int, first: int = 0) -> np.ndarray:
        """Per step and side, the worst margin over the step's samples and the
        obstacle's waypoint times inside it (``P[0]`` is the position at step ``first``)."""
        ob = self.problem.moving_obstacles[o]
        out = np.empty((L, f.n_sides))
        for t in range(L):
            worst = np.full(f.n_sides, np.inf)
            for lam in (0.0, *_bend_fractions(self.problem, o, first + t), 1.0):
                p = (1 - lam) * P[t] + lam * P[t + 1]
                c = ob.position(self.problem.time_of(first + t + lam))
                worst = np.minimum(worst, f.margins(p - c))
            out[t] = worst
        return out


def _bend_fractions(problem: TeamProblem, o: int, t: int) -> tuple[float, ...]:
    """Where, as fractions of step t, moving obstacle o passes a waypoint."""
    t0, t1 = problem.time_of(t), problem.time_of(t + 1)
    return tuple((b - t0) / (t1 - t0) for b in problem.moving_obstacles[o].bends(t0, t1))


def _components(n: int, plan: TeamPlan) -> list[tuple[int, ...]]:
    """The robots linked by the plan's engaged pair steps (union-find)."""
    parent = list(range(n))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for i, j, _ in plan.sides:
        a, b = find(i), find(j)
        if a != b:
            parent[max(a, b)] = min(a, b)
    groups: dict[int, list[int]] = {}
    for r in range(n):
        groups.setdefault(find(r), []).append(r)
    return [tuple(g) for g in groups.values()]


class _ComponentLp:
    """The LP of one component (robots ``comp``) of a plan, its rows labelled with
    the literals and flags a certificate maps back to."""

    def __init__(self, owner: TeamConPlan, plan: TeamPlan, comp: tuple[int, ...], sides: dict, msides: dict) -> None:
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
        for r in comp:
            self._robot(r)
        self._sides(sides)
        for (r, o, t), k in msides.items():
            self._mside(r, o, t, k)
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
        ai, bi = np.nonzero(m.A)
        av = m.A[ai, bi]
        ci, di = np.nonzero(m.B)
        cv = m.B[ci, di]
        if L:  # x_{t+1} - A x_t - B u_t = 0, every step at once
            t = np.arange(L)
            R = np.concatenate(
                [np.add.outer(t * n, np.arange(n)), np.add.outer(t * n, ai), np.add.outer(t * n, ci)], axis=1
            )
            C = np.concatenate(
                [
                    np.add.outer(self.x(r, 0) + (t + 1) * n, np.arange(n)),
                    np.add.outer(self.x(r, 0) + t * n, bi),
                    np.add.outer(self.u(r, 0) + t * m.m, di),
                ],
                axis=1,
            )
            V = np.tile(np.concatenate([np.ones(n), -av, -cv]), L)
            rows = L * n
            self._block(
                R.ravel(),
                C.ravel(),
                V,
                np.zeros(rows),
                np.zeros(rows),
                DYN,
                np.full(rows, -1),
                np.repeat(t, n),
                np.repeat(t + 1, n),
            )
        pos = np.asarray(m.pos)
        d = len(pos)
        regions = self.plan.regions[r]
        base_idx = len(self.literals)
        self.literals.extend(("at", r, t, regions[t]) for t in range(L + 1))
        # blocks: (t, sample) for every sample, and (t, t + 1) for every segment's end
        bt = np.concatenate([np.arange(L + 1), np.arange(L)])
        btt = np.concatenate([np.arange(L + 1), np.arange(1, L + 1)])
        Hs = [m.regions[regions[t]] for t in bt]
        K = np.array([H.shape[0] for H, _ in Hs])
        starts = np.concatenate([[0], np.cumsum(K)[:-1]])
        count = int(K.sum())
        row_of = np.repeat(starts, K) + np.concatenate([np.arange(k) for k in K])
        R = np.repeat(row_of, d)
        C = (np.repeat(self.x(r, 0) + btt * n, K * d) + np.tile(pos, count)).astype(np.int64)
        V = np.concatenate([H.ravel() for H, _ in Hs])
        hi = np.concatenate([h for _, h in Hs])
        self._block(
            R, C, V, np.full(count, -INF), hi, REG, np.repeat(base_idx + bt, K), np.repeat(bt, K), np.repeat(btt, K)
        )
        if m.goal is not None:
            if m.goal[0] == "point":
                p = np.asarray(m.goal[1], float)
                self._add(np.arange(d), self.x(r, L) + pos, np.ones(d), p, p, GOAL, None, L, L)
            else:
                H, h = m.goal[1], m.goal[2]
                K = H.shape[0]
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
        Rs, Cs, Vs, lo, lits, tl = [], [], [], [], [], []
        row = 0
        for (i, j, t), k in sides.items():
            f = owner.pair_facets[(i, j)]
            a = f.A[k]
            d = len(a)
            pi = np.asarray(owner.models[i].pos)
            pj = np.asarray(owner.models[j].pos)
            idx = len(self.literals)
            self.literals.append(("side", i, j, t, k))
            for tt in (t, t + 1):
                Rs.append(np.full(2 * d, row))
                Cs.append(np.concatenate([self.x(i, tt) + pi, self.x(j, tt) + pj]))
                Vs.append(np.concatenate([a, -a]))
                lo.append(f.b[k])
                lits.append(idx)
                tl.append(t)
                row += 1
        self._block(
            np.concatenate(Rs),
            np.concatenate(Cs),
            np.concatenate(Vs),
            np.asarray(lo, float),
            np.full(row, INF),
            SIDE,
            np.asarray(lits),
            np.asarray(tl),
            np.asarray(tl) + 1,
        )

    def _mside(self, r: int, o: int, t: int, k: int) -> None:
        owner = self.owner
        f = owner.obstacle_facets[(r, o)]
        a, b = f.A[k], f.b[k]
        pos = np.asarray(owner.models[r].pos)
        ob = owner.problem.moving_obstacles[o]
        lit = ("mside", r, o, t, k)
        d = len(a)
        for lam in (0.0, *_bend_fractions(owner.problem, o, t), 1.0):
            c = ob.position(owner.problem.time_of(t + lam))
            rhs = b + float(a @ c)
            if lam == 0.0 or lam == 1.0:
                C = self.x(r, t + int(lam)) + pos
                self._add(np.zeros(d, dtype=int), C, a, np.array([rhs]), np.array([INF]), MOVE, lit, t, t + 1)
            else:
                C = np.concatenate([self.x(r, t) + pos, self.x(r, t + 1) + pos])
                V = np.concatenate([(1 - lam) * a, lam * a])
                self._add(np.zeros(2 * d, dtype=int), C, V, np.array([rhs]), np.array([INF]), MOVE, lit, t, t + 1)

    # bounds
    def col_bounds(self, *, start: bool = True) -> tuple[np.ndarray, np.ndarray]:
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
        lp = csc_lp(self.ncol, self.rows.n_row, R, C, V, cost, clo, chi, rlo, rhi)
        self.clock = clock
        self.h = new_highs(presolve="off")
        self.h.passModel(lp)
        return self._run()

    def _run(self) -> tuple[str, np.ndarray | None, np.ndarray | None]:
        left = self.clock.remaining()
        if left <= 0:
            raise BudgetExhausted("the joint CON-PLAN", "time")
        if not math.isinf(left):
            self.h.setOptionValue("time_limit", max(left, 0.01))
        self.h.run()
        self.owner.stats.lp_calls += 1
        st = self.h.getModelStatus()
        if st == highspy.HighsModelStatus.kOptimal:
            return "feasible", np.asarray(self.h.getSolution().col_value, float), None
        if st == highspy.HighsModelStatus.kTimeLimit:
            raise BudgetExhausted("the joint CON-PLAN", "time")
        if st in (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnboundedOrInfeasible):
            _, has_ray, ray = self.h.getDualRay()
            return "infeasible", None, np.asarray(ray, float) if has_ray else None
        raise LpFailure(f"HiGHS answered {self.h.modelStatusToString(st)} on a joint CON-PLAN LP")

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
        other rows alone are infeasible."""
        kind = np.concatenate(self.kind)
        soft = np.flatnonzero((kind == SIDE) | (kind == MOVE))
        R, C, V = self.coo
        n = self.ncol + len(soft)
        R2 = np.concatenate([R, soft])
        C2 = np.concatenate([C, self.ncol + np.arange(len(soft))])
        V2 = np.concatenate([V, np.ones(len(soft))])
        clo = np.concatenate([self.cb[0], np.zeros(len(soft))])
        chi = np.concatenate([self.cb[1], np.full(len(soft), INF)])
        cost = np.zeros(n)
        cost[self.ncol :] = 1.0
        lp = csc_lp(n, self.rows.n_row, R2, C2, V2, cost, clo, chi, *self.rb)
        h = new_highs(presolve="off")
        left = self.clock.remaining()
        if not math.isinf(left):
            h.setOptionValue("time_limit", max(left, 0.01))
        h.passModel(lp)
        h.run()
        self.owner.stats.lp_calls += 1
        if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
            return None
        return self.split(np.asarray(h.getSolution().col_value, float)[: self.ncol])

    # certificates
    def _certifies(self, y: np.ndarray, rb: tuple, cb: tuple) -> bool:
        """Does the ray ``y`` prove the LP with row bounds ``rb`` and column bounds ``cb``
        infeasible? (the interval test of the module docstring)"""
        R, C, V = self.coo
        rlo, rhi = rb
        clo, chi = cb
        d = np.bincount(C, weights=V * y[R], minlength=self.ncol)
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

    def _ray_support(self, ray: np.ndarray | None, rb: tuple, cb: tuple) -> np.ndarray | None:
        """The ray, its negligible entries dropped when it still certifies, or None
        when it does not certify."""
        if ray is None or len(ray) != self.rows.n_row:
            return None
        big = float(np.max(np.abs(ray))) if ray.size else 0.0
        if big == 0.0:
            return None
        y = np.where(np.abs(ray) <= 1e-9 * big, 0.0, ray)
        if self._certifies(y, rb, cb):
            return y
        return ray if self._certifies(ray, rb, cb) else None

    def conflict(self, ray: np.ndarray | None) -> TeamConflict:
        """The counterexample of the infeasible LP (see the module docstring): the
        literals and flags of the certificate's support, shrunk by a deletion filter
        (each literal, the goal rows and the start dropped in turn when the LP stays
        infeasible without them), and the final certificate checked."""
        kind = np.concatenate(self.kind)
        lit = np.concatenate(self.lit)
        t_lo, t_hi = np.concatenate(self.t_lo), np.concatenate(self.t_hi)
        y = self._ray_support(ray, self.rb, self.cb)
        if y is None:
            return self._trivial()
        groups: dict[tuple, list[int]] = {}
        for row in np.flatnonzero(lit >= 0):
            groups.setdefault(self.literals[lit[row]], []).append(int(row))
        goal_rows = np.flatnonzero(kind == GOAL)
        sup = np.flatnonzero(y)
        keep = {self.literals[i] for i in lit[sup] if i >= 0}
        use_goal = bool(np.any(kind[sup] == GOAL))
        # the LP with only the support's literals (and the goal rows when used)
        rlo, rhi = self.rb[0].copy(), self.rb[1].copy()
        free = [r for key, rows in groups.items() if key not in keep for r in rows]
        if not use_goal:
            free += goal_rows.tolist()
        rlo[free], rhi[free] = -INF, INF
        clo, chi = self.cb[0].copy(), self.cb[1].copy()
        order = sorted(keep, key=lambda k: (k[0] != "at", k))
        # a conflict of one or two literals is small already: only its anchors are tried
        candidates: list = (["goal"] if use_goal else []) + (order if len(keep) > 2 else []) + ["start"]
        if len(keep) <= MINIMIZE_MAX_LITERALS:
            self._set_bounds(rlo, rhi, clo, chi)
            for c in candidates:
                if (c == "goal" and not use_goal) or (c not in ("goal", "start") and c not in keep):
                    continue
                if c == "start":
                    cols = self.start_columns()
                    relaxed = self.col_bounds(start=False)
                    c2, h2 = clo.copy(), chi.copy()
                    c2[cols], h2[cols] = relaxed[0][cols], relaxed[1][cols]
                    if self._certifies(y, (rlo, rhi), (c2, h2)):
                        clo, chi = c2, h2
                        continue
                trial = (rlo.copy(), rhi.copy(), clo.copy(), chi.copy())
                rows = goal_rows if c == "goal" else None if c == "start" else np.asarray(groups[c])
                if rows is not None:
                    trial[0][rows], trial[1][rows] = -INF, INF
                else:
                    cols = self.start_columns()
                    relaxed = self.col_bounds(start=False)
                    trial[2][cols], trial[3][cols] = relaxed[0][cols], relaxed[1][cols]
                self._set_bounds(*trial)
                status, _, trial_ray = self._run()
                if status == "infeasible":
                    rlo, rhi, clo, chi = trial
                    if c == "goal":
                        use_goal = False
                    elif c != "start":
                        keep.discard(c)
                    y_new = self._ray_support(trial_ray, (rlo, rhi), (clo, chi))
                    if y_new is not None:  # what the new certificate does not use goes too
                        y = y_new
                        used = {self.literals[i] for i in lit[np.flatnonzero(y)] if i >= 0}
                        for gone in keep - used:
                            rows = np.asarray(groups[gone])
                            rlo[rows], rhi[rows] = -INF, INF
                        keep &= used
                        if use_goal and not np.any(kind[np.flatnonzero(y)] == GOAL):
                            rlo[goal_rows], rhi[goal_rows] = -INF, INF
                            use_goal = False
            self._set_bounds(rlo, rhi, clo, chi)
        final = self._ray_support(y, (rlo, rhi), (clo, chi))
        if final is None:  # the filtered LP's last ray did not check: keep the first certificate
            final = self._ray_support(ray, self.rb, self.cb)
            if final is None:
                return self._trivial()
            rlo, rhi = self.rb
            clo, chi = self.cb
        sup = np.flatnonzero(final)
        lits = {self.literals[i] for i in lit[sup] if i >= 0}
        start_cols = self.start_columns()
        relaxed = self.col_bounds(start=False)
        clo2, chi2 = clo.copy(), chi.copy()
        clo2[start_cols], chi2[start_cols] = relaxed[0][start_cols], relaxed[1][start_cols]
        return TeamConflict(
            tuple(lits),
            start=not self._certifies(final, (rlo, rhi), (clo2, chi2)),
            goal=bool(np.any(kind[sup] == GOAL)),
            timed=bool(np.any(kind[sup] == MOVE)),
            horizon=self.L,
            first_time=int(t_lo[sup].min()),
            last_time=int(t_hi[sup].max()),
        )

    def _set_bounds(self, rlo: np.ndarray, rhi: np.ndarray, clo: np.ndarray, chi: np.ndarray) -> None:
        n_row, n_col = len(rlo), len(clo)
        self.h.changeRowsBounds(n_row, np.arange(n_row, dtype=np.int32), rlo, rhi)
        self.h.changeColsBounds(n_col, np.arange(n_col, dtype=np.int32), clo, chi)

    def _trivial(self) -> TeamConflict:
        """No checked certificate: the whole plan of the component at this horizon."""
        return TeamConflict(
            tuple(set(self.literals)), start=True, goal=True, timed=True, horizon=self.L, certified=False
        )

"""The joint CON-PLAN: the LP of a team plan, its counterexamples, and the engagement of
pair steps (Shoukry et al., CDC 2016, Section V, for the robots; the SMC encoding of
separation, CDC 2017, Section IV, for the pairs). The LP of one component is
:mod:`plansynth.reach.team.component_lp`, the counterexample of an infeasible one
:mod:`plansynth.reach.team.counterexample`; this module is the checker that runs them.

**Components.** Robots that no engaged pair step links have independent LPs: the plan's
LP splits into one per component of the graph of engaged pairs, each solved on its own
(a singleton's LP is the single-robot CON-PLAN), and a counterexample names the robots
of its component only. Feasible component LPs are kept by their constraints, so that a
robot whose part of the plan did not change is not solved again.

**Engagement.** When every component is feasible, each pair step and robot-obstacle
step that DIS-PLAN did not decide is checked on the trajectories: if no side holds at
both samples (and at the obstacle's waypoint times), the step and its neighbours are
engaged (:class:`~plansynth.reach.team.plans.Engage`); otherwise the team's trajectory
is the answer (every step keeps a side: a plan of the full encoding).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from plansynth.budget import Clock
from plansynth.reach.highs import new_highs
from plansynth.reach.lazy.conflict import Feasible
from plansynth.reach.team.component_lp import ComponentLp
from plansynth.reach.team.component_lp import bend_fractions as _bend_fractions
from plansynth.reach.team.counterexample import component_conflict
from plansynth.reach.team.geometry import Facets
from plansynth.reach.team.plans import Engage, TeamConflict, TeamPlan
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.team.robust import RobotMargins
from plansynth.reach.trajectory import Trajectory

__all__ = ["RobotModel", "TeamConPlan", "ENGAGE_AROUND"]

#: steps engaged on each side of a step where a pair breaks the separation
ENGAGE_AROUND = 1
#: a side "holds" when its margin is at least -this times the workspace's size
HOLD_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class RobotModel:
    """What CON-PLAN needs of one robot: dynamics, start, bounds of its states (its own
    workspace, a sized robot's shrunk one) and inputs, its regions ``(H, h)``, its goal
    (``("shape", H, h)``, ``("point", p)`` or None) and whether it must end where it
    can stay (``rest``); ``margins``: under a disturbance, how much its state bounds,
    inputs, resting input and goal tighten at each step
    (:class:`~plansynth.reach.team.robust.RobotMargins`)."""

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
    margins: RobotMargins | None = None  # under a disturbance: the tube's, step by step

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
    robot-obstacle couple (absent: nothing forbidden); ``pair_margins``,
    ``obstacle_margins``: under disturbances, how far each side moves out at each sample
    (:mod:`plansynth.reach.team.robust`; every conflict is then learned at later
    placements only, :attr:`~plansynth.reach.team.plans.TeamConflict.later_only`).
    ``hints``: where the side each engaged step keeps best in the latest trajectories
    is written (DIS-PLAN's phases).
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
        pair_margins: dict[tuple[int, int], np.ndarray] | None = None,
        obstacle_margins: dict[tuple[int, int], np.ndarray] | None = None,
    ) -> None:
        self.problem = problem
        self.pair_margins = pair_margins or {}
        self.obstacle_margins = obstacle_margins or {}
        # under a tube the margins grow with time: a conflict holds at later placements only
        self.later_only = bool(self.pair_margins or self.obstacle_margins) or any(m.margins is not None for m in models)
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
        self._steps: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}
        self._mside_rows: dict[tuple, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = {}
        self._highs: dict[str, Any] = {}
        #: what the component LPs of a robot share at a horizon (:class:`~plansynth.reach.team.component_lp.RobotRows`)
        self.row_cache: dict[tuple, Any] = {}
        ws = problem.workspace
        self.scale = max(1.0, max(abs(v) for v in ws.lo + ws.hi))

    def highs(self, role: str) -> Any:
        """The HiGHS instance of ``role`` (``"component"``: the component LP and its
        elastic LP; ``"subset"``: the deletion filter's), made once and reused: each
        LP is passed whole (``passModel`` drops the previous model, basis and
        solution), so it is solved as by a new instance, without the cost of making one."""
        h = self._highs.get(role)
        if h is None:
            h = self._highs[role] = new_highs(presolve="off")
        return h

    def obstacle_step(self, o: int, t: int) -> tuple[np.ndarray, np.ndarray]:
        """Where moving obstacle o is checked in step t: the fractions of the step (0,
        each waypoint time inside it, 1) and its centre at each (kept: every LP with an
        engaged step of o at t asks again)."""
        hit = self._steps.get((o, t))
        if hit is None:
            lams = np.array((0.0, *_bend_fractions(self.problem, o, t), 1.0))
            ob = self.problem.moving_obstacles[o]
            centres = np.array([ob.position(self.problem.time_of(t + lam)) for lam in lams], float)
            hit = self._steps[(o, t)] = (lams, centres)
        return hit

    def mside_rows(self, r: int, o: int, t: int, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The rows of robot r keeping side k of moving obstacle o during step t
        (``A_k (p_r - c) >= b_k`` at each fraction of :meth:`obstacle_step`, p_r
        interpolated from its samples): rows from 0, columns counted from the robot's
        first column, values and lower bounds (kept)."""
        key = (r, o, t, k)
        hit = self._mside_rows.get(key)
        if hit is None:
            f = self.obstacle_facets[(r, o)]
            a, b = f.A[k], f.b[k]
            m = self.models[r]
            pos = np.asarray(m.pos)
            lams, centres = self.obstacle_step(o, t)
            q, d = len(lams), len(a)
            V = np.concatenate([np.outer(1 - lams, a), np.outer(lams, a)], axis=1).ravel()
            C = np.tile(np.concatenate([t * m.n + pos, (t + 1) * m.n + pos]), q)
            R = np.repeat(np.arange(q), 2 * d)
            nz = V != 0
            lo = b + centres @ a
            grow = self.obstacle_margins.get((r, o))
            if grow is not None:  # the robot's tube, interpolated between the step's samples
                lo = lo + (1 - lams) * grow[t, k] + lams * grow[t + 1, k]
            hit = self._mside_rows[key] = (R[nz], C[nz], V[nz], lo)
        return hit

    # -- the TheoryChecker interface ---------------------------------------------------
    def check(self, plan: TeamPlan) -> Feasible | tuple:
        out = self._check(plan)
        if self.later_only and isinstance(out, tuple):
            return tuple(replace(c, later_only=True) if isinstance(c, TeamConflict) else c for c in out)
        return out

    def _check(self, plan: TeamPlan) -> Feasible | tuple:
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
        lp = ComponentLp(self, plan, comp, dict(sides), dict(msides))
        t0 = time.perf_counter()
        try:
            status, x, ray = lp.solve(self.clock)
            if status == "feasible":
                out = lp.split(x)
                self._cache[key] = tuple(out[r] for r in comp)  # type: ignore[assignment]
                return out
            self.stats.infeasible += 1
            conflict = component_conflict(lp, ray)
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
                M = self._pair_margins(i, j, pos[i][t : t + 2] - pos[j][t : t + 2], first=t)
                self.hints[("side", i, j, t)] = int(np.minimum(M[0], M[1]).argmax())
        for r, o, t in plan.msides:
            if r in robots:
                S = self._obstacle_margins(pos[r][t : t + 2], o, self.obstacle_facets[(r, o)], 1, first=t, r=r)
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
        for i, j in self.pair_facets:
            M = self._pair_margins(i, j, pos[i] - pos[j])
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
            S = self._obstacle_margins(pos[r], o, f, L, r=r)
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

    def _pair_margins(self, i: int, j: int, Z: np.ndarray, first: int = 0) -> np.ndarray:
        """Per sample (rows of Z, the relative positions from step ``first``) and side of
        pair (i, j), ``a_k z - b_k`` less the side's growth under disturbances."""
        M = self.pair_facets[(i, j)].margins(Z)
        grow = self.pair_margins.get((i, j))
        return M if grow is None else M - grow[first : first + len(Z)]

    def _obstacle_margins(
        self, P: np.ndarray, o: int, f: Facets, L: int, first: int = 0, r: int | None = None
    ) -> np.ndarray:
        """Per step and side, the worst margin over the step's samples and the
        obstacle's waypoint times inside it (``P[0]`` is the position at step ``first``;
        ``r``: the robot, whose tube's growth of the sides counts under disturbances)."""
        grow = None if r is None else self.obstacle_margins.get((r, o))
        out = np.empty((L, f.n_sides))
        for t in range(L):
            lams, centres = self.obstacle_step(o, first + t)
            p = (1 - lams)[:, None] * P[t] + lams[:, None] * P[t + 1]
            M = f.margins(p - centres)
            if grow is not None:
                M = M - ((1 - lams)[:, None] * grow[first + t] + lams[:, None] * grow[first + t + 1])
            out[t] = M.min(axis=0)
        return out


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

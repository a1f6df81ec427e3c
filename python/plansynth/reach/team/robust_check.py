"""The independent worst-case check of a team plan under disturbances, and what
:func:`plansynth.reach.solve` records with a robust team answer.

It knows the problem (each robot's W, the separation's zones, the moving obstacles)
and the plan (each robot's nominal states and inputs, and its gain K), and nothing of
the team planners: not their tightened team (:mod:`plansynth.reach.team.robust`), not the
tube of :mod:`plansynth.reach.tube`, not the facets of :mod:`plansynth.reach.team.geometry`.
Its primitives are the single-robot robust validator's (:mod:`plansynth.reach.robust.check`
and :mod:`plansynth.reach.robust.error_sets`, independent of the planner) and the
separation's definition (:mod:`plansynth.reach.team.separation`).

**Each robot** r with a disturbance: the single-robot worst case on its own problem
(:func:`~plansynth.reach.robust.check.check_robust`: inputs, state bounds, workspace,
goal, static obstacles at every sample and along every segment, with its error sets
E_{r,t} = sum_{i<t} A_K^i W_r computed exactly). A robot without one has no error.

**Every pair** i, j: the disturbances of the robots are independent, so the relative
position at step t ranges exactly over ``z_t + E_{i,t} + (-E_{j,t})`` (position parts,
``z_t = p_i - p_j`` nominal): the exact convex polygons of both error sets
(:func:`~plansynth.reach.robust.error_sets.tube_polygons`) summed by their vertices. A
``separation`` violation at step t: that polygon meets the pair's zone (the interior of
``d P + K_i + (-K_j)``, a disc's radius as a distance) deeper than tol; reached by some
pair of disturbance sequences. Along a step the relative motion of two disturbed
samples is a straight segment, inside the convex hull of both steps' polygons: checked
against the zone (sufficient, not necessary, as the single robot's segment check).

**Every robot and moving obstacle**: ``p_t + E_{r,t} - c(t)`` at each sample against the
obstacle's zone; along a step split at the obstacle's waypoint times, each piece [a, b]
inside the hull of ``Z_a`` and ``Z_b`` with ``Z_s = (1 - s) X + s Y - c(s)`` (X, Y the
step's two disturbed-position polygons, Minkowski sum: with both samples' errors fixed,
the relative motion is a straight segment on the piece, from a point of Z_a to one of
Z_b).

Violations name the robots (or the robot and the obstacle) and the step.

>>> from plansynth.reach import solve
>>> from plansynth.reach.team.families import windy_swap
>>> r = solve(windy_swap())
>>> r.status.value, r.robust["check"]["ok"], sorted(r.robust["robots"])
('found', True, ['A', 'B'])
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import shapely

from plansynth.reach.geometry import convex_hull
from plansynth.reach.result import ReachStatus
from plansynth.reach.robust.check import RobustReport, check_robust, tube_polygons
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import Violation

__all__ = ["check_robust_team", "team_gains", "annotated_team", "checked_team"]


def team_gains(problem: TeamProblem, robust: dict[str, Any] | None) -> list[np.ndarray | None]:
    """Each robot's gain K: the one a result records (``robust.robots[name].feedback.gain``),
    else its problem's design (None for a robot without a disturbance)."""
    from plansynth.reach.robust.tighten import robust_design

    recorded = (robust or {}).get("robots") or {}
    out: list[np.ndarray | None] = []
    for r, robot in enumerate(problem.robots):
        if robot.disturbance is None:
            out.append(None)
        elif robot.name in recorded:
            out.append(np.atleast_2d(np.asarray(recorded[robot.name]["feedback"]["gain"], float)))
        else:
            out.append(robust_design(problem.robot_problems[r]).K)
    return out


class _Team:
    """Violations, counts, slack and the smallest clearance, merged over the robots."""

    def __init__(self) -> None:
        self.violations: list[Violation] = []
        self.counts: dict[str, int] = {}
        self.slack: dict[str, float] = {}
        self.clearance = math.inf

    def add(self, kind: str, step: int | None, detail: str) -> None:
        self.counts[kind] = self.counts.get(kind, 0) + 1
        if self.counts[kind] <= 20:
            self.violations.append(Violation(kind, step, detail))

    def robot(self, name: str, rep: RobustReport) -> None:
        for v in rep.violations:
            self.violations.append(replace(v, detail=f"robot {name}: {v.detail}"))
        for k, c in rep.counts.items():
            self.counts[k] = self.counts.get(k, 0) + c
        for k, v in rep.slack.items():
            self.slack[k] = min(self.slack.get(k, math.inf), v)
        self.clearance = min(self.clearance, rep.clearance)


def _sum(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """The vertices (a superset) of the Minkowski sum of two convex point sets."""
    return (P[:, None, :] + Q[None, :, :]).reshape(-1, P.shape[1])


class _ZoneTest:
    """A zone (:class:`~plansynth.reach.team.separation.Zone`) against convex sets: a set
    enters it when it meets the polygon's interior shrunk by tol, or comes closer than the
    radius less tol; ``room`` is how far a set stays out (negative: inside)."""

    def __init__(self, zone: Any, tol: float) -> None:
        self.poly = zone.polygon()
        self.radius = float(zone.radius)
        self.tol = tol
        self.inner = self.poly.buffer(-tol, join_style="mitre") if tol > 0 and not self.poly.is_empty else self.poly

    def room(self, g: shapely.Geometry) -> float:
        if self.poly.is_empty:
            return math.inf
        return float(shapely.distance(self.poly, g)) - self.radius

    def enters(self, g: shapely.Geometry) -> bool:
        if self.poly.is_empty:
            return False
        if self.radius > 0.0 and float(shapely.distance(self.poly, g)) < self.radius - self.tol:
            return True
        return not self.inner.is_empty and bool(shapely.relate_pattern(self.inner, g, "T********"))


def check_robust_team(
    problem: TeamProblem,
    trajectories: Sequence[Trajectory],
    gains: Sequence[np.ndarray | None],
    *,
    tol: float = 1e-6,
) -> RobustReport:
    """The worst case of every robot's closed loop and of every pair and robot-obstacle
    couple, at every step (module doc); a :class:`~plansynth.reach.robust.check.RobustReport`
    whose ``clearance`` is the smallest room any worst case leaves (static obstacles,
    separations, moving obstacles)."""
    names = [r.name for r in problem.robots]
    N = trajectories[0].horizon
    rep = _Team()
    polys: list[list[np.ndarray]] = []
    pos: list[np.ndarray] = []
    for r, (robot, traj) in enumerate(zip(problem.robots, trajectories)):
        own = problem.robot_problems[r]
        pos.append(own.position_of(np.asarray(traj.states, float)))
        K = gains[r]
        if robot.disturbance is None or K is None:
            polys.append([np.zeros((1, 2))] * (N + 1))
            continue
        rep.robot(robot.name, check_robust(own, traj, K, tol=tol))
        polys.append(tube_polygons(own, K, N))
    for i in range(problem.n_robots):
        for j in range(i):
            if problem.robots[i].disturbance is None and problem.robots[j].disturbance is None:
                continue  # (no error: the team validator's exact separation)
            test = _ZoneTest(problem.pair_zone(i, j), tol)
            sets = [_sum(pos[i][t] - pos[j][t] + polys[i][t], -polys[j][t]) for t in range(N + 1)]
            _against(test, sets, f"robots {names[j]} and {names[i]}", "the separation", rep)
    for k in range(len(problem.moving_obstacles)):
        for i in range(problem.n_robots):
            if problem.robots[i].disturbance is None:
                continue
            _moving(problem, i, k, pos[i], polys[i], _ZoneTest(problem.obstacle_zone(i, k), tol), rep)
    return RobustReport(
        ok=not rep.counts,
        violations=tuple(rep.violations),
        counts=dict(rep.counts),
        horizon=N,
        clearance=rep.clearance,
        slack=dict(rep.slack),
        tol=tol,
    )


def _against(test: _ZoneTest, sets: list[np.ndarray], who: str, what: str, rep: _Team) -> None:
    """The relative sets at every sample, and the hull of each step's two, against a zone."""
    hit = set()
    for t, S in enumerate(sets):
        g = convex_hull(S)
        rep.clearance = min(rep.clearance, test.room(g))
        if test.enters(g):
            hit.add(t)
            rep.add("separation", t, f"{who} can come closer than {what} at step {t} under some disturbances")
    for t in range(len(sets) - 1):
        if t in hit or t + 1 in hit:
            continue
        g = convex_hull(np.vstack([sets[t], sets[t + 1]]))
        rep.clearance = min(rep.clearance, test.room(g))
        if test.enters(g):
            rep.add(
                "separation",
                t,
                f"{who}: the hull of the worst cases along the segment from step {t} to {t + 1} meets {what}",
            )


def _moving(
    problem: TeamProblem, i: int, k: int, P: np.ndarray, E: list[np.ndarray], test: _ZoneTest, rep: _Team
) -> None:
    """Robot i's disturbed positions against moving obstacle k (module doc)."""
    o = problem.moving_obstacles[k]
    name = problem.robots[i].name
    dt = problem.dt if problem.dt is not None else 1.0
    N = len(P) - 1
    for t in range(N + 1):
        X = P[t] + E[t]
        g = convex_hull(X - o.position(t * dt))
        rep.clearance = min(rep.clearance, test.room(g))
        if test.enters(g):
            rep.add("moving-obstacle", t, f"robot {name} can come within the separation of {o.name} at step {t}")
            continue
        if t == N:
            continue
        Y = P[t + 1] + E[t + 1]
        cuts = [0.0] + [(b - t * dt) / dt for b in o.times if t * dt < b < (t + 1) * dt] + [1.0]
        for a, b in zip(cuts, cuts[1:]):
            Za = _sum((1 - a) * X, a * Y) - o.position((t + a) * dt)
            Zb = _sum((1 - b) * X, b * Y) - o.position((t + b) * dt)
            g = convex_hull(np.vstack([Za, Zb]))
            if test.enters(g):
                rep.add(
                    "moving-obstacle",
                    t,
                    f"robot {name}: the hull of the worst cases along the segment from step {t} to {t + 1} meets "
                    f"the separation of {o.name}",
                )
                break


# ----------------------------------------------------------------- with solve()


def annotated_team(problem: TeamProblem, result: Any) -> Any:
    """A team planner's answer with the tightened team's record (gains, margins, what it
    guarantees) and its claims worded relative to the designs."""
    from plansynth.reach.team.robust import record, tightened_team

    tight = tightened_team(problem)
    message = result.message
    if tight.note:
        message = f"{message}; {tight.note}" if message else tight.note
    if result.status is not ReachStatus.FOUND and tight.status is None:
        rel = record(problem, tight)["relative_to"]
        message = f"{message}; {rel}" if message else rel
    return replace(result, robust=record(problem, tight), message=message)


def checked_team(problem: TeamProblem, result: Any, *, tol: float = 1e-6) -> Any:
    """The worst-case check of a ``found`` team answer that passed the team validator; a
    plan that fails it is not reported as found."""
    if result.status is not ReachStatus.FOUND or result.trajectories is None or result.robust is None:
        return result
    from plansynth.reach.robust.planning import with_check

    t0 = time.perf_counter()
    report = check_robust_team(problem, result.trajectories, team_gains(problem, result.robust), tol=tol)
    return with_check(result, report, time.perf_counter() - t0, "the robust team check")

"""The independent team validator: every robot as the reach-avoid validator checks it, and
the separation between every two robots and from every moving obstacle, at every sample
and along every segment, exactly.

It knows the problem and the trajectories, nothing of the planners: no regions, no
sides, no facets. Each robot's trajectory goes through
:func:`plansynth.reach.validate.validate` on the robot's own problem (dynamics, start,
inputs, state bounds, workspace, static obstacles with the robot's size, segments), with
the goal checked here when it is a point (the final position within tol of it) and the
mission by :func:`plansynth.reach.mission.check.check_mission`; ``stop`` asks that some
admissible input keeps the last state where it is (:func:`~plansynth.reach.mission.check.can_rest`).

**Separation, exactly.** Between two samples both robots move along straight segments
over the same time interval, so their relative position ``z = p_i - p_j`` moves along a
straight segment too; a moving obstacle's reference point moves linearly between its
waypoints, so ``p_i - c(t)`` is piecewise linear, with a bend at each waypoint time
inside the step: each piece is checked on its own. A (piece of a) segment violates the
separation when it enters the zone of the pair (:mod:`plansynth.reach.team.separation`,
the exact Minkowski sum of the norm's ball and the two shapes; discs exactly, by their
Euclidean distance) deeper than ``tol``. Each violation names the robots (or the robot
and the obstacle) and the step.

>>> from plansynth.reach.team.families import corridor_swap
>>> from plansynth.reach.trajectory import Trajectory
>>> p = corridor_swap()
>>> a = Trajectory([[0.5, 0.5, 0, 0], [0.625, 0.5, 0.5, 0]], [[1, 0]])
>>> b = Trajectory([[9.5, 0.5, 0, 0], [9.375, 0.5, -0.5, 0]], [[-1, 0]])
>>> r = validate_team(p, [a, b], require_goals=False)
>>> r.ok, [v.kind for v in r.violations]
(True, [])
>>> crossing = [Trajectory([[0.5, 0.5, 0, 0], [9.5, 0.5, 18, 0]], [[36, 0]]),
...             Trajectory([[9.5, 0.5, 0, 0], [0.5, 0.5, -18, 0]], [[-36, 0]])]
>>> [str(v) for v in validate_team(p, crossing, require_goals=False, check_robots=False).violations]
['separation at step 0: robots A and B come closer than the separation along the segment from step 0 to 1 (by 0.7)']
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from plansynth.reach.team.problem import GoalPoint, TeamProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import ValidationReport, Violation, component_tolerance, validate

__all__ = ["TeamValidationReport", "validate_team", "TEAM_VIOLATION_KINDS"]

#: The kinds this validator adds to the reach-avoid validator's
TEAM_VIOLATION_KINDS = ("robots", "separation", "moving-obstacle", "stop", "mission")


@dataclass(frozen=True)
class TeamValidationReport:
    """The team validator's verdict: ``ok`` (every robot valid and every separation kept,
    at samples and along segments), the violations (robots' ones prefixed with their
    name), each robot's own report, and the smallest margin seen."""

    ok: bool
    segment_safe: bool
    violations: tuple[Violation, ...]
    robots: tuple[ValidationReport | None, ...]
    horizon: int
    tol: float
    counts: dict[str, int] = field(default_factory=dict)
    missions: tuple[dict | None, ...] = ()

    def __bool__(self) -> bool:
        raise TypeError("a TeamValidationReport has no truth value; read .ok")

    def summary(self) -> str:
        verdict = "valid" if self.ok else "INVALID"
        counts = ", ".join(f"{k} x{n}" for k, n in self.counts.items())
        return f"{verdict}, {len(self.robots)} robots, horizon {self.horizon}" + (
            f"; violations: {counts}" if counts else ""
        )

    def to_json_dict(self) -> dict:
        return {
            "ok": self.ok,
            "segment_safe": self.segment_safe,
            "horizon": self.horizon,
            "tol": self.tol,
            "counts": dict(self.counts),
            "violations": [{"kind": v.kind, "step": v.step, "detail": v.detail} for v in self.violations[:200]],
            "robots": [None if r is None else r.to_json_dict() for r in self.robots],
            "missions": [m for m in self.missions],
        }


def validate_team(
    problem: TeamProblem,
    trajectories: Sequence[Trajectory],
    *,
    tol: float = 1e-6,
    require_segment_safe: bool = True,
    require_goals: bool = True,
    check_robots: bool = True,
    dynamics: str = "exact",
) -> TeamValidationReport:
    """Check the team's trajectories (one per robot, in the problem's order).
    ``require_segment_safe``: each robot's segments must avoid the static obstacles (the
    separation is checked along segments whatever this says); ``require_goals`` False
    skips the goals and missions (a partial plan); ``check_robots`` False checks the
    separation only; ``dynamics="curve"``: the robots' runs need not satisfy
    ``x' = A x + B u`` (disturbed closed loops, :mod:`plansynth.reach.team.robust_simulate`)
    nor end at rest."""
    names = [r.name for r in problem.robots]
    violations: list[Violation] = []
    if len(trajectories) != problem.n_robots:
        v = Violation("robots", None, f"{len(trajectories)} trajectories for {problem.n_robots} robots")
        return _report(problem, (v,), (), 0, tol, False, ())
    horizons = {t.horizon for t in trajectories}
    if len(horizons) != 1:
        v = Violation("robots", None, f"the robots' trajectories have different horizons: {sorted(horizons)}")
        return _report(problem, (v,), (), 0, tol, False, ())
    N = horizons.pop()
    reports: list[ValidationReport | None] = []
    missions: list[dict | None] = []
    segment_safe = True
    for r, traj in enumerate(trajectories):
        if not check_robots:
            reports.append(None)
            missions.append(None)
            continue
        rep, extra, mission = _robot(problem, r, traj, tol, require_segment_safe, require_goals, dynamics)
        reports.append(rep)
        missions.append(mission)
        segment_safe = segment_safe and rep.segment_safe
        violations += [replace(v, detail=f"robot {names[r]}: {v.detail}") for v in rep.violations] + extra
        if rep.violations and rep.violations[0].kind == "shape":
            return _report(problem, tuple(violations), tuple(reports), N, tol, False, tuple(missions))
    pos = [problem.robot_problems[r].position_of(t.states) for r, t in enumerate(trajectories)]
    for i in range(problem.n_robots):
        for j in range(i):
            zone = problem.pair_zone(i, j)
            Z = pos[i] - pos[j]
            violations += _along(zone, Z, Z, f"robots {names[j]} and {names[i]}", problem.separation.distance, tol)
    for k in range(len(problem.moving_obstacles)):
        for i in range(problem.n_robots):
            violations += _obstacle(problem, i, k, pos[i], names[i], tol)
    sep_segments = not any(v.kind in ("separation", "moving-obstacle") and "segment" in v.detail for v in violations)
    ok = not violations
    return _report(
        problem, tuple(violations), tuple(reports), N, tol, segment_safe and sep_segments and ok, tuple(missions), ok
    )


def _report(
    problem: TeamProblem,
    violations: tuple[Violation, ...],
    reports: tuple,
    N: int,
    tol: float,
    segment_safe: bool,
    missions: tuple,
    ok: bool | None = None,
) -> TeamValidationReport:
    counts: dict[str, int] = {}
    for v in violations:
        counts[v.kind] = counts.get(v.kind, 0) + 1
    return TeamValidationReport(
        ok=not violations if ok is None else ok,
        segment_safe=segment_safe,
        violations=violations,
        robots=reports,
        horizon=N,
        tol=tol,
        counts=counts,
        missions=missions,
    )


def _robot(
    problem: TeamProblem, r: int, traj: Trajectory, tol: float, segments: bool, goals: bool, dynamics: str = "exact"
) -> tuple[ValidationReport, list[Violation], dict | None]:
    """Robot r on its own problem; the point goal, stop and mission checked here."""
    robot = problem.robots[r]
    own = problem.robot_problems[r]
    checked = own if (goals and robot.goal is not None and not isinstance(robot.goal, GoalPoint)) else None
    if checked is None:
        checked = replace(own, goal=own.workspace, labels=(), mission=None)
    elif robot.mission is not None:
        checked = replace(own, labels=(), mission=None)
    rep = validate(checked, traj, require_segment_safe=segments, tol=tol, dynamics=dynamics)
    extra: list[Violation] = []
    if rep.violations and rep.violations[0].kind == "shape":
        return rep, extra, None
    last = own.position_of(traj.states[-1])
    if goals and isinstance(robot.goal, GoalPoint):
        g = np.asarray(robot.goal.point, float)
        if np.any(np.abs(last - g) > component_tolerance(g, tol)):
            extra.append(
                Violation("goal", traj.horizon, f"robot {robot.name}: ends at {_fmt(last)}, not at its goal {_fmt(g)}")
            )
    if dynamics == "exact" and (robot.stop or (goals and robot.mission is not None)):
        from plansynth.reach.mission.check import can_rest

        if not can_rest(own, traj.states[-1], tol):
            extra.append(
                Violation(
                    "stop",
                    traj.horizon,
                    f"robot {robot.name}: no admissible input keeps its last state {_fmt(traj.states[-1])} where it is",
                )
            )
    mission = None
    if goals and robot.mission is not None:
        from plansynth.reach.mission.check import check_mission

        report = check_mission(own, traj, None, tol=tol)
        mission = report.to_json_dict()
        if not report.ok:
            extra.append(Violation("mission", report.step, f"robot {robot.name}: {report.reason}"))
    return rep, extra, mission


def _along(zone: Any, Z0: np.ndarray, Z1: np.ndarray, who: str, distance: float, tol: float) -> list[Violation]:
    """Separation at every sample (rows of Z0) and along every segment (Z0[t] -> Z0[t+1])."""
    out = []
    at_samples = zone.intrusions(Z0, Z0)
    bad = set()
    for t in np.flatnonzero(at_samples > tol):
        bad.add(int(t))
        out.append(
            Violation(
                "separation", int(t), f"{who} are closer than the separation {distance:g} (by {at_samples[t]:.3g})"
            )
        )
    if len(Z0) > 1:
        along = zone.intrusions(Z0[:-1], Z0[1:])
        for t in np.flatnonzero(along > tol):
            if int(t) in bad or int(t) + 1 in bad:
                continue
            out.append(
                Violation(
                    "separation",
                    int(t),
                    f"{who} come closer than the separation along the segment from step {t} to {t + 1} "
                    f"(by {along[t]:.3g})",
                )
            )
    return out


def _obstacle(problem: TeamProblem, i: int, k: int, P: np.ndarray, name: str, tol: float) -> list[Violation]:
    """Robot i against moving obstacle k: at every sample, and along every step split at
    the obstacle's waypoint times (its own interpolation of the waypoints)."""
    o = problem.moving_obstacles[k]
    zone = problem.obstacle_zone(i, k)
    dt = problem.dt if problem.dt is not None else 1.0
    times = np.asarray(o.times, float)
    W = np.asarray(o.positions, float)

    def centre(tau: float) -> np.ndarray:
        return np.array([np.interp(tau, times, W[:, a]) for a in range(W.shape[1])])

    out = []
    N = len(P) - 1
    for t in range(N + 1):
        z = P[t] - centre(t * dt)
        depth = zone.intrusion(z, z)
        if depth > tol:
            out.append(
                Violation("moving-obstacle", t, f"robot {name} is within the separation of {o.name} (by {depth:.3g})")
            )
            continue
        if t == N:
            continue
        cuts = [0.0] + [(b - t * dt) / dt for b in times if t * dt < b < (t + 1) * dt] + [1.0]
        for a, b in zip(cuts, cuts[1:]):
            za = (1 - a) * P[t] + a * P[t + 1] - centre((t + a) * dt)
            zb = (1 - b) * P[t] + b * P[t + 1] - centre((t + b) * dt)
            depth = zone.intrusion(za, zb)
            if depth > tol:
                out.append(
                    Violation(
                        "moving-obstacle",
                        t,
                        f"robot {name} comes within the separation of {o.name} along the segment from step {t} "
                        f"to {t + 1} (by {depth:.3g})",
                    )
                )
                break
    return out


def _fmt(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:g}" for x in np.asarray(v).ravel()) + ")"

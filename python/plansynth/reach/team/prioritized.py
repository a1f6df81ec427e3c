"""Prioritized planning (the baseline ``prioritized``; Erdmann and Lozano-Perez, "On
multiple moving objects", Algorithmica 1987): the robots in a fixed order, each planned
alone among the earlier robots' trajectories as moving obstacles.

Robot k is planned by the joint lazy planner on the team of robot k alone
(:func:`~plansynth.reach.team.lazy.plan_team_lazy`, one horizon at a time), the
problem's moving obstacles and every earlier robot as a moving obstacle: its shape (a
disc as its circumscribed 16-gon) moving through its samples, keeping the team's
separation. Each robot must end where it can stay (``stop``), and no earlier than the
robots before it, so that once planned it waits where it ended while the later ones
move; the earlier trajectories are then held at their last state up to the final
horizon.

Fast, and incomplete: an early robot's plan may block a later one (two robots swapping
the ends of a corridor with a bay near the first one's end: the first goes straight
through, the second cannot reach the bay in time). Its failure is therefore
``unknown``, never ``infeasible``.
"""

from __future__ import annotations

import time
from dataclasses import asdict, replace
from typing import Any

import numpy as np

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.reach.geometry import Box, Polygon, Shape
from plansynth.reach.result import ReachStatus
from plansynth.reach.robot import disc_polygon
from plansynth.reach.team.lazy import plan_team_lazy
from plansynth.reach.team.options import PrioritizedOptions, TeamLazyOptions
from plansynth.reach.team.problem import MovingObstacle, TeamProblem, TeamRobot
from plansynth.reach.team.result import TeamResult
from plansynth.reach.team.robust import is_disturbed
from plansynth.reach.team.setup import TeamSetup, prepare
from plansynth.reach.trajectory import Trajectory

__all__ = ["plan_prioritized", "run", "held"]


def run(problem: Any, budget: Budget, options: PrioritizedOptions, progress: Any = None) -> TeamResult:
    """The registry's entry (:data:`plansynth.reach.planners.PLANNERS`)."""
    return plan_prioritized(problem, budget, options, progress)


def _extent(robot: TeamRobot, d: int) -> Shape:
    """A robot's extent as a moving obstacle's shape around its reference point."""
    rs = robot.robot_shape
    if rs is not None and not rs.is_point and rs.radius is not None:
        return Polygon(tuple((float(x), float(y)) for x, y in disc_polygon(rs.radius)))
    h = np.zeros(d) if rs is None or rs.is_point else np.asarray(rs.margins(d), float)
    return Box(tuple(-h), tuple(h))


def held(robot: TeamRobot, traj: Trajectory, horizon: int) -> Trajectory:
    """``traj`` held at its last state up to ``horizon`` (the input that keeps it there:
    ``B w = x - A x``, least squares, the mission checker's ``can_rest`` reading)."""
    extra = horizon - traj.horizon
    if extra <= 0:
        return traj
    A, B = np.asarray(robot.dynamics.A, float), np.asarray(robot.dynamics.B, float)
    x = traj.states[-1]
    w = np.linalg.lstsq(B, x - A @ x, rcond=None)[0]
    X = np.vstack([traj.states] + [x[None, :]] * extra)
    U = np.vstack([traj.inputs.reshape(-1, B.shape[1])] + [w[None, :]] * extra)
    return Trajectory(states=X, inputs=U)


def _parked_hit(problem: TeamProblem, r: int, traj: Trajectory, since: int) -> str | None:
    """The moving obstacle (of the problem) that robot r, held at its last state from step
    ``since``, fails to keep a side from during some step, or None."""
    from plansynth.reach.team.conplan import _bend_fractions
    from plansynth.reach.team.geometry import obstacle_facets

    P = problem.robot_problems[r].position_of(traj.states)
    for o, ob in enumerate(problem.moving_obstacles):
        f = obstacle_facets(problem, r, o)
        if f is None:
            continue
        for t in range(since, traj.horizon):
            worst = np.full(f.n_sides, np.inf)
            for lam in (0.0, *_bend_fractions(problem, o, t), 1.0):
                c = ob.position(problem.time_of(t + lam))
                worst = np.minimum(worst, f.margins((1 - lam) * P[t] + lam * P[t + 1] - c))
            if worst.max() < -1e-9:
                return ob.name
    return None


def plan_prioritized(
    problem: TeamProblem,
    budget: Budget = Budget(),
    options: PrioritizedOptions | None = None,
    progress: Any = None,
    *,
    setup: TeamSetup | None = None,
) -> TeamResult:
    """Plan the robots one after the other (see the module docstring); unvalidated.
    ``setup``: the problem's :func:`~plansynth.reach.team.setup.prepare` for this
    ``max_horizon``, when the caller has it (the seeded lazy planner shares it)."""
    if is_disturbed(problem):
        raise InvalidOption(
            "prioritized",
            "planner",
            "plans no disturbance (robots[i].disturbance); a team under disturbances is planned by lazy-smt-team "
            "and milp-team",
        )
    if problem.n_robots > 1 and problem.dt is None:
        raise InvalidOption(
            "prioritized", "planner", "the earlier robots become moving obstacles: the dynamics need a dt"
        )
    options = PrioritizedOptions() if options is None else options
    clock = budget.clock()
    t_start = time.perf_counter()
    L_max = problem.max_horizon if options.max_horizon is None else options.max_horizon
    counters: dict[str, Any] = {"robots": problem.n_robots, "iterations": 0, "lp_calls": 0, "sat_calls": 0}
    timings: dict[str, float] = {}
    record = {**asdict(options), "max_horizon": L_max, "budget_seconds": budget.seconds}
    names = tuple(r.name for r in problem.robots)

    def result(status: ReachStatus, horizon: int | None, message: str, trajs=None, regions=None) -> TeamResult:  # noqa: ANN001
        timings["total"] = time.perf_counter() - t_start
        return TeamResult(
            status, "prioritized", timings["total"], trajs, regions, horizon, counters, timings, record,
            message=message, guarantee="segments", names=names,
        )  # fmt: skip

    if setup is None or not setup.serves(problem, L_max):
        setup = prepare(problem, L_max, clock)
    bounds = setup.robots
    trajs: list[Trajectory] = []
    regions: list[tuple[int, ...]] = []
    horizon = 0
    for k, robot in enumerate(problem.robots):
        if clock.out_of_time():
            return result(ReachStatus.UNKNOWN, horizon, f"budget ran out before robot {robot.name}")
        dt = problem.dt if problem.dt is not None else 1.0
        earlier = tuple(
            MovingObstacle(
                _extent(problem.robots[j], problem.dim),
                tuple(t * dt for t in range(trajs[j].horizon + 1)),
                tuple(tuple(float(v) for v in p) for p in problem.robot_problems[j].position_of(trajs[j].states)),
                name=problem.robots[j].name,
            )
            for j in range(k)
        )
        alone = TeamProblem(
            workspace=problem.workspace,
            obstacles=problem.obstacles,
            robots=(replace(robot, stop=True),),
            separation=problem.separation,
            moving_obstacles=problem.moving_obstacles + earlier,
            labels=problem.labels,
            max_horizon=L_max,
            name=f"{problem.name}/{robot.name}",
            source=problem.source,
        )
        first = max(horizon, int(min(bounds[k].bound, L_max + 1)))
        out = plan_team_lazy(
            alone, clock.left(), TeamLazyOptions(max_horizon=L_max, horizon_search="linear"), progress,
            horizons=range(first, L_max + 1),
        )  # fmt: skip
        for key in ("iterations", "lp_calls", "sat_calls"):
            counters[key] += int(out.counters.get(key) or 0)
        if out.status is not ReachStatus.FOUND:
            why = "the budget ran out" if out.status is ReachStatus.UNKNOWN else f"no plan up to horizon {L_max}"
            counters["failed_robot"] = robot.name
            return result(
                ReachStatus.UNKNOWN,
                out.horizon,
                f"robot {robot.name} (number {k + 1} in the order) found no plan among the earlier robots' "
                f"trajectories ({why}); prioritized planning is incomplete: not a proof",
            )
        horizon = out.horizon
        trajs.append(out.trajectories[0])
        regions.append(out.regions[0])
    final = tuple(held(problem.robots[r], t, horizon) for r, t in enumerate(trajs))
    for r, t in enumerate(trajs):
        hit = _parked_hit(problem, r, final[r], t.horizon)
        if hit is not None:
            counters["failed_robot"] = problem.robots[r].name
            return result(
                ReachStatus.UNKNOWN,
                horizon,
                f"robot {problem.robots[r].name}, waiting at its goal from step {t.horizon}, is in the way of "
                f"moving obstacle {hit} before the last robot arrives; prioritized planning is incomplete: not a proof",
            )
    regs = tuple(tuple(reg) + (reg[-1],) * (horizon - len(reg) + 1) for reg in regions)
    counters["minimal"] = False
    return result(ReachStatus.FOUND, horizon, f"found at horizon {horizon} (robots in the order given)", final, regs)

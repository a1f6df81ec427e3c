"""What every team planner computes first, per robot and per pair, from the single-robot
pieces: each robot's planning problem (its configuration space, and for a mission the
whole workspace as goal), its decomposition (:func:`~plansynth.reach.abstraction.abstract`,
refined by the labels for a mission, :func:`~plansynth.reach.mission.labels.label_abstraction`),
its region graph, its time windows and horizon bound
(:func:`~plansynth.reach.lazy.bounds.time_windows`), the LP data of the joint CON-PLAN
(:class:`~plansynth.reach.team.conplan.RobotModel`), and the sides of every pair and
robot-obstacle couple (:mod:`plansynth.reach.team.geometry`).

A joint plan is a plan of every robot's own problem, so each robot's bounds hold for
the team: the joint horizon is at least the largest of them.

Under disturbances (:mod:`plansynth.reach.team.robust`) a disturbed robot's planning
problem is its own problem tightened by the single-robot code (grown obstacles, the tube
attached), its model carries the tube's step-wise margins, and every pair and
robot-obstacle couple involving it the margins of its sides.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from plansynth.budget import Budget, Clock
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.geometry import Box, halfspaces
from plansynth.reach.lazy.bounds import time_windows
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.lazy.guide import reference_plan, route
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robot import configuration_space
from plansynth.reach.team.conplan import RobotModel
from plansynth.reach.team.geometry import Facets, obstacle_facets, pair_facets
from plansynth.reach.team.problem import GoalPoint, TeamProblem
from plansynth.reach.team.robust import obstacle_margins, pair_margins, robot_margins, tightened_team

__all__ = ["RobotSetup", "TeamSetup", "prepare"]


@dataclass(eq=False)
class RobotSetup:
    """One robot's planning data (see the module docstring)."""

    planning: ReachProblem
    abstraction: Abstraction
    graph: RegionGraph
    model: RobotModel
    earliest: tuple[float, ...]
    to_go: tuple[float, ...]
    bound: float
    labels_of: tuple[frozenset[str], ...] | None = None


@dataclass(eq=False)
class TeamSetup:
    """Every robot's :class:`RobotSetup`, the sides of the pairs and robot-obstacle
    couples, and the horizon lower bound ``first`` (the robots' largest)."""

    problem: TeamProblem
    robots: list[RobotSetup]
    pair_facets: dict[tuple[int, int], Facets]
    obstacle_facets: dict[tuple[int, int], Facets]
    first: float
    counters: dict[str, Any] = field(default_factory=dict)
    #: under disturbances: per pair / robot-obstacle couple, how far each side moves out
    #: at each sample (rows t = 0..max_horizon, :func:`~plansynth.reach.team.robust.pair_margins`)
    pair_margins: dict[tuple[int, int], np.ndarray] = field(default_factory=dict)
    obstacle_margins: dict[tuple[int, int], np.ndarray] = field(default_factory=dict)
    #: the largest horizon it was prepared for, and the seconds its preparation took
    max_horizon: int | None = None
    seconds: float = 0.0

    def serves(self, problem: TeamProblem, max_horizon: int) -> bool:
        """Is this the setup :func:`prepare` makes of ``problem`` for ``max_horizon``?
        (A planner given a setup, the seeded lazy planner's from its seed's, checks.)"""
        return self.problem is problem and self.max_horizon == max_horizon

    @property
    def tightened(self) -> bool:
        """Is this the setup of a team tightened by its robots' tubes?"""
        return any(s.model.margins is not None for s in self.robots)

    def guide(self, r: int, L: int) -> tuple[int, ...] | None:
        """Robot r's reference region sequence for horizon L (None for a mission)."""
        return _reference(self, r, L)


def _reference(setup: TeamSetup, r: int, L: int) -> tuple[int, ...] | None:
    """Robot r's reference plan for horizon L, kept; its route (the same at every
    horizon) is found once."""
    cache = setup.__dict__.setdefault("_refs", {})
    if (r, L) not in cache:
        s = setup.robots[r]
        if s.labels_of is not None:
            cache[(r, L)] = None
        else:
            if ("route", r) not in cache:
                cache[("route", r)] = route(s.planning, s.abstraction)
            path = cache[("route", r)]
            cache[(r, L)] = None if path is None else reference_plan(s.planning, s.abstraction, L, path=path)
    return cache[(r, L)]


def prepare(problem: TeamProblem, max_horizon: int, clock: Clock | None = None) -> TeamSetup:
    """The :class:`TeamSetup` of ``problem`` for horizons up to ``max_horizon``."""
    clock = clock if clock is not None else Budget().clock()
    t0 = time.perf_counter()
    robots = [_robot(problem, r, max_horizon, clock) for r in range(problem.n_robots)]
    tubes = [s.planning.tube for s in robots]
    pos = [tuple(r.dynamics.position) for r in problem.robots]
    pairs, pm = {}, {}
    for i in range(problem.n_robots):
        for j in range(i + 1, problem.n_robots):
            f = pair_facets(problem, i, j)
            if f is not None:
                pairs[(i, j)] = f
                m = pair_margins(f, tubes[i], pos[i], tubes[j], pos[j], max_horizon)
                if m is not None:
                    pm[(i, j)] = m
    obstacles, om = {}, {}
    for r in range(problem.n_robots):
        for o in range(len(problem.moving_obstacles)):
            f = obstacle_facets(problem, r, o)
            if f is not None:
                obstacles[(r, o)] = f
                m = obstacle_margins(f, tubes[r], pos[r], max_horizon)
                if m is not None:
                    om[(r, o)] = m
    first = max(s.bound for s in robots)
    counters = {
        "regions": sum(s.graph.n_regions for s in robots),
        "robot_regions": [s.graph.n_regions for s in robots],
        "robot_bounds": [None if math.isinf(s.bound) else int(s.bound) for s in robots],
        "pairs": len(pairs),
    }
    return TeamSetup(problem, robots, pairs, obstacles, first, counters, pm, om, max_horizon, time.perf_counter() - t0)


def alone_bound(problem: TeamProblem, r: int, model: RobotModel, lo: int, hi: int, clock: Clock) -> float:
    """The fewest steps in which robot r reaches its goal (and, with ``stop``, can stay
    there) obstacles ignored: the least L in lo..hi whose LP (dynamics, bounds, the
    robot's workspace, its goal and end state) is feasible (inf: none). Found by
    bisection, sound when the robot starts at rest (a plan of L steps, after a wait at
    the start, is one of L + 1); otherwise ``lo``. Each L asks only whether its LP is
    feasible: an infeasible one is not turned into a counterexample (no certificate,
    no deletion filter), which halves the cost of the search on a slow robot
    (SMC-LTL's crossing: 10 LPs per robot from a window bound of 1 to 29)."""
    from plansynth.reach.team.component_lp import ComponentLp
    from plansynth.reach.team.conplan import TeamConPlan
    from plansynth.reach.team.plans import TeamPlan

    if not problem.robot_problems[r].starts_at_rest or model.margins is not None or lo > hi:
        return lo  # (a tube's margins grow with time: a plan after a wait need not exist)
    ws = problem.robot_problems[r].workspace
    lo_s, hi_s = model.x_lo[list(model.pos)], model.x_hi[list(model.pos)]
    H, h = halfspaces(Box(tuple(np.maximum(lo_s, ws.lo)), tuple(np.minimum(hi_s, ws.hi))))
    relaxed = replace(model, regions=((H, h),))
    owner = TeamConPlan(problem, [relaxed] * (r + 1), {}, {}, clock)

    def feasible(L: int) -> bool:
        plan = TeamPlan(((0,) * (L + 1),) * (r + 1))
        status, _, _ = ComponentLp(owner, plan, (r,), {}, {}).solve(clock)
        return status == "feasible"

    top, step = lo, 0
    while not feasible(top):  # widen geometrically from the lower bound, then bisect
        if top >= hi:
            return math.inf
        lo = top + 1
        step = max(1, step * 2, top // 4)
        top = min(hi, top + step)
    hi = top
    while lo < hi:
        mid = (lo + hi) // 2
        if feasible(mid):
            hi = mid
        else:
            lo = mid + 1
    return lo


def _robot(problem: TeamProblem, r: int, max_horizon: int, clock: Clock) -> RobotSetup:
    own = problem.robot_problems[r]
    robot = problem.robots[r]
    cs = configuration_space(own)
    if robot.disturbance is not None:  # its own problem tightened by its tube
        tight = tightened_team(problem).planning[r]
        if tight is None:
            raise ValueError(f"robot {robot.name} has no tightened problem to plan (tightened_team says why)")
        cs = tight
    labels_of = None
    if robot.mission is not None:
        from plansynth.reach.mission.labels import label_abstraction, planning_problem

        la = label_abstraction(cs)
        abstraction, labels_of = la.abstraction, la.labels_of
        planning = planning_problem(cs)
    else:
        planning = cs
        abstraction = abstract(cs)
    graph = RegionGraph.from_abstraction(abstraction)
    w = time_windows(planning, abstraction, max_horizon)
    if robot.mission is not None:
        goal = None
    elif isinstance(robot.goal, GoalPoint):
        goal = ("point", np.asarray(robot.goal.point, float))
    else:
        goal = ("shape", *halfspaces(robot.goal))
    lo, hi = planning.state_box
    margins = None
    if planning.tube is not None and planning.tube.varies:
        goal_H = goal[1] if goal is not None and goal[0] == "shape" else None
        margins = robot_margins(planning.tube, tuple(robot.dynamics.position), goal_H, max_horizon)
    model = RobotModel(
        A=np.asarray(robot.dynamics.A, float),
        B=np.asarray(robot.dynamics.B, float),
        pos=tuple(robot.dynamics.position),
        start=np.asarray(robot.start, float),
        x_lo=np.asarray(lo, float),
        x_hi=np.asarray(hi, float),
        u_bound=robot.input_bound,
        regions=tuple((np.asarray(g.H, float), np.asarray(g.h, float)) for g in abstraction.regions),
        goal=goal,
        rest=robot.stop or robot.mission is not None,
        margins=margins,
    )
    bound = w.horizon
    if math.isfinite(bound) and robot.mission is None:
        bound = max(bound, alone_bound(problem, r, model, int(bound), max_horizon, clock))
    return RobotSetup(planning, abstraction, graph, model, tuple(w.earliest), tuple(w.to_go), bound, labels_of)

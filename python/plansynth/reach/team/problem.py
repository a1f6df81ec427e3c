"""Team problems: several robots and moving obstacles in one static world, the immutable
problem value (the multi-robot reach-avoid problem of Shoukry et al., CDC 2017, "Linear
temporal logic motion planning for teams of underactuated robots using satisfiability
modulo convex programming", Section II; SMC-LTL's ``MultiRobotMotionPlanner``).

A :class:`TeamProblem` is the workspace and static obstacles of a reach-avoid problem
(:class:`~plansynth.reach.problem.ReachProblem`), a tuple of :class:`TeamRobot` (each its
dynamics, start, goal, input bound, optional state bounds, size and mission), a
:class:`Separation` that every two robots keep (the distance between their shapes in the
infinity norm or a polygonal norm, :mod:`plansynth.reach.team.separation`), and
:class:`MovingObstacle` values (convex shapes moved along waypoints with times, linearly
between them, keeping the separation from every robot). All robots share one time step:
the joint trajectory has one horizon N, and robot r's trajectory is a trajectory of its
own problem (:attr:`TeamProblem.robot_problems`): a robot that arrives early waits in
its goal.

A goal is a convex shape, or a point (:class:`GoalPoint`: the final position equals it);
``stop`` asks the robot to end where it can stay (some admissible input keeps its last
state where it is: every derivative 0 for an integrator chain), as SMC-LTL's robots end
at rest. A robot with a mission (an LTL formula over the problem's labels, finite
semantics: the last position held forever) needs no goal. A robot may carry its own
bounded disturbance (``disturbance``: its W and feedback design, as one robot's
``robot.disturbance``); the team is then planned tightened by every robot's error tube
(:mod:`plansynth.reach.team.robust`).

The problem is checked when it is made: each robot's problem as a reach-avoid problem
is (its fields renamed ``robots[i]....``), the robots share a time step, the norm is a
centrally symmetric convex polygon around the origin, the moving obstacles are convex
with increasing times, and the robots' starts keep the separation from each other and
from the moving obstacles at time 0.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import LinearDynamics
from plansynth.reach.geometry import Box, Polygon, Shape, _frozen_array, is_convex, polygon_problem
from plansynth.reach.problem import DEFAULT_MAX_HORIZON, MAX_COORDINATE, ReachProblem
from plansynth.reach.robot import RobotShape
from plansynth.reach.team.separation import Zone, zone_of

__all__ = [
    "GoalPoint",
    "TeamRobot",
    "Separation",
    "MovingObstacle",
    "TeamProblem",
    "MAX_ROBOTS",
    "MAX_WAYPOINTS",
    "POINT_GOAL_BOX",
    "shape_parts",
]

#: Most robots of a team, and most moving obstacles.
MAX_ROBOTS = 64
#: Most waypoints of one moving obstacle.
MAX_WAYPOINTS = 10_000
#: Half the side of the box that stands for a point goal where a goal needs an area
#: (the decomposition's goal regions, the horizon bounds), relative to the workspace's
#: largest side: a superset of the point, so every bound computed with it holds for
#: the point.
POINT_GOAL_BOX = 1e-4


@dataclass(frozen=True)
class GoalPoint:
    """A goal that is one position: the robot's final position equals ``point``."""

    point: tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "point", tuple(float(v) for v in self.point))

    @property
    def dim(self) -> int:
        return len(self.point)

    def box(self, workspace: Box) -> Box:
        """The tiny box that stands for the point where an area is needed."""
        e = POINT_GOAL_BOX * max(h - l for l, h in zip(workspace.lo, workspace.hi))
        return Box(tuple(v - e for v in self.point), tuple(v + e for v in self.point))


@dataclass(frozen=True, eq=False)
class TeamRobot:
    """One robot of a team: its own dynamics, start, input bound, goal (a convex shape,
    a :class:`GoalPoint`, or None with a mission), optional state bounds, size and
    mission; ``stop``: it ends where it can stay; ``disturbance``: its own W and
    feedback design (:mod:`plansynth.reach.team.robust`)."""

    name: str
    dynamics: LinearDynamics
    start: np.ndarray
    input_bound: float
    goal: Shape | GoalPoint | None = None
    state_bounds: Box | None = None
    robot_shape: RobotShape | None = None
    mission: str | None = None
    stop: bool = False
    disturbance: Disturbance | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _frozen_array(np.asarray(self.start, dtype=float).reshape(-1)))
        object.__setattr__(self, "input_bound", float(self.input_bound))

    @property
    def start_position(self) -> np.ndarray:
        return self.start[list(self.dynamics.position)]

    def _key(self) -> tuple:
        rs = None if self.robot_shape is None or self.robot_shape.is_point else self.robot_shape
        return (
            self.name,
            self.dynamics,
            self.start.tobytes(),
            self.input_bound,
            self.goal,
            self.state_bounds,
            rs,
            self.mission,
            self.stop,
            self.disturbance,
        )

    def __eq__(self, other: object) -> bool:
        return isinstance(other, TeamRobot) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


@dataclass(frozen=True)
class Separation:
    """Every two robots keep ``distance`` between their shapes, measured in the norm
    whose unit ball is ``norm`` (a centrally symmetric convex polygon around the origin,
    2-D) or, with ``norm`` None, in the infinity norm."""

    distance: float = 0.0
    norm: Polygon | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "distance", float(self.distance))

    @property
    def norm_name(self) -> str:
        return "inf" if self.norm is None else "polygon"


@dataclass(frozen=True, eq=False)
class MovingObstacle:
    """A convex ``shape`` (given around its reference point; a box may be flat or a
    point: a parked point robot) whose reference point is at
    ``positions[k]`` at time ``times[k]`` (seconds), moving linearly between waypoints,
    at the first one before its time and at the last one after. ``separation``: the
    distance every robot keeps from it (None: the team's)."""

    shape: Shape
    times: tuple[float, ...]
    positions: tuple[tuple[float, ...], ...]
    name: str = "obstacle"
    separation: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "times", tuple(float(t) for t in self.times))
        object.__setattr__(self, "positions", tuple(tuple(float(v) for v in p) for p in self.positions))

    def position(self, time: float) -> np.ndarray:
        """The reference point at ``time`` (seconds).

        >>> o = MovingObstacle(Box((-1, -1), (1, 1)), (0.0, 10.0), ((0.0, 0.0), (10.0, 0.0)))
        >>> o.position(2.5).tolist(), o.position(-1).tolist(), o.position(99).tolist()
        ([2.5, 0.0], [0.0, 0.0], [10.0, 0.0])
        """
        P = np.asarray(self.positions, float)
        return np.array([np.interp(time, self.times, P[:, a]) for a in range(P.shape[1])])

    def bends(self, t0: float, t1: float) -> tuple[float, ...]:
        """The waypoint times strictly between t0 and t1 (where the motion may bend)."""
        return tuple(t for t in self.times if t0 < t < t1)

    def _key(self) -> tuple:
        return (self.shape, self.times, self.positions, self.name, self.separation)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, MovingObstacle) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


def shape_parts(robot: TeamRobot) -> list[tuple[str, np.ndarray | float]]:
    """A robot's extent as parts of a zone (:func:`~plansynth.reach.team.separation.zone_of`)."""
    rs = robot.robot_shape
    if rs is None or rs.is_point:
        return []
    if rs.radius is not None:
        return [("disc", rs.radius)]
    return [("box", np.asarray(rs.half_extent, float))]


def obstacle_part(shape: Shape) -> tuple[str, np.ndarray]:
    """A moving obstacle's shape, reflected through its reference point (``-O``), as a
    zone part: the robot at p and the obstacle at c overlap when p - c lies in K + (-O)."""
    if isinstance(shape, Box):
        lo, hi = np.asarray(shape.lo, float), np.asarray(shape.hi, float)
        if np.allclose(lo, -hi):
            return ("box", hi)
        if len(lo) == 2:
            v = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
            return ("polygon", -v)
        return ("box3", np.concatenate([-hi, -lo]))
    return ("polygon", -np.asarray(shape.vertices, float))


@dataclass(frozen=True, eq=False)
class TeamProblem:
    """Several robots in one workspace (see the module docstring), checked on construction."""

    workspace: Box
    obstacles: tuple[Shape, ...]
    robots: tuple[TeamRobot, ...]
    separation: Separation = Separation()
    moving_obstacles: tuple[MovingObstacle, ...] = ()
    labels: tuple[tuple[str, Shape], ...] = ()
    max_horizon: int = DEFAULT_MAX_HORIZON
    name: str = "team"
    source: str | None = field(default=None)

    def __post_init__(self) -> None:
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(self, "robots", tuple(self.robots))
        object.__setattr__(self, "moving_obstacles", tuple(self.moving_obstacles))
        labels = self.labels.items() if isinstance(self.labels, Mapping) else self.labels
        object.__setattr__(self, "labels", tuple((str(k), v) for k, v in labels))
        _check_team(self)

    # what the planners' registry and the bench read of any problem
    mission = None  # a team has no mission of its own (its robots may)

    @property
    def dim(self) -> int:
        return self.workspace.dim

    @property
    def n_robots(self) -> int:
        return len(self.robots)

    @property
    def dt(self) -> float | None:
        """The time step every robot shares (None: explicit dynamics without one)."""
        return self.robots[0].dynamics.dt

    @property
    def dynamics(self) -> LinearDynamics:
        """The first robot's dynamics (for code that reads one robot's time step)."""
        return self.robots[0].dynamics

    @cached_property
    def robot_problems(self) -> tuple[ReachProblem, ...]:
        """Robot r's own reach-avoid problem: the static world, its goal (a point goal as
        the box of :data:`POINT_GOAL_BOX`), its dynamics, start, bounds, size and mission."""
        return tuple(_robot_problem(self, i) for i in range(self.n_robots))

    def time_of(self, step: float) -> float:
        """Seconds at a (possibly fractional) step: ``step * dt`` (dt 1 when none)."""
        return float(step) * (self.dt if self.dt is not None else 1.0)

    def pair_zone(self, i: int, j: int) -> Zone:
        """The exact zone of robots i and j (:mod:`plansynth.reach.team.separation`)."""
        return zone_of(
            self.separation.distance, _norm_vertices(self), shape_parts(self.robots[i]) + shape_parts(self.robots[j])
        )

    def obstacle_zone(self, i: int, k: int) -> Zone:
        """The exact zone of robot i and moving obstacle k (relative position
        ``p_i - c_k(t)``)."""
        o = self.moving_obstacles[k]
        d = self.separation.distance if o.separation is None else o.separation
        kind, part = obstacle_part(o.shape)
        if kind == "box3":  # an off-centre 3-D box: its reflection is the box [-hi, -lo]
            lo, hi = part[:3], part[3:]
            centre, half = (lo + hi) / 2, (hi - lo) / 2
            z = zone_of(d, None, shape_parts(self.robots[i]) + [("box", half)])
            return Zone(z.H, z.h + z.H @ centre, z.radius)
        return zone_of(d, _norm_vertices(self), shape_parts(self.robots[i]) + [(kind, part)])

    def _key(self) -> tuple:
        return (
            self.workspace,
            self.obstacles,
            self.robots,
            self.separation,
            self.moving_obstacles,
            self.labels,
            self.max_horizon,
            self.name,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TeamProblem):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


def _norm_vertices(p: TeamProblem) -> np.ndarray | None:
    return None if p.separation.norm is None else np.asarray(p.separation.norm.vertices, float)


def _robot_problem(team: TeamProblem, i: int) -> ReachProblem:
    r = team.robots[i]
    goal = r.goal.box(team.workspace) if isinstance(r.goal, GoalPoint) else r.goal
    return ReachProblem(
        workspace=team.workspace,
        obstacles=team.obstacles,
        goal=goal,
        dynamics=r.dynamics,
        start=r.start,
        input_bound=r.input_bound,
        state_bounds=r.state_bounds,
        max_horizon=team.max_horizon,
        name=f"{team.name}/{r.name}",
        source=team.source,
        robot_shape=r.robot_shape,
        labels=team.labels if r.mission is not None else (),
        mission=r.mission,
        disturbance=r.disturbance,
    )


def _check_team(p: TeamProblem) -> None:
    src = p.source
    if not isinstance(p.workspace, Box):
        raise InvalidProblem(src, "workspace", "must be a box {min, max}")
    if not p.robots:
        raise InvalidProblem(src, "robots", "a team needs at least one robot")
    if len(p.robots) > MAX_ROBOTS:
        raise InvalidProblem(src, "robots", f"at most {MAX_ROBOTS} robots, got {len(p.robots)}")
    if len(p.moving_obstacles) > MAX_ROBOTS:
        raise InvalidProblem(
            src, "moving_obstacles", f"at most {MAX_ROBOTS} moving obstacles, got {len(p.moving_obstacles)}"
        )
    names: set[str] = set()
    for i, r in enumerate(p.robots):
        if not isinstance(r, TeamRobot):
            raise InvalidProblem(src, f"robots[{i}]", f"expected a TeamRobot, got {type(r).__name__}")
        if r.name in names:
            raise InvalidProblem(src, f"robots[{i}].name", f"robot name {r.name!r} used twice")
        names.add(r.name)
        if r.goal is None and r.mission is None:
            raise InvalidProblem(
                src, f"robots[{i}].goal", "missing required field (a robot without a mission needs a goal)"
            )
        if isinstance(r.goal, GoalPoint):
            if r.goal.dim != p.dim:
                raise InvalidProblem(src, f"robots[{i}].goal.point", f"must have {p.dim} coordinates, got {r.goal.dim}")
            if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in r.goal.point):
                raise InvalidProblem(src, f"robots[{i}].goal.point", "coordinates must be finite numbers")
        if r.disturbance is not None:
            _check_disturbed(src, i, r)
    dts = {r.dynamics.dt for r in p.robots}
    if len(dts) > 1:
        shown = ", ".join("none" if d is None else f"{d:g}" for d in sorted(dts, key=lambda d: (d is None, d or 0)))
        raise InvalidProblem(
            src, "robots", f"every robot must have the same time step dt (the joint plan's), got {shown}"
        )
    if p.moving_obstacles and p.dt is None:
        raise InvalidProblem(
            src, "moving_obstacles", "moving obstacles move in seconds: the robots' dynamics need a dt"
        )
    _check_separation(p)
    for k, o in enumerate(p.moving_obstacles):
        _check_moving(p, k, o)
    problems = []
    for i in range(len(p.robots)):
        try:
            problems.append(_robot_problem(p, i))
        except InvalidProblem as exc:
            raise InvalidProblem(src, _robot_field(exc.field, i), exc.reason) from None
    object.__setattr__(p, "robot_problems", tuple(problems))  # (the cached property, computed once)
    _check_starts(p)


def _check_disturbed(src: str | None, i: int, r: TeamRobot) -> None:
    """What a robot under a disturbance cannot ask for: a point goal (the disturbed
    closed loop cannot end exactly at a point) or a mission (a team's robots plan their
    missions without disturbances)."""
    if isinstance(r.goal, GoalPoint):
        raise InvalidProblem(
            src,
            f"robots[{i}].goal",
            f"robot {r.name} has a disturbance: its goal must be a region (the disturbed closed loop cannot end "
            "exactly at a point)",
        )
    if r.mission is not None:
        raise InvalidProblem(
            src, f"robots[{i}].disturbance", f"robot {r.name} has a mission: in a team, missions plan no disturbance"
        )


def _robot_field(field_name: str, i: int) -> str:
    """A robot problem's field as the team file names it."""
    if field_name.startswith("robot."):
        return f"robots[{i}].{field_name[len('robot.') :]}"
    if field_name in ("goal", "mission"):
        return f"robots[{i}].{field_name}"
    return field_name


def _check_separation(p: TeamProblem) -> None:
    src, sep = p.source, p.separation
    if not isinstance(sep, Separation):
        raise InvalidProblem(src, "separation", f"expected a Separation, got {type(sep).__name__}")
    if not math.isfinite(sep.distance) or sep.distance < 0 or sep.distance > MAX_COORDINATE:
        raise InvalidProblem(src, "separation.distance", f"must be a non-negative number, got {sep.distance}")
    if sep.norm is None:
        return
    if p.dim != 2:
        raise InvalidProblem(src, "separation.norm", "a polygonal norm needs a 2-D workspace (3-D: the infinity norm)")
    why = polygon_problem(sep.norm) if isinstance(sep.norm, Polygon) else "expected a polygon"
    if why is not None:
        raise InvalidProblem(src, "separation.norm", why)
    if not is_convex(sep.norm):
        raise InvalidProblem(src, "separation.norm", "the unit ball of a norm must be convex")
    v = np.asarray(sep.norm.vertices, float)
    scale = float(np.max(np.abs(v)))
    if any(np.min(np.max(np.abs(v + w), axis=1)) > 1e-9 * scale for w in v):
        raise InvalidProblem(
            src, "separation.norm", "the unit ball of a norm must be centrally symmetric (with v, -v is a vertex)"
        )
    from shapely.geometry import Point

    from plansynth.reach.geometry import shape_to_shapely

    if not shape_to_shapely(sep.norm).contains(Point(0.0, 0.0)):
        raise InvalidProblem(src, "separation.norm", "the unit ball of a norm must contain the origin inside")


def _check_moving(p: TeamProblem, k: int, o: MovingObstacle) -> None:
    src, where = p.source, f"moving_obstacles[{k}]"
    if not isinstance(o.shape, (Box, Polygon)):
        raise InvalidProblem(src, f"{where}.shape", "expected a box or a polygon")
    if o.shape.dim != p.dim:
        raise InvalidProblem(src, f"{where}.shape", f"is {o.shape.dim}-D but the workspace is {p.dim}-D")
    if isinstance(o.shape, Box) and any(not l <= h for l, h in zip(o.shape.lo, o.shape.hi)):
        raise InvalidProblem(src, f"{where}.shape", f"min {list(o.shape.lo)} exceeds max {list(o.shape.hi)}")
    if isinstance(o.shape, Polygon):
        why = polygon_problem(o.shape)
        if why is not None:
            raise InvalidProblem(src, f"{where}.shape", why)
        if not is_convex(o.shape):
            raise InvalidProblem(src, f"{where}.shape", "a moving obstacle must be convex (split it into convex ones)")
    if not o.times:
        raise InvalidProblem(src, f"{where}.path", "needs at least one waypoint")
    if len(o.times) > MAX_WAYPOINTS:
        raise InvalidProblem(src, f"{where}.path", f"at most {MAX_WAYPOINTS} waypoints, got {len(o.times)}")
    if len(o.positions) != len(o.times):
        raise InvalidProblem(src, f"{where}.path", "one position per time")
    for w, (t, pos) in enumerate(zip(o.times, o.positions)):
        if not math.isfinite(t) or t < 0:
            raise InvalidProblem(src, f"{where}.path[{w}].t", f"must be a non-negative time in seconds, got {t}")
        if w and not t > o.times[w - 1]:
            raise InvalidProblem(src, f"{where}.path[{w}].t", "waypoint times must increase")
        if len(pos) != p.dim or not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in pos):
            raise InvalidProblem(src, f"{where}.path[{w}].at", f"must be {p.dim} finite coordinates")
    if o.separation is not None and (not math.isfinite(o.separation) or o.separation < 0):
        raise InvalidProblem(src, f"{where}.separation", f"must be a non-negative number, got {o.separation}")


def _check_starts(p: TeamProblem) -> None:
    """The robots' starts keep the separation from each other and from the moving
    obstacles at time 0 (exact zones)."""
    src = p.source
    for i in range(p.n_robots):
        pi = p.robots[i].start_position
        for j in range(i):
            z = pi - p.robots[j].start_position
            if p.pair_zone(i, j).intrusion(z, z) > 0.0:
                raise InvalidProblem(
                    src,
                    f"robots[{i}].start",
                    f"robot {p.robots[i].name} starts closer than the separation to robot {p.robots[j].name}",
                )
        for k, o in enumerate(p.moving_obstacles):
            z = pi - o.position(0.0)
            if p.obstacle_zone(i, k).intrusion(z, z) > 0.0:
                raise InvalidProblem(
                    src,
                    f"robots[{i}].start",
                    f"robot {p.robots[i].name} starts closer than the separation to moving obstacle {o.name}",
                )

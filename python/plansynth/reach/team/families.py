"""Team problems as code: the cases of the ``team`` benchmark family and the examples.

* :func:`smc_crossing`: SMC-LTL's two-robot crossing (``TestcaseExample.py``,
  ``motionPlanning_test1``, exactly its numbers): a 5 x 5 workspace split 3 x 3 at
  x = 1, 3 and y = 2, 3 with the four corner cells as obstacles (a cross), a chain of
  two integrators per axis with Ts = 0.2, |u|_inf <= 0.5, robots at least 0.5 apart in
  the infinity norm (``|x_i - x_j| >= 0.5`` or ``|y_i - y_j| >= 0.5``), robot 0 from
  (0, 2.5) to (4, 2.5), robot 1 from (2, 0.5) to (2, 4.5), both from rest to rest.
  (SMC-LTL grows the horizon from 3 in blocks of 20 samples; here a horizon counts samples.)
* :func:`corridor_swap`: two robots swap the ends of a corridor with one passing bay near
  robot A's end: one must wait in the bay. Prioritized planning (A first) fails.
* :func:`room_corners`: four robots exchange the corners of a room with a central pillar.
* :func:`team_maze`: the lazy paper's maze-n (Section VI) with 2 or 4 robots entering
  from both ends.
* :func:`antipodal`: n robots on a circle in an empty 10 x 10 room, each to the
  antipodal point.
* :func:`patrol_gap`: maze-1 with a vehicle patrolling back and forth through the gap.
* :func:`narrow_corridor`: two robots that must swap the ends of a corridor too narrow
  to pass, no bay: infeasible.
* :func:`windy_swap`: the corridor swap with a bounded disturbance on each robot (the
  ``robust`` benchmark family's team, :mod:`plansynth.reach.team.robust`).

>>> [r.name for r in smc_crossing().robots], smc_crossing().separation.distance
(['robot0', 'robot1'], 0.5)
>>> sorted(TEAM_CASES)[:3]
['antipodal-16', 'antipodal-8', 'corridor-swap']
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import double_integrator, integrator_chain
from plansynth.reach.geometry import Box
from plansynth.reach.robot import RobotShape
from plansynth.reach.team.problem import GoalPoint, MovingObstacle, Separation, TeamProblem, TeamRobot

__all__ = [
    "smc_crossing",
    "corridor_swap",
    "room_corners",
    "team_maze",
    "antipodal",
    "patrol_gap",
    "narrow_corridor",
    "windy_swap",
    "WINDY_SWAP_BOX",
    "TEAM_CASES",
    "INFEASIBLE_CASES",
    "team_case",
]


def _at_rest(p: tuple[float, ...], n: int) -> np.ndarray:
    x = np.zeros(n)
    x[: len(p)] = p
    return x


def smc_crossing() -> TeamProblem:
    """SMC-LTL's crossing (see the module docstring)."""
    dyn = integrator_chain(2, 2, 0.2)
    corners = (Box((0, 0), (1, 2)), Box((0, 3), (1, 5)), Box((3, 0), (5, 2)), Box((3, 3), (5, 5)))
    robots = (
        TeamRobot("robot0", dyn, _at_rest((0.0, 2.5), 4), 0.5, goal=GoalPoint((4.0, 2.5)), stop=True),
        TeamRobot("robot1", dyn, _at_rest((2.0, 0.5), 4), 0.5, goal=GoalPoint((2.0, 4.5)), stop=True),
    )
    return TeamProblem(
        workspace=Box((0, 0), (5, 5)),
        obstacles=corners,
        robots=robots,
        separation=Separation(0.5),
        max_horizon=200,
        name="smc-crossing",
    )


def _corridor(bay: bool, name: str, max_horizon: int) -> TeamProblem:
    dyn = double_integrator(2, 0.5)
    bounds = Box((0, 0, -1, -1), (10, 2, 1, 1))
    size = RobotShape(half_extent=(0.25, 0.25))
    obstacles = (Box((0, 1), (2, 2)), Box((3.5, 1), (10, 2))) if bay else (Box((0, 1), (10, 2)),)
    robots = (
        TeamRobot(
            "A", dyn, _at_rest((0.5, 0.5), 4), 1.0, goal=Box((9, 0), (10, 1)), state_bounds=bounds, robot_shape=size
        ),
        TeamRobot(
            "B", dyn, _at_rest((9.5, 0.5), 4), 1.0, goal=Box((0, 0), (1, 1)), state_bounds=bounds, robot_shape=size
        ),
    )
    return TeamProblem(
        workspace=Box((0, 0), (10, 2)),
        obstacles=obstacles,
        robots=robots,
        separation=Separation(0.2),
        max_horizon=max_horizon,
        name=name,
    )


def corridor_swap() -> TeamProblem:
    """Two box robots (0.5 x 0.5, 0.2 apart) swap the ends of a 1 m corridor with a bay
    (1.5 x 1 m) above it near A's end; double integrators, dt 0.5, |u| <= 1, |v| <= 1."""
    return _corridor(True, "corridor-swap", 80)


def narrow_corridor() -> TeamProblem:
    """:func:`corridor_swap` without the bay: the robots cannot pass (infeasible)."""
    return _corridor(False, "narrow-corridor", 40)


#: the windy swap's disturbance: 2 cm and 5 cm/s per 0.5 s step on each axis
WINDY_SWAP_BOX = (0.02, 0.02, 0.05, 0.05)


def windy_swap(scale: float = 1.0) -> TeamProblem:
    """:func:`corridor_swap` with the disturbance ``scale`` times :data:`WINDY_SWAP_BOX`
    on both robots (each its own LQR feedback): the robots, their separation and the
    corridor's walls are kept under every disturbance sequence."""
    p = corridor_swap()
    w = Disturbance(box=tuple(scale * v for v in WINDY_SWAP_BOX))
    suffix = "" if scale == 1.0 else f"-x{scale:g}"
    return replace(p, robots=tuple(replace(r, disturbance=w) for r in p.robots), name=f"corridor-swap-windy{suffix}")


def room_corners() -> TeamProblem:
    """Four box robots (0.6 x 0.6, 0.2 apart) exchange the diagonally opposite corners
    of a 10 x 10 room around a 2 x 2 pillar; double integrators, dt 0.5, |u| <= 1, |v| <= 1.5."""
    dyn = double_integrator(2, 0.5)
    bounds = Box((0, 0, -1.5, -1.5), (10, 10, 1.5, 1.5))
    size = RobotShape(half_extent=(0.3, 0.3))
    corners = ((1.0, 1.0), (9.0, 1.0), (9.0, 9.0), (1.0, 9.0))
    robots = []
    for k, c in enumerate(corners):
        g = corners[(k + 2) % 4]
        robots.append(
            TeamRobot(
                f"c{k}",
                dyn,
                _at_rest(c, 4),
                1.0,
                goal=Box((g[0] - 0.5, g[1] - 0.5), (g[0] + 0.5, g[1] + 0.5)),
                state_bounds=bounds,
                robot_shape=size,
            )
        )
    return TeamProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Box((4, 4), (6, 6)),),
        robots=tuple(robots),
        separation=Separation(0.2),
        max_horizon=120,
        name="room-corners",
    )


def team_maze(n: int, robots: int = 2) -> TeamProblem:
    """The lazy paper's maze-n (:func:`plansynth.reach.families.maze`: 30 x 30, walls
    1 m thick with 2 m gaps, the double integrator with dt 0.5, |u| <= 1, |v| <= 2) with
    ``robots`` (2 or 4) point robots 1 m apart: half start at the bottom left and go to
    the maze's goal end, half start at the goal end and go to the bottom left."""
    from plansynth.reach.families import maze

    base = maze(n)
    dyn = base.dynamics
    g = base.goal
    gx = (g.lo[0] + g.hi[0]) / 2
    up_starts = [(1.0, 1.0), (3.0, 1.0)]
    up_goals = [
        Box((gx - 1, 27), (gx + 1, 29)),
        Box((gx - 1 + (2 if gx < 15 else -2), 27), (gx + 1 + (2 if gx < 15 else -2), 29)),
    ]
    down_starts = [(gx, 28.0), (gx + (2 if gx < 15 else -2), 28.0)]
    down_goals = [Box((0, 0), (2, 2)), Box((2, 0), (4, 2))]
    half = robots // 2
    team = []
    for k in range(half):
        team.append(
            TeamRobot(f"up{k}", dyn, _at_rest(up_starts[k], 4), 1.0, goal=up_goals[k], state_bounds=base.state_bounds)
        )
    for k in range(half):
        team.append(
            TeamRobot(
                f"down{k}", dyn, _at_rest(down_starts[k], 4), 1.0, goal=down_goals[k], state_bounds=base.state_bounds
            )
        )
    return TeamProblem(
        workspace=base.workspace,
        obstacles=base.obstacles,
        robots=tuple(team),
        separation=Separation(1.0),
        max_horizon=300,
        name=f"maze-{n}-{robots}robots",
    )


def antipodal(n: int, radius: float = 4.0) -> TeamProblem:
    """``n`` point robots on a circle of ``radius`` around the centre of an empty
    10 x 10 room, each to the antipodal point (a 0.4 x 0.4 goal box), 0.5 apart;
    double integrators, dt 0.5, |u| <= 1, |v| <= 1."""
    dyn = double_integrator(2, 0.5)
    bounds = Box((0, 0, -1, -1), (10, 10, 1, 1))
    robots = []
    for k in range(n):
        a = 2 * math.pi * k / n
        s = (5 + radius * math.cos(a), 5 + radius * math.sin(a))
        g = (5 - radius * math.cos(a), 5 - radius * math.sin(a))
        robots.append(
            TeamRobot(
                f"a{k}",
                dyn,
                _at_rest((round(s[0], 6), round(s[1], 6)), 4),
                1.0,
                goal=Box((round(g[0] - 0.2, 6), round(g[1] - 0.2, 6)), (round(g[0] + 0.2, 6), round(g[1] + 0.2, 6))),
                state_bounds=bounds,
            )
        )
    return TeamProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(),
        robots=tuple(robots),
        separation=Separation(0.5),
        max_horizon=100,
        name=f"antipodal-{n}",
    )


def patrol_gap() -> TeamProblem:
    """Maze-1 (:func:`plansynth.reach.families.maze`) with its robot, and a 1.5 x 1.5
    vehicle that patrols through the wall's gap (x = 28, from y = 12.5 to y = 17.5 and
    back, 5 s each way, for 200 s), keeping 0.5 from the robot: the robot cannot share
    the gap with it, and must time its passage."""
    from plansynth.reach.families import maze

    base = maze(1)
    times, positions = [], []
    for k in range(41):
        times.append(5.0 * k)
        positions.append((28.0, 12.5 if k % 2 == 0 else 17.5))
    vehicle = MovingObstacle(Box((-0.75, -0.75), (0.75, 0.75)), tuple(times), tuple(positions), "vehicle")
    robot = TeamRobot(
        "robot", base.dynamics, base.start, base.input_bound, goal=base.goal, state_bounds=base.state_bounds
    )
    return TeamProblem(
        workspace=base.workspace,
        obstacles=base.obstacles,
        robots=(robot,),
        separation=Separation(0.5),
        moving_obstacles=(vehicle,),
        max_horizon=200,
        name="patrol-gap",
    )


#: the cases of the ``team`` benchmark family, by name
TEAM_CASES = {
    "smc-crossing": smc_crossing,
    "corridor-swap": corridor_swap,
    "room-corners": room_corners,
    **{f"maze-{n}-{k}robots": (lambda n=n, k=k: team_maze(n, k)) for n in (1, 2, 3, 4) for k in (2, 4)},
    "antipodal-8": lambda: antipodal(8),
    "antipodal-16": lambda: antipodal(16),
    "patrol-gap": patrol_gap,
    "narrow-corridor": narrow_corridor,
}


#: the cases that have no plan (of the encoding; the narrow corridor has none at all)
INFEASIBLE_CASES = ("narrow-corridor",)


def team_case(name: str) -> TeamProblem:
    """The case called ``name`` (:data:`TEAM_CASES`)."""
    return TEAM_CASES[name]()

"""Robot size (robot.radius / robot.half_extent): configuration space, door checks,
planners and the validator's own clearance checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem
from plansynth.reach.families import maze
from plansynth.reach.fileformat import reach_problem_from_dict, reach_problem_to_dict
from plansynth.reach.geometry import Box
from plansynth.reach.result import ReachStatus
from plansynth.reach.robot import RobotShape, configuration_space, disc_polygon, with_robot
from plansynth.reach.solve import solve
from plansynth.reach.validate import validate


def _doc(**robot):
    d = reach_problem_to_dict(maze(1))
    d["robot"].update(robot)
    return d


def test_existing_files_keep_a_point_robot():
    p = reach_problem_from_dict(reach_problem_to_dict(maze(1)))
    assert p.robot_shape is None and configuration_space(p) is p
    assert "radius" not in reach_problem_to_dict(p)["robot"]


def test_robot_keys_round_trip():
    p = reach_problem_from_dict(_doc(radius=0.4), source="m.yaml")
    assert p.robot_shape == RobotShape(radius=0.4)
    assert reach_problem_from_dict(reach_problem_to_dict(p)) == p
    q = reach_problem_from_dict(_doc(half_extent=[0.2, 0.3]), source="m.yaml")
    assert q.robot_shape.half_extent == (0.2, 0.3) and q != p


@pytest.mark.parametrize(
    "robot, field, reason",
    [
        ({"radius": 1.5}, "robot.start", "does not fit in the workspace"),
        ({"radius": 0.4, "half_extent": [0.1, 0.1]}, "robot.radius", "not both"),
        ({"radius": -1}, "robot.radius", "non-negative"),
        ({"half_extent": [0.1]}, "robot.half_extent", "2"),
        ({"radius": 1.0}, "goal", "unreachable for the robot"),
    ],
)
def test_bad_robot_sizes_are_rejected_at_the_door(robot, field, reason):
    d = _doc(**robot)
    if field == "goal":
        d["goal"] = {"min": [0, 27], "max": [0.5, 29]}  # the robot's centre cannot come within 1 of x = 0
    with pytest.raises(InvalidProblem, match=reason) as e:
        reach_problem_from_dict(d, source="m.yaml")
    assert e.value.field == field and e.value.file == "m.yaml"


def test_a_disc_needs_a_2d_workspace():
    d = {
        "workspace": {"min": [0, 0, 0], "max": [5, 5, 5]},
        "goal": {"min": [4, 4, 4], "max": [5, 5, 5]},
        "robot": {
            "dynamics": {"model": "single-integrator", "dt": 1},
            "start": [1, 1, 1],
            "input_bound": 1,
            "radius": 0.2,
        },
    }
    with pytest.raises(InvalidProblem, match="2-D workspace"):
        reach_problem_from_dict(d)


def test_the_disc_polygon_covers_the_disc():
    v = disc_polygon(0.7)
    poly = shapely.Polygon(v)
    circle = [shapely.Point(0.7 * math.cos(a), 0.7 * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 721)]
    assert all(poly.buffer(1e-12).contains(c) for c in circle)
    assert poly.area > math.pi * 0.7**2


def test_box_robot_among_boxes_is_exact():
    c = configuration_space(with_robot(maze(1), RobotShape(half_extent=(0.25, 0.5))))
    assert c.workspace == Box((0.25, 0.5), (29.75, 29.5))
    assert c.obstacles[0] == Box((0.25, 14.0), (27.25, 16.0)) and c.robot_shape is None


def _clearance(p, traj) -> float:
    pts = p.position_of(traj.states)
    geoms = [shapely.box(*o.lo, *o.hi) for o in p.obstacles]
    segs = [shapely.LineString([pts[t], pts[t + 1]]) for t in range(len(pts) - 1)]
    return min(g.distance(s) for g in geoms for s in segs)


@pytest.mark.parametrize("robot", [RobotShape(radius=0.4), RobotShape(half_extent=(0.3, 0.4))])
def test_lazy_smt_keeps_the_robot_clear(robot):
    p = with_robot(maze(1), robot)
    r = solve(p, "lazy-smt", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.validated, r.message
    assert "robot:" in r.message and r.options["robot"]
    if robot.radius is not None:
        assert _clearance(p, r.trajectory) >= 0.4 - 1e-6
    else:  # Chebyshev-style: the robot's box never overlaps a wall box
        pos = p.position_of(r.trajectory.states)
        for o in p.obstacles:
            inside = np.all(
                (pos > np.array(o.lo) - robot.half_extent + 1e-6) & (pos < np.array(o.hi) + robot.half_extent - 1e-6),
                axis=1,
            )
            assert not inside.any()


def test_the_validator_checks_clearance_itself():
    point = solve(maze(1), "lazy-smt", Budget(seconds=60))
    assert point.status is ReachStatus.FOUND
    assert _clearance(maze(1), point.trajectory) < 0.4  # the point plan rides along the wall
    for robot in (RobotShape(radius=0.4), RobotShape(half_extent=(0.4, 0.4))):
        rep = validate(with_robot(maze(1), robot), point.trajectory, require_segment_safe=True)
        assert not rep.ok and ({"obstacle", "segment", "workspace"} & set(rep.counts))


@pytest.mark.parametrize("radius,tol", [(1e-7, 1e-6), (1e-6, 1e-6), (0.01, 0.02)])
def test_a_disc_no_larger_than_the_tolerance_still_may_not_enter_an_obstacle(radius, tol):
    """The clearance test (distance < R - tol) never fires when R <= tol: the interior
    test of a point robot still applies (found by a review: such a robot passed straight
    through an obstacle)."""
    from plansynth.reach.dynamics import single_integrator
    from plansynth.reach.problem import ReachProblem
    from plansynth.reach.trajectory import Trajectory

    p = ReachProblem(
        workspace=Box((0, 0), (30, 30)),
        obstacles=(Box((10, 10), (20, 20)),),
        goal=Box((25, 25), (27, 27)),
        dynamics=single_integrator(2, 1.0),
        start=[5, 5],
        input_bound=20.0,
        robot_shape=RobotShape(radius=radius),
    )
    t = Trajectory(states=[[5, 5], [15, 15], [26, 26]], inputs=[[10, 10], [11, 11]])
    r = validate(p, t, require_segment_safe=True, tol=tol)
    assert not r.ok and {v.kind for v in r.violations} >= {"obstacle", "segment"}


def test_the_plot_draws_the_robot(tmp_path):
    from plansynth.reach.abstraction import abstract
    from plansynth.reach.plot import plot_problem

    p = with_robot(maze(1), RobotShape(radius=0.4))
    r = solve(p, "lazy-smt", Budget(seconds=60))
    fig = plot_problem(p, abstract(configuration_space(p)), r.regions, r.trajectory, path=tmp_path / "m.png")
    ax = fig.axes[0]
    circles = [a for a in ax.patches if type(a).__name__ == "Circle"]
    dashed = [a for a in ax.patches if a.get_linestyle() == "--"]
    assert circles and abs(circles[0].radius - 0.4) < 1e-12 and len(dashed) == len(configuration_space(p).obstacles)
    assert (tmp_path / "m.png").stat().st_size > 0


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    radius=st.floats(0.05, 0.8),
    box=st.booleans(),
    pts=st.lists(st.tuples(st.floats(0, 10), st.floats(0, 10)), min_size=20, max_size=20),
)
def test_the_configuration_space_is_conservative(seed, radius, box, pts):
    """Outside every grown obstacle, the robot (disc: clearance >= R; box: its box) meets
    no original obstacle's interior: the growth covers the exact Minkowski sum."""
    from plansynth.reach.families import random_workspace
    from plansynth.reach.geometry import point_in_interior

    base = random_workspace(seed, 4)
    robot = RobotShape(half_extent=(radius, radius / 2)) if box else RobotShape(radius=radius)
    grown = [_grow(o, robot) for o in base.obstacles]
    originals = [
        shapely.Polygon(o.vertices) if hasattr(o, "vertices") else shapely.box(*o.lo, *o.hi) for o in base.obstacles
    ]
    # the random points, and the points just outside every edge of every grown obstacle
    # (where an inner approximation of the disc would come too close)
    probe = list(pts)
    for g in grown:
        v = np.array(
            g.vertices
            if hasattr(g, "vertices")
            else [(g.lo[0], g.lo[1]), (g.hi[0], g.lo[1]), (g.hi[0], g.hi[1]), (g.lo[0], g.hi[1])]
        )
        for a, b in zip(v, np.roll(v, -1, axis=0)):
            e = b - a
            n = np.array([e[1], -e[0]]) / np.hypot(*e)  # outward for CCW
            probe.append(tuple((a + b) / 2 + 1e-7 * n))
    for x, y in probe:
        if any(point_in_interior(g, (x, y)) for g in grown):
            continue
        if box:
            body = shapely.box(x - radius, y - radius / 2, x + radius, y + radius / 2)
            assert not any(o.buffer(-1e-9).intersects(body) for o in originals)
        else:
            assert all(o.distance(shapely.Point(x, y)) >= radius - 1e-9 for o in originals)


def _grow(o, robot):
    from plansynth.reach.robot import _inflate

    return _inflate(o, robot)

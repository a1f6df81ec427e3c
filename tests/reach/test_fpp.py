"""The FPP baseline (Marcucci, Nobel, Tedrake and Boyd, IEEE T-RO 2024, through the
``fastpathplanning`` library): a validated continuous-time curve through the maximal free
boxes, re-timed to the problem's |v| and |a| bounds, the guarantee it states, the budget
honoured by its child process, and what it refuses to plan."""

from __future__ import annotations

import time

import numpy as np
import pytest

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.reach.dynamics import double_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.planners.curves import PiecewiseBezier
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus
from plansynth.reach.solve import planners, solve
from plansynth.reach.validate import validate

pytest.importorskip("fastpathplanning")


@pytest.fixture(scope="module")
def maze1_fpp():
    return solve(maze(1), "fpp", Budget(seconds=120))


def test_fpp_is_a_planner_of_solve():
    assert "fpp" in planners()


def test_fpp_finds_a_validated_curve_on_maze_1(maze1_fpp):
    r = maze1_fpp
    assert r.status is ReachStatus.FOUND, r.message
    assert r.planner == "fpp" and r.guarantee == "curve" and r.validated is True
    assert r.curve_validation.ok and r.curve_validation.segment_safe
    assert "FPP plans no dynamics" in r.message and "NOT a trajectory" in r.message
    X, U = r.trajectory.states, r.trajectory.inputs
    assert np.allclose(X[0], maze(1).start)
    assert np.abs(X[:, 2:]).max() <= 2.0 + 1e-6 and np.abs(U).max() <= 1.0 + 1e-6
    assert r.counters["boxes"] == 3 and r.options["sets"] == "boxes"
    # the exact validator refuses the samples as a trajectory of x' = A x + B u
    assert not validate(maze(1), r.trajectory).ok


def test_fpp_duration_is_the_shortest_uniform_retiming(maze1_fpp):
    """FPP's own curve (duration 300 s) is well within the bounds; the uniform re-timing
    brings the binding one (here |v|) to exactly its bound, which the dense samples show."""
    c = maze1_fpp.counters
    speed, accel = c["fpp_speed_ratio"], c["fpp_accel_ratio"]
    assert 0 < speed < 1 and 0 < accel < 1
    s = max(speed, np.sqrt(accel))
    assert c["retimed_duration"] == pytest.approx(c["fpp_duration"] * s)
    V = np.asarray(maze1_fpp.curve.states)[:, 2:]
    bound = 2.0 / c["stretch"]  # the last stretch to whole time steps slows it a little more
    assert 0.97 * bound <= np.abs(V).max() <= bound + 1e-9


def test_fpp_budget_is_honoured():
    t0 = time.perf_counter()
    r = solve(maze(4), "fpp", Budget(seconds=0.2))
    assert time.perf_counter() - t0 <= 0.2 + 1.0
    assert r.status is ReachStatus.UNKNOWN and "budget" in r.message


def test_fpp_refuses_what_it_cannot_plan():
    with pytest.raises(SolverUnavailable, match="single- and double-integrator"):
        solve(maze(1, order=3), "fpp", Budget(seconds=10))

    def world(obstacles: tuple, start: list[float]) -> ReachProblem:
        return ReachProblem(
            workspace=Box((0, 0), (10, 10)),
            obstacles=obstacles,
            goal=Box((8, 1), (9, 2)),
            dynamics=double_integrator(2, 0.5),
            start=start,
            input_bound=1.0,
        )

    poly = world((Polygon(((3, 0), (5, 0), (4, 7))),), [1, 1, 0, 0])
    with pytest.raises(SolverUnavailable, match="every obstacle must be a box"):
        solve(poly, "fpp", Budget(seconds=10))
    moving = world((), [1, 1, 0.5, 0])
    with pytest.raises(SolverUnavailable, match="starts at rest"):
        solve(moving, "fpp", Budget(seconds=10))


def test_piecewise_bezier_derivatives_and_bounds():
    """The curve helper: values and derivatives against finite differences, the
    control-point extremes bound the sampled values, and stretching slows it uniformly."""
    rng = np.random.default_rng(0)
    pts = tuple(rng.normal(size=(6, 2)) for _ in range(3))
    c = PiecewiseBezier(pts, np.array([0.0, 1.0, 2.5, 3.0]))
    t = np.linspace(0.01, 2.99, 200)
    v = c.derivative()
    h = 1e-6
    fd = (c(t + h) - c(t - h)) / (2 * h)
    inner = np.all(np.abs(t[:, None] - np.array([1.0, 2.5])[None, :]) > 1e-3, axis=1)
    assert np.allclose(v(t)[inner], fd[inner], atol=1e-4)
    lo, hi = c.extremes()
    assert np.all(c(t) >= lo - 1e-12) and np.all(c(t) <= hi + 1e-12)
    s = c.stretched(2.0)
    assert s.duration == pytest.approx(6.0)
    assert np.allclose(s.derivative()(2 * t), v(t) / 2)


def test_fpp_out_of_budget_is_unknown_and_took_its_budget():
    """A budget too short for FPP (its child process alone imports cvxpy): ``unknown``,
    and the seconds reported are the time it ran, not 0 (a child killed at the budget
    spent it on FPP's work, not on start-up overhead)."""
    r = solve(maze(1), "fpp", Budget(seconds=0.3))
    assert r.status is ReachStatus.UNKNOWN, r.message
    assert r.seconds >= 0.3, (r.seconds, r.timings)

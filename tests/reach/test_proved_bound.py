"""``infeasible`` must be proved: DIS-PLAN moves one region per step, so
refuting every horizon through a decomposition of thousands of sliver regions is not
a proof. Only :func:`plansynth.reach.lazy.bounds.proved_horizon_bound` may prove it; these
tests check that it is a lower bound on every trajectory found, and that the cases that
used to be answered ``infeasible`` are not."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reach_oracles import problems
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import OUTER_VERTICES, abstract, outer_polygon
from plansynth.reach.dynamics import double_integrator, single_integrator
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.lazy.bounds import proved_horizon_bound, touching
from plansynth.reach.problem import ReachProblem

PROPS = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def circle(cx: float, cy: float, r: float, n: int) -> Polygon:
    return Polygon(
        tuple((cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n)) for k in range(n))
    )


def issue_problem(n: int) -> ReachProblem:
    """The reported case: a wall and a circle given as an n-vertex polygon."""
    return ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Box((4, 0), (5, 8)), circle(6, 4, 1.5, n)),
        goal=Box((8, 8), (9, 9)),
        dynamics=double_integrator(2, 0.5),
        start=[1, 1, 0, 0],
        input_bound=1.0,
        state_bounds=Box((0, 0, -2, -2), (10, 10, 2, 2)),
        max_horizon=100,
    )


def ring(n: int) -> ReachProblem:
    """Around a circle (n vertices) from left to right: every decomposition fans out
    from the workspace corners into slivers that a short path crosses one per step.
    Before the fix: "infeasible up to horizon 30" with 400 vertices; 3 steps suffice."""
    return ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(circle(5, 5, 3, n),),
        goal=Box((9, 4.5), (9.5, 5.5)),
        dynamics=single_integrator(2, 1.0),
        start=[0.5, 5],
        input_bound=3.0,
        max_horizon=30,
    )


def test_issue_case_is_found() -> None:
    r = solve(issue_problem(1000))
    assert r.status is ReachStatus.FOUND and r.validated is True and r.segment_safe is True
    assert r.counters["exact_abstraction"] is False and r.counters["regions"] < 100


@pytest.mark.slow
def test_issue_case_with_10000_vertices_is_found() -> None:
    r = solve(issue_problem(10_000))
    assert r.status is ReachStatus.FOUND and r.validated is True


@pytest.mark.parametrize("planner", ["lazy-smt", "milp"])
def test_sliver_fans_are_not_infeasible(planner: str) -> None:
    p = ring(400)
    r = solve(p, planner)
    assert r.status is not ReachStatus.INFEASIBLE, r.message
    if r.status is ReachStatus.UNKNOWN:
        assert "not a proof" in r.message and r.counters["abstraction_refuted"] == 30
    # the proved bound is a bound on the real problem: a straight-ish 3-step path exists
    assert r.counters["proved_bound"] <= 4


def test_exact_sliver_abstraction_is_not_infeasible() -> None:
    """Without coarsening (all 400 slivers), the hop bound exceeds 30 but proves nothing."""
    p = ring(400)
    ab = abstract(p, coarsen=False)
    assert ab.exact and ab.n_regions >= 300
    r = solve(p, "lazy-smt", abstraction=ab, exact_segments=False)  # (auto: tests/reach/test_exact_auto.py)
    assert r.status is ReachStatus.UNKNOWN and "no plan through the abstraction" in r.message
    assert proved_horizon_bound(p, ab, 30) <= 4


def test_disconnected_goal_is_still_proved_infeasible() -> None:
    p = ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Box((6, 6), (10, 7)), Box((6, 7), (7, 10))),
        goal=Box((8, 8), (9, 9)),
        dynamics=single_integrator(2, 1.0),
        start=[1, 1],
        input_bound=1.0,
    )
    assert math.isinf(proved_horizon_bound(p, abstract(p), 200))
    # samples may jump over a wall: nothing is proved about them but the distance
    assert proved_horizon_bound(p, abstract(p), 200, segment_safe=False) == 7


def test_point_contacts_count_as_touching() -> None:
    """Two obstacles meeting at a corner: the regions on either side of that point
    touch (a segment-safe path may pass through it) though they share no edge."""
    p = ReachProblem(
        workspace=Box((0, 0), (4, 4)),
        obstacles=(Box((0, 2), (2, 4)), Box((2, 0), (4, 2))),
        goal=Box((3, 3), (3.5, 3.5)),
        dynamics=single_integrator(2, 1.0),
        start=[0.5, 0.5],
        input_bound=1.0,
    )
    ab = abstract(p)
    assert ab.n_regions == 2 and ab.adjacency == ((), ())
    assert touching(ab) == ((1,), (0,))
    assert proved_horizon_bound(p, ab, 50) == 3  # the distance bound: through the corner


@PROPS
@given(problems(), st.integers(3, 9), st.booleans())
def test_proved_bound_never_exceeds_a_found_horizon(p: ReachProblem, max_horizon: int, segment_safe: bool) -> None:
    """The proved bound is at most the true minimal horizon, which is at most the
    horizon of any validated trajectory (the paper's loop, and the region MILP)."""
    ab = abstract(p)
    bound = proved_horizon_bound(p, ab, max_horizon, segment_safe=segment_safe)
    for r in (
        solve(
            p,
            "lazy-smt",
            abstraction=ab,
            max_horizon=max_horizon,
            segment_safe=segment_safe,
            horizon_search="linear",
            exact_segments=False,
        ),
        solve(p, "milp", abstraction=ab, max_horizon=max_horizon, segment_safe=segment_safe),
    ):
        if r.status is ReachStatus.FOUND:
            assert r.validated is True
            assert bound <= r.horizon, (bound, r.horizon, r.planner)
        elif r.status is ReachStatus.INFEASIBLE:
            # the proved bound, or (samples only, regions covering the free space) the
            # planners' exact search, which tests/reach/test_exact_claims.py checks
            assert bound > max_horizon or (not segment_safe and ab.exact)


@given(st.integers(OUTER_VERTICES + 1, 2000), st.floats(0.1, 100), st.floats(0.2, 5), st.floats(0, 6.3))
def test_outer_polygon_contains_the_polygon(n: int, r: float, stretch: float, turn: float) -> None:
    ang = 2 * np.pi * np.arange(n) / n
    pts = np.stack([r * stretch * np.cos(ang), r * np.sin(ang)], axis=1)
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    poly = Polygon(tuple(map(tuple, (pts @ rot.T + 50).tolist())))
    out = outer_polygon(poly)
    assert len(out.vertices) <= OUTER_VERTICES
    inner, outer = ShPolygon(poly.vertices), ShPolygon(out.vertices)
    assert outer.is_valid and outer.contains(inner)
    assert outer.area <= inner.area * 1.01


def test_sweep_stopped_early_still_gives_a_bound(monkeypatch: pytest.MonkeyPatch) -> None:
    from plansynth.reach.families import maze
    from plansynth.reach.lazy.bounds import proved

    p = maze(1)
    full = proved_horizon_bound(p, abstract(p), 200)
    monkeypatch.setattr(proved, "SWEEP_MAX_WORK", 50)
    early = proved_horizon_bound(p, abstract(p), 200)
    assert 26 <= early < full == 38  # at least the distance bound, never more than the full sweep


def test_coarsened_abstraction_proves_only_the_distance_bound() -> None:
    """Around an outer polygon the regions miss part of the free space, so the sweep
    over them would prove nothing: only the distance bound is used."""
    p = issue_problem(200)
    ab = abstract(p)
    assert not ab.exact
    assert proved_horizon_bound(p, ab, 100) == proved_horizon_bound(p, ab, 100, segment_safe=False)

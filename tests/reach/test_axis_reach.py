"""The per-axis reachable sets of :mod:`plansynth.reach.lazy.axisreach` (the minimal
search's bound and tube), checked against the region MILP
(:func:`~plansynth.reach.planners.milp.solve_horizon`: an independent big-M formulation
over the same region graph and semantics, segment-safe or samples only over the
one-step region pairs): no horizon below the sets' bound has a plan, and a plan the
MILP finds at the bound visits only pairs of the tube."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.reach import ReachStatus, plan_lazy
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import LinearDynamics, integrator_chain
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.axisreach import AxisReach, _hull, _meet
from plansynth.reach.lazy.bounds import step_adjacency
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.planners.milp import solve_horizon
from plansynth.reach.problem import ReachProblem


def _sets(p: ReachProblem, segment_safe: bool = True):
    ab = abstract(p)
    adj = ab.adjacency if segment_safe else step_adjacency(p, ab)
    return ab, adj, AxisReach.build(p, ab, adj, ab.start_regions, ab.goal_regions, segment_safe=segment_safe)


@pytest.mark.parametrize("passages, minimum", [(1, 57), (2, 85)])
def test_the_maze_bound_is_the_minimum(passages: int, minimum: int) -> None:
    """maze-1/2: the sets' first goal step is the minimal horizon (the region MILP's:
    tests/reach/test_minimal_horizon.py), and the tube admits the planner's plan."""
    p = maze(passages)
    ab, adj, ar = _sets(p)
    assert ar is not None and ar.first_horizon(minimum + 10) == minimum
    tube = ar.tube(minimum)
    r = plan_lazy(p, options=LazyOptions(horizon_search="minimal", exact_segments=False), abstraction=ab)
    assert r.horizon == minimum and r.counters["reach_sets_bound"] == minimum
    assert all((t, i) in tube for t, i in enumerate(r.regions))
    assert len(tube) < 0.5 * (minimum + 1) * len(ab.regions)  # it does prune


def test_no_goal_step_below_the_limit_is_none() -> None:
    _, _, ar = _sets(maze(1))
    assert ar.first_horizon(56) is None and ar.tube(57) is None  # (swept only to 56)


def test_coupled_dynamics_are_not_swept() -> None:
    p = maze(1, order=3)  # three states per axis
    assert _sets(p)[2] is None
    base = maze(1)
    A = np.asarray(base.dynamics.A).copy()
    A[0, 1] = 0.1  # x's position moved by y's: the axes couple
    coupled = ReachProblem(
        workspace=base.workspace,
        obstacles=base.obstacles,
        goal=base.goal,
        dynamics=LinearDynamics(A, base.dynamics.B, base.dynamics.position),
        start=base.start,
        input_bound=base.input_bound,
        state_bounds=base.state_bounds,
    )
    assert _sets(coupled)[2] is None


def test_polygon_helpers() -> None:
    assert _hull([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5), (1, 0)]) == [(0, 0), (1, 0), (1, 1), (0, 1)]
    square = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)]
    got = _meet(square, [(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)])
    # (each cut relaxed by EPS: the sets only grow)
    assert got is not None and sorted((round(x, 5), round(y, 5)) for x, y in got) == [(1, 1), (1, 2), (2, 1), (2, 2)]
    assert _meet(square, [(3.0, 3.0), (4.0, 3.0), (4.0, 4.0)]) is None
    seg = _meet(square, [(-1.0, 1.0), (1.0, 1.0)])  # a segment: along its line, within its ends
    assert seg is not None and {round(x, 5) for x, _ in seg} == {0.0, 1.0} and {round(y, 5) for _, y in seg} == {1.0}


@st.composite
def worlds(draw) -> ReachProblem:
    """A 10 m square crossed by one or two 0.5-1 m walls, each with a gap (a turn near
    the gap couples the legs, as on the mazes), sometimes a block; a single or double
    integrator, at rest or moving at the start."""
    order = draw(st.sampled_from([2, 2, 1]))
    boxes = []
    ys = [3.0, 6.0] if draw(st.booleans()) else [draw(st.floats(3.0, 6.0))]
    for y in ys:
        g, w, h = draw(st.floats(0.0, 8.5)), draw(st.floats(0.6, 1.5)), draw(st.floats(0.5, 1.0))
        if g > 0.05:
            boxes.append(Box((-0.1, y), (g, y + h)))
        if g + w < 9.95:
            boxes.append(Box((g + w, y), (10.1, y + h)))
    if draw(st.booleans()):
        x0 = draw(st.floats(1.0, 8.0))
        boxes.append(Box((x0, 1.5), (x0 + 1.0, 2.3)))
    dyn = integrator_chain(order, 2, 0.5 if order == 2 else 1.0)
    start = np.zeros(dyn.n_states)
    start[:2] = (draw(st.floats(0.5, 9.5)), 0.8)
    if order == 2:
        start[2] = draw(st.sampled_from([0.0, 0.0, -0.5, 0.5]))
    gx = draw(st.floats(1.0, 9.0))
    vmax = [2.0] * (2 * (order - 1))
    return ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=tuple(boxes),
        goal=Box((gx - 0.6, 8.6), (gx + 0.6, 9.6)),
        dynamics=dyn,
        start=start,
        input_bound=1.0 if order == 2 else 0.8,
        state_bounds=Box(tuple([0.0, 0.0] + [-v for v in vmax]), tuple([10.0, 10.0] + vmax)),
        max_horizon=40,
    )


#: seconds for one region MILP of the soundness test: far above what they take (at most
#: ~1 s, most ~0.01 s), so that a time limit is not what decides a case
MILP_SECONDS = 300.0


def _bound_and_tube_hold(problem: ReachProblem, segment_safe: bool, tally: Counter) -> None:
    """One case of the soundness test: every horizon below the sets' first goal step b
    (the three below b, or below the sweep's limit when b is None) is infeasible for the
    region MILP, and a plan the MILP finds at b lies in the tube of b. ``tally`` counts
    what the MILP decided; a MILP out of time decides nothing (no agreement)."""
    try:
        ab, adj, ar = _sets(problem, segment_safe)
    except ValueError:  # the start or the goal inside an obstacle: not a problem
        return
    assert ar is not None
    b = ar.first_horizon(30)
    top = 30 if b is None else b
    for L in range(max(0, top - 3), top):
        status = solve_horizon(problem, ab, L, segment_safe=segment_safe, adjacency=adj, seconds=MILP_SECONDS)[0]
        assert status != "found", f"the region MILP has a plan of horizon {L}, below the sets' bound {b}"
        tally["refuted below the bound" if status == "infeasible" else "undecided"] += 1
    if b is None:
        return
    status, regions, _ = solve_horizon(problem, ab, b, segment_safe=segment_safe, adjacency=adj, seconds=MILP_SECONDS)
    tube = ar.tube(b)
    if status == "found" and tube is not None:
        assert all((t, i) in tube for t, i in enumerate(regions)), (b, regions)
        tally["plans in the tube"] += 1
    elif status == "unknown":
        tally["undecided"] += 1


def test_the_bound_and_the_tube_hold_for_the_region_milp() -> None:
    """Soundness, on random worlds: no horizon below the sets' bound has a plan, and a
    plan at the bound lies in the tube (:func:`_bound_and_tube_hold`), each case decided
    by the region MILP. From a start at rest feasibility is monotone, so the three
    horizons below the bound stand for all of them. The test asserts how many cases the
    MILP actually decided: a case it leaves undecided (out of time) is no agreement."""
    tally: Counter = Counter()

    @settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(worlds(), st.booleans())
    def cases(problem: ReachProblem, segment_safe: bool) -> None:
        _bound_and_tube_hold(problem, segment_safe, tally)

    cases()
    assert tally["undecided"] == 0, tally
    assert tally["refuted below the bound"] >= 30 and tally["plans in the tube"] >= 8, tally


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(worlds())
def test_the_minimal_search_with_the_sets_is_the_milp_minimum(problem: ReachProblem) -> None:
    """End to end (segment-safe): the horizon the minimal search proves minimal with the
    sets on is the region MILP's minimum: a plan there, none one step shorter."""
    try:
        ab = abstract(problem)
    except ValueError:
        return
    r = plan_lazy(problem, options=LazyOptions(horizon_search="minimal", exact_segments=False), abstraction=ab)
    if r.status is ReachStatus.FOUND:
        assert r.counters["minimal"] is True, r.message
        assert solve_horizon(problem, ab, r.horizon)[0] == "found"
        if r.horizon > 0:
            assert solve_horizon(problem, ab, r.horizon - 1)[0] == "infeasible"


def test_a_capped_sweep_is_a_bound_and_the_probes_continue(monkeypatch: pytest.MonkeyPatch) -> None:
    """At its work cap the sweep answers the step it reached (no plan below it), without
    the probe at it; the probes above prove the minimum as without the sets."""
    from plansynth.reach.lazy import axisreach

    monkeypatch.setattr(axisreach, "MAX_SWEEPS", 20)
    r = plan_lazy(maze(1), options=LazyOptions(horizon_search="minimal", exact_segments=False))
    assert r.status is ReachStatus.FOUND and r.horizon == 57 and r.counters["minimal"] is True
    assert r.counters["reach_sets_reached"] is False and 0 < r.counters["reach_sets_bound"] < 57
    assert "monotonicity" in r.message

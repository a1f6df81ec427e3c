"""The transit-time layer in front of CON-PLAN: legs of a plan, gap bounds against an
independent LP, and the lazy loop with and without it."""

from __future__ import annotations

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.reach.abstraction import abstract
from plansynth.reach.families import maze, random_workspace
from plansynth.reach.geometry import halfspaces
from plansynth.reach.highs import new_highs
from plansynth.reach.lazy.conflict import Feasible
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.lazy.transit import GOAL, START, TransitCheck
from plansynth.reach.problem import ReachProblem


def test_legs_of_a_plan() -> None:
    p = maze(1)
    tc = TransitCheck(ConPlan(p, abstract(p)), abstract(p))
    # visits: 0 at 0..1, 1 at 2..3, 2 at 4, 1 at 5, 2 at 6 (horizon 6)
    legs = tc.legs((0, 0, 1, 1, 2, 1, 2))
    assert sorted(legs) == sorted(
        [
            (START, 1, 0, 2),
            (0, 1, 1, 1),
            (START, 2, 0, 4),
            (0, 2, 1, 3),
            (1, 2, 3, 1),
            (0, 1, 1, 4),
            (2, 1, 4, 1),
            (0, 2, 1, 5),
            (1, 2, 5, 1),
            (0, GOAL, 1, 5),
            (1, GOAL, 5, 1),
        ]
    )


def leg_feasible(p: ReachProblem, regions, a: int, b: int, k: int, segment_safe: bool = True) -> bool:
    """An LP written from the definitions, independent of conplan: can the robot be in a
    (or at the start) at time 0 and in b (or the goal) at time k?"""
    dyn = p.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A), np.asarray(dyn.B)
    lo, hi = np.array(p.state_bounds.lo, float), np.array(p.state_bounds.hi, float)
    h = new_highs()  # the package's constructor: one HiGHS scheduler setting per process
    X = [[h.addVariable(lb=float(lo[i]), ub=float(hi[i])) for i in range(n)] for _ in range(k + 1)]
    U = [[h.addVariable(lb=-p.input_bound, ub=p.input_bound) for _ in range(m)] for _ in range(k)]
    for t in range(k):
        for i in range(n):
            rhs = sum(float(A[i, j]) * X[t][j] for j in range(n) if A[i, j] != 0)
            rhs = rhs + sum(float(B[i, j]) * U[t][j] for j in range(m) if B[i, j] != 0)
            h.addConstr(X[t + 1][i] - rhs == 0)

    def inside(H, hh, t: int) -> None:
        for row, c in zip(H, hh):
            h.addConstr(sum(float(v) * X[t][j] for v, j in zip(row, dyn.position)) <= float(c))

    if a == START:
        for i in range(n):
            h.addConstr(X[0][i] == float(p.start[i]))
    else:
        inside(regions[a].H, regions[a].h, 0)
        if segment_safe and k >= 1:
            inside(regions[a].H, regions[a].h, 1)
    if b == GOAL:
        inside(*halfspaces(p.goal), k)
    else:
        inside(regions[b].H, regions[b].h, k)
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kOptimal


@pytest.mark.parametrize("leg", [(0, 2), (2, 0), (START, 1), (START, 2), (0, GOAL), (1, GOAL)])
def test_first_gap_is_exact_near_the_box_bound(leg: tuple[int, int]) -> None:
    p = maze(1)
    ab = abstract(p)
    tc = TransitCheck(ConPlan(p, ab), ab)
    a, b = leg
    first = tc.first_gap(a, b)
    assert first >= tc.box_gap(a, b)
    for k in range(1, first):
        assert not leg_feasible(p, ab.regions, a, b, k), f"gap {k} of {leg} is feasible"
    assert leg_feasible(p, ab.regions, a, b, first)


def test_a_plan_that_jumps_a_corridor_too_fast_is_caught_without_conplan() -> None:
    p = maze(1)
    ab = abstract(p)
    tc = TransitCheck(ConPlan(p, ab), ab)
    plan = (0,) * 5 + (1,) + (2,) * 5  # region 2 five steps after the start: too early
    out = tc.check(plan)
    assert isinstance(out, tuple) and out
    assert tc.inner.stats.by_kind.get("plan", 0) == 0 and tc.plans_caught == 1
    # every conflict is a transit fact that the independent LP confirms
    for c in out:
        if c.anchored_start:
            ((t, r),) = c.literals
            assert not leg_feasible(p, ab.regions, START, r, t)


@pytest.mark.parametrize("n", [1, 2])
def test_the_transit_layer_saves_lps_and_keeps_answers(n: int) -> None:
    p = maze(n)
    with_t = plan_lazy(p, options=LazyOptions(transit=True, horizon_search="linear", exact_segments=False))
    without = plan_lazy(p, options=LazyOptions(transit=False, horizon_search="linear", exact_segments=False))
    assert with_t.status.value == without.status.value == "found"
    assert with_t.horizon == without.horizon  # both minimal: the layer only prunes infeasible plans
    assert with_t.counters["transit_conflicts"] > 0
    assert with_t.counters["lp_calls"] < without.counters["lp_calls"]


def test_feasible_plans_pass_through_to_conplan() -> None:
    p = maze(1)
    ab = abstract(p)
    r = plan_lazy(p)
    tc = TransitCheck(ConPlan(p, ab), ab)
    assert isinstance(tc.check(r.regions), Feasible)


def test_a_slow_chain_leaving_its_resting_start_is_bisected_exactly() -> None:
    # an order-8 chain needs far more steps into the first gap than the box bound says;
    # from a start at rest the leg is monotone, so galloping + bisection finds the first
    # feasible gap with fewer LPs than the scan, and every smaller gap is infeasible
    p = maze(1, order=8)
    ab = abstract(p)
    tc = TransitCheck(ConPlan(p, ab), ab)
    assert tc.start_at_rest
    box, first = tc.box_gap(START, 1), tc.first_gap(START, 1)
    assert first - box >= 8
    assert tc.lp_calls < first - box + 1
    for k in range(box, first):
        assert not leg_feasible(p, ab.regions, START, 1, k), f"gap {k} is feasible"
    assert leg_feasible(p, ab.regions, START, 1, first)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10_000))
def test_monotone_start_legs_agree_with_the_linear_scan(seed: int) -> None:
    p = random_workspace(seed, 3, polygons=False, order=2, dt=0.5)
    ab = abstract(p)
    fast = TransitCheck(ConPlan(p, ab), ab)
    slow = TransitCheck(ConPlan(p, ab), ab)
    slow.start_at_rest = False  # the scan, one LP per gap
    for b in range(len(ab.regions)):
        assert fast.first_gap(START, b) == slow.first_gap(START, b)


def test_a_moving_start_is_not_treated_as_monotone() -> None:
    p = maze(1)
    moving = ReachProblem(
        workspace=p.workspace,
        obstacles=p.obstacles,
        goal=p.goal,
        dynamics=p.dynamics,
        start=np.array([1.0, 1.0, 1.0, 0.5]),
        input_bound=p.input_bound,
        state_bounds=p.state_bounds,
        name="moving",
    )
    ab = abstract(moving)
    tc = TransitCheck(ConPlan(moving, ab), ab)
    assert not tc.start_at_rest
    first = tc.first_gap(START, 1)
    for k in range(tc.box_gap(START, 1), first):
        assert not leg_feasible(moving, ab.regions, START, 1, k)
    assert leg_feasible(moving, ab.regions, START, 1, first)


def test_a_start_leg_searched_per_axis_agrees_with_the_joint_scan() -> None:
    """Split LPs (an order-5 chain on a maze of boxes): the first gap of a start leg is
    the largest of the axes' own first gaps, each searched with that axis's LP alone;
    the scan asks the whole LP at every gap."""
    p = maze(2, order=5)
    ab = abstract(p)
    fast = TransitCheck(ConPlan(p, ab), ab)
    assert fast.inner.span_parts() == 2
    slow = TransitCheck(ConPlan(p, ab), ab)
    slow.start_at_rest = False  # the scan, one LP of both axes per gap
    for b in range(len(ab.regions)):
        assert fast.first_gap(START, b) == slow.first_gap(START, b), b
    with pytest.raises(ValueError, match="split"):
        ConPlan(maze(1), abstract(maze(1))).refutes(TransitCheck.leg(START, 1, 5, N=5), part=0)

"""The region MILP: the cross-check oracle of the lazy planner."""

from __future__ import annotations

import numpy as np
import pytest

from plansynth.budget import Budget
from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.planners.milp import MilpOptions, _big_m, plan_milp, solve_horizon
from plansynth.reach.problem import ReachProblem


def test_big_m_is_the_largest_violation_over_the_box() -> None:
    H = np.array([[1.0, 0.0], [0.0, -1.0], [0.6, 0.8]])
    h = np.array([2.0, -1.0, 3.0])
    M = _big_m(H, h, np.array([0.0, 0.0]), np.array([10.0, 5.0]))
    assert M.tolist() == pytest.approx([8.0, 1.0, 6.0 + 4.0 - 3.0])
    # never negative: a row satisfied everywhere needs no relaxation
    assert _big_m(np.array([[1.0, 0.0]]), np.array([20.0]), np.zeros(2), np.ones(2)).tolist() == [0.0]


def corridor() -> ReachProblem:
    return ReachProblem(
        workspace=Box((0, 0), (10, 4)),
        obstacles=(Box((4, 0), (5, 3)),),
        goal=Box((8, 0.5), (9, 1.5)),
        dynamics=single_integrator(2, 1.0),
        start=[1, 1],
        input_bound=1.0,
    )


def test_milp_finds_the_shortest_horizon_and_a_validated_trajectory() -> None:
    p = corridor()
    r = solve(p, "milp")
    assert r.status is ReachStatus.FOUND and r.validated and r.segment_safe
    ab = abstract(p)
    assert solve_horizon(p, ab, r.horizon - 1)[0] == "infeasible"
    assert solve(p, horizon_search="linear", exact_segments=False).horizon == r.horizon
    # the default window search may stop above the shortest horizon, and then says so
    lazy = solve(p)
    assert lazy.horizon >= r.horizon
    assert lazy.horizon == r.horizon or not lazy.counters["minimal"]


def test_milp_samples_only_is_never_longer() -> None:
    p = corridor()
    seg = plan_milp(p)
    samples = solve(p, "milp", segment_safe=False)
    assert samples.status is ReachStatus.FOUND and samples.validated and samples.guarantee == "samples"
    assert samples.horizon <= seg.horizon


def test_milp_infeasible_up_to_max_horizon_by_the_proved_bound() -> None:
    r = plan_milp(maze(1), options=MilpOptions(max_horizon=30))  # every trajectory needs 38 steps or more
    assert r.status is ReachStatus.INFEASIBLE and r.horizon == 30
    assert r.counters["proved_bound"] == 31 and r.counters["milp_calls"] == 0  # (the sweep stops at 31)


def test_milp_refuting_the_abstraction_is_not_infeasible() -> None:
    r = plan_milp(maze(1), options=MilpOptions(max_horizon=45))
    assert r.status is ReachStatus.UNKNOWN and r.horizon == 45
    assert r.counters["milp_calls"] == 45 - 2 + 1  # every horizon from the BFS distance 2
    assert r.counters["abstraction_refuted"] == 45 and "not a proof" in r.message


def test_milp_proved_bound_is_tight_on_the_corridor() -> None:
    r = plan_milp(corridor())
    assert r.status is ReachStatus.FOUND and r.counters["proved_bound"] == r.horizon == 7


def test_milp_with_a_start_horizon_does_not_claim_infeasibility() -> None:
    r = plan_milp(maze(1), options=MilpOptions(start_horizon=40, max_horizon=42))
    assert r.status is ReachStatus.UNKNOWN and "shorter ones not tried" in r.message


def test_milp_budget() -> None:
    r = plan_milp(maze(2), Budget(iterations=1))
    assert r.status is ReachStatus.UNKNOWN

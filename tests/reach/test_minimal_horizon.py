"""``horizon_search="minimal"``: the window search, then the horizon found is proved
minimal (every shorter horizon refuted, by bisection when the start is at rest). Checked
against the region MILP (an independent formulation over the same region graph) and
against the paper's linear search."""

from __future__ import annotations

import pytest

from plansynth.reach import ReachStatus, plan_lazy
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import double_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.loop import compressed
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.planners.milp import solve_horizon
from plansynth.reach.problem import ReachProblem
from plansynth.reach.validate import validate


def test_minimal_on_maze_1_is_the_milp_minimum() -> None:
    p = maze(1)
    window = plan_lazy(p)
    r = plan_lazy(p, horizon_search="minimal")
    assert window.counters["minimal"] is False and window.horizon > r.horizon  # the window's top, not minimal
    assert r.status is ReachStatus.FOUND and r.counters["minimal"] is True and r.counters["minimal_probes"] >= 1
    assert "proved minimal" in r.message and "monotonicity" in r.message
    assert validate(p, r.trajectory, require_segment_safe=True).ok
    ab = abstract(p)
    assert solve_horizon(p, ab, r.horizon)[0] == "found"
    assert solve_horizon(p, ab, r.horizon - 1)[0] == "infeasible"


def moving_start() -> ReachProblem:
    """A wall with a gap; the robot starts moving away from it (not at rest: no
    monotonicity, so the window below the plan is refuted as a whole)."""
    return ReachProblem(
        workspace=Box((0, 0), (8, 8)), obstacles=(Box((0, 3.5), (6, 4.5)),), goal=Box((1, 6), (2, 7)),
        dynamics=double_integrator(2, 0.5), start=[1, 1, -0.5, 0], input_bound=1.0,
        state_bounds=Box((0, 0, -2, -2), (8, 8, 2, 2)), max_horizon=60,
    )


@pytest.mark.parametrize("problem", [maze(2), moving_start()], ids=["maze-2", "moving-start"])
def test_minimal_equals_the_linear_search(problem: ReachProblem) -> None:
    linear = plan_lazy(problem, horizon_search="linear")
    r = plan_lazy(problem, horizon_search="minimal")
    assert linear.counters["minimal"] is True and r.counters["minimal"] is True
    assert r.horizon == linear.horizon
    assert ("monotonicity" in r.message) == problem.starts_at_rest


def test_minimal_within_an_iteration_budget_is_not_proved() -> None:
    from plansynth.budget import Budget

    r = plan_lazy(maze(2), Budget(iterations=3), horizon_search="minimal")
    assert r.status is ReachStatus.FOUND and r.counters["minimal"] is False and "not proved minimal" in r.message


def test_minimal_is_an_option_value() -> None:
    assert LazyOptions(horizon_search="minimal").horizon_search == "minimal"


def test_compressed_keeps_the_route_and_every_stay() -> None:
    plan = (0,) * 10 + (1,) * 2 + (2,) * 10
    for h in range(2, 21):
        c = compressed(plan, h)
        assert len(c) == h + 1 and c[0] == 0 and c[-1] == 2
        assert [r for i, r in enumerate(c) if i == 0 or c[i - 1] != r] == [0, 1, 2]

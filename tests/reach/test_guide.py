"""The reference sequence that DIS-PLAN prefers: a route, evenly timed; only a hint."""

from __future__ import annotations

import pytest

from plansynth.reach.decompose import abstract
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.families import cluttered, maze
from plansynth.reach.guide import reference_plan, route
from plansynth.reach.lazy import plan_lazy
from plansynth.reach.problem import Box, ReachProblem
from plansynth.reach.validate import validate


@pytest.mark.parametrize("problem", [maze(1), maze(2), maze(3), maze(4), cluttered()], ids=lambda p: p.name)
def test_the_reference_walks_the_region_graph_from_start_to_goal(problem: ReachProblem) -> None:
    ab = abstract(problem)
    for horizon in (40, 150):
        ref = reference_plan(problem, ab, horizon)
        assert ref is not None and len(ref) == horizon + 1
        assert ref[0] in ab.start_regions and ref[-1] in ab.goal_regions
        assert all(b == a or b in ab.adjacency[a] for a, b in zip(ref, ref[1:]))
    # the maze route visits every region once, in order
    if problem.name.startswith("maze"):
        assert route(problem, ab) == list(range(len(ab.regions)))


def test_no_route_to_a_walled_off_goal() -> None:
    p = ReachProblem(workspace=Box((0, 0), (10, 10)), obstacles=(Box((6, 6), (10, 7)), Box((6, 7), (7, 10))),
                     goal=Box((8, 8), (9, 9)), dynamics=single_integrator(2, 1.0), start=[1, 1], input_bound=1.0)
    ab = abstract(p)
    assert route(p, ab) is None and reference_plan(p, ab, 10) is None


@pytest.mark.parametrize("guided", [True, False])
def test_guidance_changes_the_search_not_the_answer(guided: bool) -> None:
    p = maze(2)
    r = plan_lazy(p, guided=guided, horizon_search="linear")
    assert r.status.value == "found" and r.counters["minimal"] is True
    assert validate(p, r.trajectory, require_segment_safe=True).ok
    assert r.horizon == plan_lazy(p, guided=not guided, horizon_search="linear").horizon

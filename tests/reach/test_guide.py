"""The reference sequence that DIS-PLAN prefers: a route, evenly timed; only a hint."""

from __future__ import annotations

import pytest

from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.families import cluttered, maze
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.guide import departure, reference_plan, route
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.problem import ReachProblem
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
    p = ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Box((6, 6), (10, 7)), Box((6, 7), (7, 10))),
        goal=Box((8, 8), (9, 9)),
        dynamics=single_integrator(2, 1.0),
        start=[1, 1],
        input_bound=1.0,
    )
    ab = abstract(p)
    assert route(p, ab) is None and reference_plan(p, ab, 10) is None


@pytest.mark.parametrize("guided", [True, False])
def test_guidance_changes_the_search_not_the_answer(guided: bool) -> None:
    p = maze(2)
    r = plan_lazy(p, options=LazyOptions(guided=guided, horizon_search="linear", exact_segments=False))
    assert r.status.value == "found" and r.counters["minimal"] is True
    assert validate(p, r.trajectory, require_segment_safe=True).ok
    assert (
        r.horizon
        == plan_lazy(p, options=LazyOptions(guided=not guided, horizon_search="linear", exact_segments=False)).horizon
    )


@pytest.mark.parametrize("depart", [40, 55])
def test_depart_holds_the_first_leg_back_and_keeps_the_route(depart: int) -> None:
    p = maze(2)
    ab = abstract(p)
    path = route(p, ab)
    even = reference_plan(p, ab, 90)
    held = reference_plan(p, ab, 90, depart=depart)
    assert even.index(path[1]) < depart  # constant speed would enter earlier
    assert held.index(path[1]) == depart
    assert held[0] in ab.start_regions and held[-1] in ab.goal_regions
    assert all(b == a or b in ab.adjacency[a] for a, b in zip(held, held[1:]))
    assert [r for i, r in enumerate(held) if i == 0 or r != held[i - 1]] == path


def test_depart_never_rushes_the_first_leg() -> None:
    p = maze(2)
    ab = abstract(p)
    even = reference_plan(p, ab, 90)
    assert reference_plan(p, ab, 90, depart=2) == even
    assert departure(20) == 21 and departure(58) == 61


@pytest.mark.parametrize("n", [1, 4])
def test_the_first_plan_is_the_reference_at_the_window_top(n: int) -> None:
    """DIS-PLAN's phases describe the whole reference plan: its regions, its end at the
    window's top (the phases of the ends-before ladder, also when prefer() comes before the
    first solve) and, beyond 8 regions (maze-4 has 9: the sequential counter), the
    auxiliary variables of the exactly-one encoding. On the mazes that plan is realisable,
    so the loop ends after one iteration and one plan LP, at the window's top (the loop
    alone: without the timed route, which plans these mazes before DIS-PLAN is built)."""
    p = maze(n)
    r = plan_lazy(p, options=LazyOptions(timed_route=False))
    first = r.counters["first_horizon"]
    top = first + int(0.25 * first)
    assert r.counters["iterations"] == 1 and r.horizon == top
    assert r.counters["lp_calls_by_kind"].get("plan") == 1
    assert validate(p, r.trajectory, require_segment_safe=True).ok

"""``horizon_search="minimal"``: the window search, then the horizon found is proved
minimal (every shorter horizon refuted, by bisection when the start is at rest). Checked
against the region MILP (an independent formulation over the same region graph) and
against the paper's linear search."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.reach import ReachStatus, plan_lazy
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import double_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.displan import DisPlan, RegionGraph
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.minimal import compressed, retimed
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.transit import TransitCheck
from plansynth.reach.planners.milp import solve_horizon
from plansynth.reach.problem import ReachProblem
from plansynth.reach.validate import validate


def test_minimal_on_maze_1_is_the_milp_minimum() -> None:
    p = maze(1)
    window = plan_lazy(p)
    r = plan_lazy(
        p, options=LazyOptions(horizon_search="minimal", reach_sets=False, exact_segments=False)
    )  # the probes alone
    assert window.counters["minimal"] is False and window.horizon > r.horizon  # the window's top, not minimal
    assert r.status is ReachStatus.FOUND and r.counters["minimal"] is True and r.counters["minimal_probes"] >= 1
    assert "proved minimal" in r.message and "monotonicity" in r.message
    assert "reach_sets_bound" not in r.counters
    assert validate(p, r.trajectory, require_segment_safe=True).ok
    ab = abstract(p)
    assert solve_horizon(p, ab, r.horizon)[0] == "found"
    assert solve_horizon(p, ab, r.horizon - 1)[0] == "infeasible"


def moving_start() -> ReachProblem:
    """A wall with a gap; the robot starts moving away from it (not at rest: no
    monotonicity, so the window below the plan is refuted as a whole)."""
    return ReachProblem(
        workspace=Box((0, 0), (8, 8)),
        obstacles=(Box((0, 3.5), (6, 4.5)),),
        goal=Box((1, 6), (2, 7)),
        dynamics=double_integrator(2, 0.5),
        start=[1, 1, -0.5, 0],
        input_bound=1.0,
        state_bounds=Box((0, 0, -2, -2), (8, 8, 2, 2)),
        max_horizon=60,
    )


@pytest.mark.parametrize("reach_sets", [True, False], ids=["reach-sets", "probes"])
@pytest.mark.parametrize("problem", [maze(2), moving_start()], ids=["maze-2", "moving-start"])
def test_minimal_equals_the_linear_search(problem: ReachProblem, reach_sets: bool) -> None:
    linear = plan_lazy(problem, options=LazyOptions(horizon_search="linear", exact_segments=False))
    r = plan_lazy(problem, options=LazyOptions(horizon_search="minimal", reach_sets=reach_sets, exact_segments=False))
    assert linear.counters["minimal"] is True and r.counters["minimal"] is True
    assert r.horizon == linear.horizon
    if reach_sets:  # the sets prove it: their bound is the minimum (one probe, under the tube), or,
        # when the first plan (the timed route) is already minimal, no shorter horizon reaches the goal
        bound, probes = r.counters["reach_sets_bound"], r.counters["minimal_probes"]
        assert (bound == r.horizon and probes == 1) or (bound is None and probes == 0), (bound, probes)
        assert "per-axis reachable sets" in r.message
    else:
        assert ("monotonicity" in r.message) == problem.starts_at_rest


def test_minimal_within_an_iteration_budget_is_not_proved() -> None:
    from plansynth.budget import Budget

    r = plan_lazy(maze(2), Budget(iterations=3), options=LazyOptions(horizon_search="minimal", exact_segments=False))
    assert r.status is ReachStatus.FOUND and r.counters["minimal"] is False and "not proved minimal" in r.message


def test_minimal_is_an_option_value() -> None:
    assert LazyOptions(horizon_search="minimal").horizon_search == "minimal"


def test_compressed_keeps_the_route_and_every_stay() -> None:
    plan = (0,) * 10 + (1,) * 2 + (2,) * 10
    for h in range(2, 21):
        c = compressed(plan, h)
        assert len(c) == h + 1 and c[0] == 0 and c[-1] == 2
        assert [r for i, r in enumerate(c) if i == 0 or c[i - 1] != r] == [0, 1, 2]


def _stays(plan) -> list[int]:
    return [r for i, r in enumerate(plan) if i == 0 or plan[i - 1] != r]


@pytest.mark.parametrize("passages", [1, 3])
def test_retimed_lowers_a_plan_by_lps_alone(passages: int) -> None:
    """The re-timing before the probes: no SAT call, a realised plan through the same
    route, shorter than the window's, never below the minimum (the region MILP's)."""
    p = maze(passages)
    ab = abstract(p)
    window = plan_lazy(p, abstraction=ab)
    displan = DisPlan(RegionGraph.from_abstraction(ab), waits_at_start=True)
    theory = TransitCheck(ConPlan(p, ab, counterexample="trivial", generalize=True, minimize=True), ab)
    found = LoopOutcome(ReachStatus.FOUND, window.horizon, "found", window.trajectory, window.regions, minimal=False)
    timings = {"lp": 0.0}
    out = retimed(displan, theory, found, 0, Budget(seconds=60).clock(), timings)
    assert displan.sat_calls == 0 and timings["lp"] > 0
    assert out.status is ReachStatus.FOUND and out.minimal is False
    assert out.horizon < window.horizon and len(out.regions) == out.horizon + 1
    assert _stays(out.regions) == _stays(window.regions)
    assert validate(p, out.trajectory, require_segment_safe=True).ok
    assert solve_horizon(p, ab, out.horizon)[0] == "found"
    minimum = {1: 57, 3: 113}[passages]  # the linear search's and the region MILP's (test above: maze-1)
    assert out.horizon >= minimum
    displan.delete()


def test_retimed_within_no_budget_keeps_the_plan() -> None:
    p = maze(1)
    ab = abstract(p)
    window = plan_lazy(p, abstraction=ab)
    displan = DisPlan(RegionGraph.from_abstraction(ab))
    theory = TransitCheck(ConPlan(p, ab), ab)
    found = LoopOutcome(ReachStatus.FOUND, window.horizon, "found", window.trajectory, window.regions, minimal=False)
    out = retimed(displan, theory, found, 0, Budget(seconds=1e-9).clock(), {"lp": 0.0})
    assert out is found
    displan.delete()


@st.composite
def walls(draw) -> ReachProblem:
    """A maze-like world: a double integrator at rest (sometimes moving) below one or
    two 1 m walls across a 20 m square, each with a gap; long enough that the first
    window's plan lies several steps above the minimum (re-timing, probes)."""
    size = 20.0
    ys = sorted(draw(st.lists(st.floats(4.0, 15.0), min_size=1, max_size=2)))
    boxes: list = []
    last = -10.0
    for y in ys:
        if y - last < 3.0:
            continue
        last = y
        g = draw(st.floats(0.5, size - 2.5))
        w = draw(st.floats(1.0, 2.0))
        if g > 0.1:
            boxes.append(Box((-0.1, y), (g, y + 1.0)))
        boxes.append(Box((g + w, y), (size + 0.1, y + 1.0)))
    vx = draw(st.sampled_from([0.0, 0.0, 0.0, -0.5, 0.5]))
    sx, gx = draw(st.floats(1.0, size - 1.0)), draw(st.floats(1.5, size - 1.5))
    return ReachProblem(
        workspace=Box((0, 0), (size, size)),
        obstacles=tuple(boxes),
        goal=Box((gx - 1.0, size - 2.0), (gx + 1.0, size - 0.5)),
        dynamics=double_integrator(2, 0.5),
        start=[sx, 1, vx, 0],
        input_bound=1.0,
        state_bounds=Box((0, 0, -2, -2), (size, size, 2, 2)),
        max_horizon=120,
    )


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(walls())
def test_minimal_is_the_region_milp_minimum(problem: ReachProblem) -> None:
    """On random walls with gaps (start at rest: probes; moving: windows), the horizon
    the minimal search proves minimal is the region MILP's minimum: a plan at h, none at
    h - 1 (an independent formulation over the same region graph)."""
    r = plan_lazy(problem, Budget(seconds=60), options=LazyOptions(horizon_search="minimal", exact_segments=False))
    assert r.status is ReachStatus.FOUND and r.counters["minimal"] is True, r.message
    assert validate(problem, r.trajectory, require_segment_safe=True).ok
    ab = abstract(problem)
    assert solve_horizon(problem, ab, r.horizon)[0] == "found"
    if r.horizon > 0:
        assert solve_horizon(problem, ab, r.horizon - 1)[0] == "infeasible", r.horizon


class _TimedStays:
    """A theory over the line 0 - 1 - 2 (start 0, goal 2) that realises exactly the plans
    0^a 1^b 2^c with (a, b, c) in ``FEASIBLE`` (upward closed in a: waiting at the
    start keeps a plan feasible, so feasibility is monotone in the horizon), and
    refutes the others with sound conflicts: a step back, or the whole plan."""

    FEASIBLE = (
        lambda a, b, c: a >= 8 and b == 5 and c >= 4,
        lambda a, b, c: a >= 5 and b == 2 and c == 7,
        lambda a, b, c: a >= 6 and b == 3 and c == 3,
    )  # shortest: 6 + 3 + 3 steps, horizon 11

    def __init__(self) -> None:
        self.checked: list[int] = []

    def check(self, regions):
        from plansynth.reach.lazy.conflict import Conflict, Feasible

        N = len(regions) - 1
        self.checked.append(N)
        for t in range(N):
            if regions[t + 1] < regions[t]:
                return Conflict(
                    ((t, regions[t]), (t + 1, regions[t + 1])), anchored_start=False, anchored_goal=False, horizon=N
                )
        a, b, c = (sum(1 for r in regions if r == k) for k in (0, 1, 2))
        if a and b and c and any(f(a, b, c) for f in self.FEASIBLE):
            return Feasible(None)  # type: ignore[arg-type]
        return Conflict(tuple(enumerate(regions)), anchored_start=True, anchored_goal=True, horizon=N)


def test_prove_minimal_finds_the_least_horizon_past_a_stuck_retiming() -> None:
    """The search logic alone, against a theory whose answers are known: the window's
    plan (horizon 17) re-times only to 16 (every shorter stay breaks it), probes find
    other timings below, and the minimum 11 is proved by refuting 10 (monotone)."""
    from plansynth.reach.lazy.loop import lazy_loop
    from plansynth.reach.lazy.minimal import prove_minimal

    graph = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(2,))
    displan = DisPlan(graph, waits_at_start=True)
    theory = _TimedStays()
    clock, timings = Budget(seconds=120).clock(), {"sat": 0.0, "lp": 0.0}
    start = (0,) * 9 + (1,) * 5 + (2,) * 4
    displan.prefer(start)
    first = lazy_loop(displan, theory, [(2, 17)], clock, timings, None, lambda H: start)
    assert first.status is ReachStatus.FOUND and first.horizon == 17
    out, probes = prove_minimal(displan, theory, first, 2, clock, timings, monotone=True)
    assert out.status is ReachStatus.FOUND and out.minimal is True and out.horizon == 11, out
    assert probes >= 2 and 16 in theory.checked  # the re-timing stopped at 16
    a, b, c = (out.regions.count(k) for k in (0, 1, 2))
    assert any(f(a, b, c) for f in _TimedStays.FEASIBLE)
    for h in range(2, 11):  # every shorter horizon closed, none realisable
        assert h in displan.closed
        assert not any(
            f(a, b, h + 1 - a - b) for f in _TimedStays.FEASIBLE for a in range(1, h) for b in range(1, h + 1 - a)
        )
    displan.delete()

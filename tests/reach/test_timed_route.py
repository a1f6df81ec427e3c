"""The timed route (:mod:`plansynth.reach.lazy.timed`): the first plan the lazy planner
checks, its stays timed by an LP over crossing points and repaired where CON-PLAN's slack
LP finds them too tight. Its plans are DIS-PLAN plans that validate, near the proved
minima on the mazes, never claimed minimal; where it gives up, the loop decides."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.reach.abstraction import abstract
from plansynth.reach.families import gcs_maze, maze, random_workspace
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.guide import route
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.lazy.timed import crossing_times, stays_plan, timed_route
from plansynth.reach.result import ReachStatus
from plansynth.reach.validate import validate

#: horizons proved minimal through the decomposition (lazy-smt-minimal; RESULTS.md)
MINIMA = {1: 57, 2: 85, 3: 113, 4: 141}


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_mazes_are_planned_near_their_minimum_without_sat(n: int) -> None:
    p = maze(n)
    r = plan_lazy(p, Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and "the timed route" in r.message
    assert r.counters["sat_calls"] == 0 and r.counters["minimal"] is False
    assert MINIMA[n] <= r.horizon <= MINIMA[n] + 4  # within 3% of the proved minimum
    assert validate(p, r.trajectory, require_segment_safe=True).ok
    a = abstract(p)
    regs = r.regions
    assert regs[0] in a.start_regions and regs[-1] in a.goal_regions
    assert all(b == c or c in a.adjacency[b] for b, c in zip(regs, regs[1:]))


def test_the_gcs_maze_of_50_is_planned_far_below_the_window_top() -> None:
    """The window search returned 1,146 steps, shortened to 667, after 772,000 clauses;
    the timed route plans it with no SAT call in a few repair rounds."""
    p = gcs_maze(50)
    r = plan_lazy(p, Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.counters["sat_calls"] == 0
    assert r.horizon <= 430 and r.counters["timed_route_rounds"] <= 8
    assert validate(p, r.trajectory, require_segment_safe=True).ok


def test_violations_are_zero_exactly_on_a_realised_plan() -> None:
    p = maze(1)
    a = abstract(p)
    cp = ConPlan(p, a, generalize=True)
    path = route(p, a)
    rushed = stays_plan(path, crossing_times(p, a, path))  # full speed from rest: too fast
    slack, realised = cp.violations(rushed, 1e-9)
    assert realised is None and slack.max() > 0.1
    good = plan_lazy(p).regions
    slack, realised = cp.violations(good, 1e-7)
    assert slack.max() <= 1e-7 and realised is not None
    assert validate(p, realised.trajectory, require_segment_safe=True).ok


def test_stays_plan_follows_the_route() -> None:
    rng = np.random.default_rng(0)
    for _ in range(50):
        path = tuple(int(x) for x in rng.choice(100, size=int(rng.integers(2, 8)), replace=False))
        stays = rng.uniform(0.2, 5.0, size=len(path))
        plan = stays_plan(path, stays)
        runs = [plan[0]] + [b for a, b in zip(plan, plan[1:]) if b != a]
        assert tuple(runs) == path and plan[-1] == plan[-2] == path[-1]
        assert abs((len(plan) - 1) - max(np.round(np.cumsum(stays))[-1], len(path))) <= len(path)


def test_it_gives_up_and_the_loop_decides() -> None:
    """Too short a max_horizon for the timed plan: no timed route, the loop runs (and
    here refutes every horizon through the abstraction, as without it)."""
    p = maze(1)
    a = abstract(p)
    out = timed_route(p, a, route(p, a), ConPlan(p, a), Budget().clock(), {}, max_horizon=40)
    assert out is None
    r = plan_lazy(p, options=LazyOptions(max_horizon=55, lower_bound=False, exact_segments=False))
    assert r.status is ReachStatus.UNKNOWN and r.counters["sat_calls"] > 0


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10_000), st.sampled_from([1, 2]))
def test_every_timed_plan_validates(seed: int, order: int) -> None:
    """Random workspaces (boxes and non-convex polygons): whatever the timed route
    returns is a DIS-PLAN plan whose trajectory the validator accepts, segment by segment,
    and never shorter than the proved minimum through the decomposition."""
    p = random_workspace(seed, 4, order=order, dt=0.5 if order == 2 else 1.0)
    a = abstract(p)
    path = route(p, a)
    out = timed_route(p, a, path, ConPlan(p, a, generalize=True), Budget(seconds=30).clock(), {})
    if out is None:
        return
    assert out.status is ReachStatus.FOUND and out.minimal is False
    assert validate(p, out.trajectory, require_segment_safe=True).ok
    assert all(b == c or c in a.adjacency[b] for b, c in zip(out.regions, out.regions[1:]))
    m = plan_lazy(p, Budget(seconds=60), LazyOptions(horizon_search="minimal", exact_segments=False))
    if m.status is ReachStatus.FOUND and m.counters.get("minimal"):
        assert m.horizon <= out.horizon

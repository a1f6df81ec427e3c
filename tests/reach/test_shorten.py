"""Shortening the timed route's plan (:mod:`plansynth.reach.lazy.shorten`): the shortened
plan keeps the route's regions, validates, is never longer than the plan it started
from and is never claimed minimal; ``shorten=0`` gives the timed route's plan."""

from __future__ import annotations

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
from plansynth.reach.lazy.shorten import plan_of, runs_of, shorten_plan
from plansynth.reach.lazy.timed import timed_route
from plansynth.reach.result import ReachStatus
from plansynth.reach.validate import validate
from plansynth.reach.oracle import oracle_lp


def _check(p, a, long, short) -> None:
    assert short.status is ReachStatus.FOUND and short.minimal is False
    assert short.horizon <= long.horizon and len(short.regions) == short.horizon + 1
    assert tuple(runs_of(short.regions)[0]) == tuple(runs_of(long.regions)[0])  # the same regions, in order
    assert validate(p, short.trajectory, require_segment_safe=True).ok


@pytest.mark.parametrize("n", [1, 4])
def test_a_maze_plan_shortened_validates(n: int) -> None:
    p = maze(n)
    a = abstract(p)
    cp = ConPlan(p, a, generalize=True)
    long = timed_route(p, a, route(p, a), cp, Budget().clock(), {})
    counters: dict = {}
    short = shorten_plan(cp, long, Budget().clock(), 10.0, counters=counters)
    _check(p, a, long, short)
    assert counters["shortened_from"] == long.horizon and counters["shorten_lps"] > 0


def test_shorten_zero_gives_the_timed_routes_plan() -> None:
    p = gcs_maze(20)  # (249 regions: the planner shortens above 200)
    off = plan_lazy(p, Budget(seconds=60), LazyOptions(shorten=0))
    on = plan_lazy(p, Budget(seconds=60))
    a = abstract(p)
    cp = ConPlan(p, a, generalize=True)
    again = timed_route(p, a, route(p, a), cp, Budget().clock(), {}, first_leg=2)
    assert "shorten_lps" not in off.counters and "shortened" not in off.message
    assert tuple(off.regions) == tuple(again.regions)
    assert on.status is ReachStatus.FOUND and on.horizon <= off.horizon and on.counters["minimal"] is False
    assert validate(p, on.trajectory, require_segment_safe=True).ok
    # the bench's oracle LP reads a shortened plan as any other: one region per sample
    lim = oracle_lp(p, on.regions, abstraction=a)
    assert lim is not None and lim.feasible


def test_the_gcs_maze_of_50_gets_shorter() -> None:
    p = gcs_maze(50)
    r = plan_lazy(p, Budget(seconds=120), LazyOptions(shorten=20))
    assert r.status is ReachStatus.FOUND and r.counters["shortened_from"] == 423
    assert r.horizon <= 400 and r.counters["minimal"] is False
    assert validate(p, r.trajectory, require_segment_safe=True).ok


def test_nothing_to_shorten_returns_the_plan() -> None:
    assert plan_of(*runs_of((2, 2, 5))) == (2, 2, 5)
    p = maze(1)
    a = abstract(p)
    cp = ConPlan(p, a, generalize=True)
    long = timed_route(p, a, route(p, a), cp, Budget().clock(), {})
    assert shorten_plan(cp, long, Budget().clock(), 0.0) is long


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10_000), st.sampled_from([1, 2]))
def test_every_shortened_plan_validates(seed: int, order: int) -> None:
    """Random workspaces (boxes and non-convex polygons): whatever the pass keeps is a
    DIS-PLAN plan through the same regions whose trajectory the validator accepts."""
    p = random_workspace(seed, 4, order=order, dt=0.5 if order == 2 else 1.0)
    a = abstract(p)
    cp = ConPlan(p, a, generalize=True)
    long = timed_route(p, a, route(p, a), cp, Budget(seconds=30).clock(), {})
    if long is None:
        return
    short = shorten_plan(cp, long, Budget(seconds=30).clock(), 5.0)
    _check(p, a, long, short)
    assert all(b == c or c in a.adjacency[b] for b, c in zip(short.regions, short.regions[1:]))

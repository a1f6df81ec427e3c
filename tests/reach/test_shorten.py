"""Shortening the timed route's plan (:mod:`plansynth.reach.lazy.shorten`) with the
prism LP (:mod:`plansynth.reach.lazy.prismlp`): the shortened plan keeps the route's
regions in order (some thin boxes skipped), validates, is never longer than the plan it
started from and is never claimed minimal; ``shorten=0`` gives the timed route's plan;
every prism lies in the union of its regions."""

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
from plansynth.reach.lazy.prismlp import PrismLP
from plansynth.reach.lazy.shorten import plan_of, runs_of, shorten_plan
from plansynth.reach.lazy.timed import timed_route
from plansynth.reach.result import ReachStatus
from plansynth.reach.validate import validate


def _is_subsequence(short: np.ndarray, long: np.ndarray) -> bool:
    it = iter(long.tolist())
    return all(any(x == y for y in it) for x in short.tolist())


def _check(p, long, short) -> None:
    minimal = short.counters["minimal"] if hasattr(short, "counters") else short.minimal
    assert short.status is ReachStatus.FOUND and minimal is False
    assert short.horizon <= long.horizon and len(short.regions) == short.horizon + 1
    assert _is_subsequence(runs_of(short.regions)[0], runs_of(long.regions)[0])  # the route's regions, in order
    assert runs_of(short.regions)[0][0] == runs_of(long.regions)[0][0]
    assert runs_of(short.regions)[0][-1] == runs_of(long.regions)[0][-1]
    assert validate(p, short.trajectory, require_segment_safe=True).ok


def test_the_gcs_maze_of_20_gets_shorter_and_validates() -> None:
    p = gcs_maze(20)  # (249 regions: the planner shortens above 200)
    off = plan_lazy(p, Budget(seconds=60), LazyOptions(shorten=0))
    on = plan_lazy(p, Budget(seconds=60))
    _check(p, off, on)
    assert on.horizon < off.horizon and on.counters["shortened_from"] == off.horizon
    assert on.counters["minimal"] is False and "shortened from" in on.message


def test_shorten_zero_gives_the_timed_routes_plan() -> None:
    p = gcs_maze(20)
    a = abstract(p)
    off = plan_lazy(p, Budget(seconds=60), LazyOptions(shorten=0))
    again = timed_route(p, a, route(p, a), ConPlan(p, a, generalize=True), Budget().clock(), {}, first_leg=2)
    assert "shortened_from" not in off.counters and "shorten_lps" not in off.counters
    assert again is not None and tuple(off.regions) == tuple(again.regions)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_the_mazes_are_left_alone(n: int) -> None:
    """Small abstractions (at most 200 regions): no pass, the timed route's plan."""
    r = plan_lazy(maze(n))
    assert "shorten_lps" not in r.counters and "shortened" not in r.message


def test_the_gcs_maze_of_50_is_within_a_tenth_of_gcs() -> None:
    """gcs-decomposition's curve takes 159 s (318 steps of 0.5 s); 1.1 x 159 s = 349 steps."""
    p = gcs_maze(50)
    r = plan_lazy(p, Budget(seconds=120), LazyOptions(shorten=10))
    assert r.status is ReachStatus.FOUND and r.counters["shortened_from"] == 423
    assert r.horizon <= 349 and r.counters["skipped_regions"] > 0
    assert validate(p, r.trajectory, require_segment_safe=True).ok


def test_nothing_to_shorten_returns_the_plan() -> None:
    assert plan_of(*runs_of((2, 2, 5))) == (2, 2, 5)
    p = maze(1)
    a = abstract(p)
    long = timed_route(p, a, route(p, a), ConPlan(p, a, generalize=True), Budget().clock(), {})
    assert shorten_plan(PrismLP(p, a), long, Budget().clock(), 0.0) is long


def test_every_prism_lies_in_its_regions() -> None:
    """Points sampled in the prism of a chain of adjacent regions of the 10 x 10 maze lie
    in one of the chain's regions (so a segment between two of them is free)."""
    p = gcs_maze(10)
    a = abstract(p)
    lp = PrismLP(p, a)
    rng = np.random.default_rng(0)
    found = 0
    for i in range(len(a.regions)):
        for j in a.adjacency[i]:
            for chain in ([i, j], *([i, j, k] for k in a.adjacency[j] if k != i)):
                lo, hi = lp.prism(chain)
                if lo is None:
                    continue
                found += 1
                pts = rng.uniform(lo, hi, size=(20, 2))
                pts = np.r_[pts, lo[None], hi[None]]
                inside = np.zeros(len(pts), dtype=bool)
                for r in chain:
                    inside |= np.all(pts @ np.asarray(a.regions[r].H).T <= np.asarray(a.regions[r].h) + 1e-9, axis=1)
                assert inside.all(), chain
    assert found > 50


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10_000), st.sampled_from([1, 2]), st.booleans())
def test_every_shortened_plan_validates(seed: int, order: int, polygons: bool) -> None:
    """Random workspaces (boxes, or boxes and non-convex polygons): whatever the pass
    keeps runs through the timed route's regions in order, and the validator accepts its
    trajectory, segment by segment."""
    p = random_workspace(seed, 4, order=order, dt=0.5 if order == 2 else 1.0, polygons=polygons)
    a = abstract(p)
    long = timed_route(p, a, route(p, a), ConPlan(p, a, generalize=True), Budget(seconds=30).clock(), {})
    if long is None:
        return
    short = shorten_plan(PrismLP(p, a), long, Budget(seconds=30).clock(), 5.0)
    _check(p, long, short)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(3, 6), st.integers(0, 10_000))
def test_every_shortened_maze_plan_validates(n: int, seed: int) -> None:
    """Random small mazes (box regions, doorways: the prisms and the skips at work):
    the pass's plan runs through the timed route's regions in order and validates."""
    p = gcs_maze(n, seed=seed)
    a = abstract(p)
    long = timed_route(p, a, route(p, a), ConPlan(p, a, generalize=True), Budget(seconds=30).clock(), {})
    if long is None:
        return
    counters: dict = {}
    short = shorten_plan(PrismLP(p, a), long, Budget(seconds=30).clock(), 5.0, counters=counters)
    _check(p, long, short)

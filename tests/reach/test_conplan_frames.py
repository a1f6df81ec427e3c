"""CON-PLAN's shared LP frames and long-chain settings (conplan.py: ``_Layout`` windows,
``slack_lp``, certified prefix bounds).

LPs of different horizons and spans are loaded into one HiGHS model per purpose, the
rows outside their window freed and the goal rows moved, so that they warm-start.
These tests check that this changes no answer: on random small workspaces and random
region walks of varying horizons, one long-lived ConPlan agrees with a cold LP written
for exactly the walk's horizon (``refutes``), every trajectory validates, and every
counterexample is refuted by its own LP.
"""

from __future__ import annotations

import os
import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import abstract
from plansynth.reach.families import cluttered, maze, random_workspace
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.validate import validate

#: Hypothesis examples per property test below; PLANSYNTH_TEST_SCALE=N runs N times as
#: many (a longer hunt than CI's, which runs each of them in three random orders).
SCALE = max(1, int(os.environ.get("PLANSYNTH_TEST_SCALE", "1")))

PROPS = settings(max_examples=8 * SCALE, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def walks(abstraction, rng: random.Random, count: int, max_len: int) -> list[tuple[int, ...]]:
    """Random region walks from a start region (staying put or moving to a neighbour)."""
    out = []
    for _ in range(count):
        r = rng.choice(abstraction.start_regions)
        walk = [r]
        for _ in range(rng.randint(0, max_len)):
            r = rng.choice((r, r, *abstraction.adjacency[r]))
            walk.append(r)
        out.append(tuple(walk))
    return out


@PROPS
@given(st.integers(0, 10**6), st.sampled_from([1, 2, 5]), st.booleans())
def test_frames_agree_with_cold_lps_of_the_exact_horizon(seed: int, order: int, slack_lp: bool) -> None:
    try:
        p = random_workspace(seed, 3, order=order, dt=1.0 if order == 1 else 0.5)
    except RuntimeError:
        return
    a = abstract(p)
    c = ConPlan(p, a, slack_lp=slack_lp)
    g = ConPlan(p, a, slack_lp=slack_lp, generalize=True, minimize=True)
    rng = random.Random(seed)
    for walk in walks(a, rng, 12, 10):
        N = len(walk) - 1
        whole = Conflict(tuple(enumerate(walk)), anchored_start=True, anchored_goal=True, horizon=N)
        traj = c.feasible(walk)
        assert (traj is None) == c.refutes(whole, cold=True) == c.refutes(whole)
        if traj is not None:
            assert validate(p, traj, require_segment_safe=True).ok
        for prefix in (0, N // 2, N):
            lits = tuple((t, walk[t]) for t in range(prefix + 1))
            claim = Conflict(lits, anchored_start=True, anchored_goal=False, horizon=N, last_time=N)
            assert c.prefix_feasible(walk, prefix) == (not c.refutes(claim, cold=True)) == (not c.refutes(claim))
        out = g.check(walk)
        if isinstance(out, Feasible):
            assert traj is not None
            assert validate(p, out.trajectory, require_segment_safe=True).ok
        else:
            assert traj is None and g.refutes(out, cold=True)


def test_long_chains_skip_the_slack_lp_and_short_ones_keep_it() -> None:
    assert ConPlan(maze(1, order=5), abstract(maze(1))).slack_lp is False
    assert ConPlan(maze(1), abstract(maze(1))).slack_lp is True


def test_zeroprefix_without_slack_lp_finds_the_earliest_infeasible_prefix() -> None:
    p = maze(1)
    a = abstract(p)
    c = ConPlan(p, a, slack_lp=False)
    regions = (0,) * 20 + (1,) * 3 + (2,) * 30  # at the gap far too early
    out = c.check(regions)
    assert isinstance(out, Conflict) and c.refutes(out, cold=True)
    k = max(t for t, _ in out.literals)
    assert not c.prefix_feasible(regions, k) and c.prefix_feasible(regions, k - 1)


def test_order_25_chain_plan_is_found_and_validated() -> None:
    r = solve(maze(0, order=25), max_horizon=70)
    assert r.status is ReachStatus.FOUND and r.validated is True and r.validation.ok
    assert r.trajectory.states.shape[1] == 50
    assert r.counters["ipm_fallbacks"] == 0


@pytest.mark.parametrize("order", [10, 25])
def test_long_chain_frames_warm_start_across_horizons(order: int) -> None:
    p = maze(1, order=order)
    c = ConPlan(p, abstract(p))
    early = (0,) * 20 + (1,) * 2 + (2,) * 40  # reaches the gap too fast: infeasible
    assert c.feasible(early) is None
    frame = c.slot.layout
    shorter = early[:-5]
    assert c.feasible(shorter) is None
    assert c.slot.layout.frame == frame.frame and c.slot.layout.t1 == len(shorter) - 1


@PROPS
@given(st.integers(0, 10**6), st.sampled_from([1, 2, 5]), st.sampled_from([2, 3]))
def test_split_lps_agree_with_the_whole_lp(seed: int, order: int, dim: int) -> None:
    """Box workspaces are separable per axis: the LPs split into one part per axis give
    the same answers as the whole LP, and their conflicts are refuted by their own LP."""
    try:
        p = random_workspace(seed, 3, dim=dim, polygons=False, order=order, dt=1.0 if order == 1 else 0.5)
    except RuntimeError:
        return
    a = abstract(p)
    whole = ConPlan(p, a, split=False, generalize=True, minimize=True)
    split = ConPlan(p, a, split=True, generalize=True, minimize=True)
    assert split.slot.splits == (split.blocks is not None)
    rng = random.Random(seed)
    for walk in walks(a, rng, 12, 10):
        N = len(walk) - 1
        assert (whole.feasible(walk) is None) == (split.feasible(walk) is None)
        for prefix in (0, N // 2):
            assert whole.prefix_feasible(walk, prefix) == split.prefix_feasible(walk, prefix)
        out = split.check(walk)
        if isinstance(out, Feasible):
            assert validate(p, out.trajectory, require_segment_safe=True).ok
        else:
            assert whole.refutes(out, cold=True) and split.refutes(out)


def test_maze_chains_split_per_axis_and_polygons_do_not() -> None:
    p = maze(2, order=5)
    c = ConPlan(p, abstract(p))
    assert c.slot.splits and c.blocks is not None and c.blocks[0].tolist() == [0, 1] * 5
    assert c.feasible((0,) * 10) is None  # (the goal is far)
    assert c.slot.parts is not None and len(c.slot.parts) == 2
    q = cluttered()  # regions with slanted edges couple the axes
    assert ConPlan(q, abstract(q), split=True).blocks is None

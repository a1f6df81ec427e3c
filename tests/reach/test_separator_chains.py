"""Random dynamics: the separator-chain bounds and the window
search's deferral, against brute force over small region graphs."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from tests.reach.test_displan import graphs, walks

from plansynth.budget import Budget
from plansynth.reach.families import maze, random_dynamics
from plansynth.reach.lazy.bounds import GOAL_NODE, START_NODE, separator_bounds
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.displan import DisPlan, RegionGraph
from plansynth.reach.lazy.loop import lazy_loop
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.result import ReachStatus
from plansynth.reach.trajectory import Trajectory


def respects(seq: tuple[int, ...], gap) -> bool:
    """Does the walk keep every gap: ``t' - t >= gap(a, b)`` between any two samples,
    ``t >= gap(START, r_t)`` and ``N - t >= gap(r_t, GOAL)``?"""
    N = len(seq) - 1
    if N < gap(START_NODE, GOAL_NODE):
        return False
    for t, a in enumerate(seq):
        if t < gap(START_NODE, a) or N - t < gap(a, GOAL_NODE):
            return False
        for u in range(t + 1, N + 1):
            if seq[u] != a and u - t < gap(a, seq[u]):
                return False
    return True


@st.composite
def gap_tables(draw, k: int):
    nodes = [START_NODE, *range(k), GOAL_NODE]
    table = {(a, b): draw(st.sampled_from((0, 0, 0, 1, 1, 2, 3))) for a in nodes for b in nodes if a != b}
    return lambda a, b: table.get((a, b), 0)


@settings(max_examples=50, deadline=None)
@given(graphs(max_regions=4), st.data())
def test_separator_bounds_hold_for_every_walk_that_keeps_the_gaps(g: RegionGraph, data) -> None:
    """Exact check of the soundness argument: every walk (brute force, horizons 0..7)
    that keeps the gaps is in region j no earlier than ``earliest[j]``, no later than
    ``to_go[j]`` before its end, and is no shorter than ``horizon``."""
    gap = data.draw(gap_tables(g.n_regions))
    b = separator_bounds(g.adjacency, g.start_regions, g.goal_regions, gap)
    for N in range(8):
        for seq in walks(g, N):
            if not respects(seq, gap):
                continue
            assert N >= b.horizon, (seq, b)
            for t, r in enumerate(seq):
                assert t >= b.earliest[r] and N - t >= b.to_go[r], (seq, t, b)


def test_separator_bounds_on_a_corridor() -> None:
    """A path graph 0 - .. - 4 from region 0 to region 4: regions 1..3 separate; gap 4
    from 1 to 3 and from 2 to 4 (the start and goal regions are not separators: the
    start and the goal count through START and GOAL)."""
    adj = ((1,), (0, 2), (1, 3), (2, 4), (3,))
    gaps = {(1, 3): 4, (2, 4): 4, (4, GOAL_NODE): 0}
    b = separator_bounds(adj, (0,), (4,), lambda a, c: gaps.get((a, c), 1))
    assert b.earliest == (0, 1, 2, 5, 6) and b.horizon == 6 and b.to_go == (6, 5, 2, 1, 0)
    assert b.critical[0] == START_NODE and b.critical[-1] == GOAL_NODE


def test_chains_raise_the_horizon_bound_on_random_dynamics() -> None:
    """Maze-3 with n = 4 random dynamics: the sweep's bound is 17 (one-step displacement
    6 m); the chains of gap regions give 86 (the planner's plan: 135). The double
    integrator's maze keeps its bounds (no multi-step table). The bounds are the loop's
    (the timed route plans before them, and its plan respects them too)."""
    loop = LazyOptions(timed_route=False)
    r = plan_lazy(random_dynamics(3, 4, seed=0), Budget(seconds=60), loop)
    c = r.counters
    assert c["box_bound"] == 17 and c["chain_bound"] == 86 and c["first_horizon"] == 86
    assert r.status is ReachStatus.FOUND and r.horizon >= 86
    regions = r.regions
    assert regions is not None
    m = plan_lazy(maze(3), options=loop)
    assert "chain_bound" not in m.counters and m.counters["first_horizon"] == 98
    quick = plan_lazy(random_dynamics(3, 4, seed=0), Budget(seconds=60))
    assert quick.status is ReachStatus.FOUND and quick.horizon >= 86


# -- deferral ------------------------------------------------------------------


class SetTheory:
    """A toy theory: exactly the walks in ``feasible`` are realised; every other plan is
    refuted by its whole sequence (sound: it blocks that plan only)."""

    def __init__(self, feasible: set[tuple[int, ...]]) -> None:
        self.feasible = feasible
        self.plans_checked = 0

    def check(self, regions):
        self.plans_checked += 1
        plan = tuple(regions)
        N = len(plan) - 1
        if plan in self.feasible:
            return Feasible(Trajectory(states=np.zeros((N + 1, 1)), inputs=np.zeros((N, 1))))
        return Conflict(tuple(enumerate(plan)), anchored_start=True, anchored_goal=True, horizon=N)


@settings(max_examples=60, deadline=None)
@given(graphs(max_regions=3), st.data(), st.integers(1, 3))
def test_deferral_keeps_every_claim_true(g: RegionGraph, data, defer_after: int) -> None:
    """Against brute force: with windows deferred after ``defer_after`` costly plans the
    loop finds a plan iff one exists in the windows, ``minimal`` only when no shorter
    one exists, and ``infeasible`` only when none exists."""
    all_walks = sorted(set().union(*(walks(g, N) for N in range(1, 7))), key=lambda s: (len(s), s))
    chosen = data.draw(st.lists(st.sampled_from(all_walks), max_size=3, unique=True)) if all_walks else []
    theory = SetTheory(set(chosen))
    out = lazy_loop(
        DisPlan(g), theory, [(1, 2), (3, 4), (5, 6)], Budget().clock(), {"sat": 0.0, "lp": 0.0}, defer_after=defer_after
    )
    if not chosen:
        assert out.status is ReachStatus.INFEASIBLE
        return
    assert out.status is ReachStatus.FOUND and out.regions in theory.feasible
    least = min(len(s) - 1 for s in chosen)
    if out.minimal:
        assert out.horizon == least
    if out.horizon > least:
        assert not out.minimal


def test_a_deferred_window_is_named_in_the_message() -> None:
    """Path 0 - 1 - 2: the plans of horizons 2..4 are all refuted, but window 2..4 has
    more of them than ``defer_after``; the loop defers it and finds the plan of window
    5..6 (not minimal: horizons 2..4 were not all refuted)."""
    g = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,))
    target = (0, 0, 0, 0, 1, 2)
    theory = SetTheory({target})
    out = lazy_loop(DisPlan(g), theory, [(2, 4), (5, 6)], Budget().clock(), {"sat": 0.0, "lp": 0.0}, defer_after=2)
    assert out.status is ReachStatus.FOUND and out.regions == target and out.minimal is False
    assert "not all" in out.message
    plain = lazy_loop(DisPlan(g), SetTheory({target}), [(2, 4), (5, 6)], Budget().clock(), {"sat": 0.0, "lp": 0.0})
    assert plain.regions == target and plain.minimal is True and "not all" not in plain.message
    assert math.isfinite(plain.horizon)


def test_deferral_comes_back_to_the_deferred_window() -> None:
    """The only plan lies in the deferred window: the loop returns to it after the last
    window is refuted (every horizon of 5..6 closed) and finds it there."""
    g = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,))
    target = (0, 0, 1, 1, 2)
    displan = DisPlan(g)
    out = lazy_loop(
        displan, SetTheory({target}), [(2, 4), (5, 6)], Budget().clock(), {"sat": 0.0, "lp": 0.0}, defer_after=1
    )
    assert out.status is ReachStatus.FOUND and out.regions == target and out.minimal is False
    assert {5, 6} <= displan.closed


def test_dense_dynamics_keep_sound_farkas_conflicts() -> None:
    """n = 50 random dynamics (2,402 nonzeros in A) make CON-PLAN's LPs dear: a conflict
    keeps its Farkas support without the deletion filter; it is still refuted by an LP
    over exactly its claims (the double integrator keeps the filter)."""
    from plansynth.reach.abstraction import abstract
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.guide import reference_plan

    p = random_dynamics(1, 50, seed=0)
    a = abstract(p)
    cp = ConPlan(p, a, counterexample="trivial", generalize=True, minimize=True)
    assert cp.dear and not ConPlan(maze(1), abstract(maze(1))).dear
    out = cp.check(reference_plan(p, a, 30))  # 30 steps: far too fast
    assert isinstance(out, Conflict) and out.literals
    assert cp.refutes(out, cold=True)
    assert "minimize" not in cp.stats.by_kind and "unanchor" not in cp.stats.by_kind

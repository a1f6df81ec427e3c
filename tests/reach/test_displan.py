"""DIS-PLAN (Section IV): the SAT encoding against brute-force enumeration of walks."""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.displan import CARDINALITY_ENCODINGS, DisPlan, RegionGraph, SatOutcome

MAX_MODELS = 400


def walks(g: RegionGraph, L: int, earliest=None, to_go=None) -> set[tuple[int, ...]]:
    """Every region sequence r_0..r_L of the paper's constraints, by brute force."""
    out = set()
    for seq in itertools.product(range(g.n_regions), repeat=L + 1):
        if seq[0] not in g.start_regions or seq[-1] not in g.goal_regions:
            continue
        if any(b != a and b not in g.adjacency[a] for a, b in zip(seq, seq[1:])):
            continue
        if earliest is not None and any(t < earliest[r] for t, r in enumerate(seq)):
            continue
        if to_go is not None and any(L - t < to_go[r] for t, r in enumerate(seq)):
            continue
        out.add(seq)
    return out


def models(d: DisPlan, L: int) -> set[tuple[int, ...]]:
    """Every plan DIS-PLAN proposes at horizon L, each blocked after it is seen."""
    seen: set[tuple[int, ...]] = set()
    for _ in range(MAX_MODELS):
        outcome, plan = d.solve(L)
        if outcome is SatOutcome.UNSAT:
            return seen
        assert outcome is SatOutcome.SAT and plan is not None
        assert plan not in seen, "a blocked plan came back"
        seen.add(plan)
        d.learn(Conflict(tuple(enumerate(plan)), anchored_start=True, anchored_goal=True, horizon=L))
    raise AssertionError("too many models for a unit test")


@st.composite
def graphs(draw, max_regions: int = 5) -> RegionGraph:
    k = draw(st.integers(1, max_regions))
    pairs = [(i, j) for i in range(k) for j in range(i + 1, k)]
    edges = draw(st.lists(st.sampled_from(pairs), unique=True, max_size=len(pairs))) if pairs else []
    adj = [set() for _ in range(k)]
    for i, j in edges:
        adj[i].add(j)
        adj[j].add(i)
    start = draw(st.lists(st.integers(0, k - 1), min_size=1, max_size=2, unique=True))
    goal = draw(st.lists(st.integers(0, k - 1), min_size=1, max_size=2, unique=True))
    return RegionGraph(k, tuple(tuple(sorted(a)) for a in adj), tuple(sorted(start)), tuple(sorted(goal)))


PATH3 = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,))
TRIANGLE = RegionGraph(3, ((1, 2), (0, 2), (0, 1)), (0,), (1, 2))


@pytest.mark.parametrize("graph", [PATH3, TRIANGLE], ids=["path", "triangle"])
@pytest.mark.parametrize("L", [0, 1, 2, 3, 4])
def test_models_are_exactly_the_walks(graph: RegionGraph, L: int) -> None:
    assert models(DisPlan(graph), L) == walks(graph, L)


@settings(max_examples=40)
@given(graphs(), st.integers(0, 3), st.sampled_from(sorted(CARDINALITY_ENCODINGS) + ["paths"]))
def test_models_are_exactly_the_walks_on_random_graphs(graph: RegionGraph, L: int, encoding: str) -> None:
    assert models(DisPlan(graph, cardinality=encoding), L) == walks(graph, L)


@settings(max_examples=25)
@given(graphs(max_regions=4), st.data())
def test_time_windows_exclude_exactly_the_early_and_late_visits(graph: RegionGraph, data) -> None:
    earliest = data.draw(
        st.lists(st.sampled_from([0, 1, 2, math.inf]), min_size=graph.n_regions, max_size=graph.n_regions)
    )
    to_go = data.draw(
        st.lists(st.sampled_from([0, 1, 2, math.inf]), min_size=graph.n_regions, max_size=graph.n_regions)
    )
    for encoding in ("auto", "paths"):
        d = DisPlan(graph, earliest=earliest, to_go=to_go, cardinality=encoding)
        for L in range(4):
            assert models(d, L) == walks(graph, L, earliest, to_go)


def _satisfies(plan, conflicts, graph: RegionGraph) -> bool:
    """Is ``plan`` a walk of ``graph`` that breaks none of ``conflicts`` (at the shifts
    DIS-PLAN instantiates them: start-anchored as given, goal-anchored moved with the
    horizon, free ones at every shift)?"""
    H = len(plan) - 1
    if plan[0] not in graph.start_regions or plan[-1] not in graph.goal_regions:
        return False
    if any(b != a and b not in graph.adjacency[a] for a, b in zip(plan, plan[1:])):
        return False
    for c in conflicts:
        if c.anchored_start:
            shifts = [H - c.horizon] if c.anchored_goal else [0]
        elif c.anchored_goal:
            shifts = [H - c.horizon]
        else:
            shifts = range(-c.first_time, H - c.last_time + 1)
        for sh in shifts:
            if c.anchored_start and c.anchored_goal and sh != 0:
                continue
            if (
                c.literals
                and all(0 <= t + sh <= H and plan[t + sh] == i for t, i in c.literals)
                and c.last_time + sh <= H
            ):
                return False
    return True


@settings(max_examples=60, deadline=None)
@given(graphs(max_regions=5), st.data())
def test_paths_encoding_agrees_with_the_dense_one(graph: RegionGraph, data) -> None:
    """The ``paths`` encoding (no exactly-one, backward transitions, variables only
    inside the time windows) answers a random run of windows and learned conflicts as
    the dense encoding does: the same SAT / UNSAT at each question, and every plan it
    returns a walk that breaks no learned clause."""
    k = graph.n_regions
    earliest = data.draw(st.lists(st.sampled_from([0, 0, 1, 2]), min_size=k, max_size=k))
    to_go = data.draw(st.lists(st.sampled_from([0, 0, 1, 2]), min_size=k, max_size=k))
    dense = DisPlan(graph, earliest=earliest, to_go=to_go, cardinality="seqcounter")
    paths = DisPlan(graph, earliest=earliest, to_go=to_go, cardinality="paths")
    learned: list[Conflict] = []
    lo = data.draw(st.integers(0, 2))
    for _ in range(data.draw(st.integers(1, 6))):
        hi = lo + data.draw(st.integers(0, 2))
        a, pa = dense.solve(hi, lowest=lo)
        b, pb = paths.solve(hi, lowest=lo)
        assert a is b
        if b is SatOutcome.SAT:
            assert lo <= len(pb) - 1 <= hi
            assert _satisfies(pb, [c for c in learned if c.anchored_start], graph)
            assert all(earliest[r] <= t for t, r in enumerate(pb))
            # learn a conflict about the plan just seen: one of its literals, or a pair
            H = len(pb) - 1
            t1 = data.draw(st.integers(0, H))
            t2 = data.draw(st.integers(t1, H))
            lits = ((t1, pb[t1]),) if t1 == t2 else ((t1, pb[t1]), (t2, pb[t2]))
            kind = data.draw(st.sampled_from(["start", "free", "goal"]))
            c = Conflict(lits, anchored_start=kind == "start", anchored_goal=kind == "goal", horizon=H)
            learned.append(c)
            dense.learn(c)
            paths.learn(c)
        else:
            for h in range(lo, hi + 1):
                dense.close(h)
                paths.close(h)
            lo = hi + 1
    dense.delete()
    paths.delete()


def test_one_solver_serves_every_horizon_and_keeps_start_anchored_clauses() -> None:
    d = DisPlan(PATH3)
    assert d.solve(1) == (SatOutcome.UNSAT, None)  # below the BFS distance
    d.close(1)
    assert d.plan(2) == (0, 1, 2)
    # "region 1 at time 1" is impossible: a start-anchored prefix clause, for every horizon
    d.learn(Conflict(((0, 0), (1, 1)), anchored_start=True, anchored_goal=False, horizon=2))
    assert d.plan(2) is None
    d.close(2)
    for L in (3, 4):
        got = models(d, L)
        assert got == {w for w in walks(PATH3, L) if w[1] != 1}
    assert d.sat_calls > 0 and d.clauses > 0


def test_goal_anchored_conflict_shifts_with_the_goal() -> None:
    d = DisPlan(PATH3)
    # "region 1 one step before the end" is impossible, with or without the start
    d.learn(Conflict(((1, 1),), anchored_start=False, anchored_goal=True, horizon=2))
    for L in (2, 3, 4):
        assert models(d, L) == {w for w in walks(PATH3, L) if w[L - 1] != 1}


def test_free_conflict_holds_at_every_shift() -> None:
    d = DisPlan(PATH3)
    # "region 0 followed immediately by region 1" (at any time) is impossible
    d.learn(Conflict(((5, 0), (6, 1)), anchored_start=False, anchored_goal=False, horizon=6))
    for L in (2, 3, 4, 5):
        assert models(d, L) == set()  # every walk from 0 to 2 must step 0 -> 1 somewhere


def test_free_conflict_respects_the_states_its_proof_needs() -> None:
    d = DisPlan(PATH3)
    # the proof used states 2..4 around the literal at 3: no copy where they do not exist
    d.learn(Conflict(((3, 2),), anchored_start=False, anchored_goal=False, horizon=5, first_time=2, last_time=4))
    assert models(d, 2) == walks(PATH3, 2)  # last_time - first_time = 2: a copy at 0..2 puts
    # the literal at time 1, where region 2 is unreachable anyway
    assert models(d, 3) == {w for w in walks(PATH3, 3) if w[1] != 2 and w[2] != 2}


def test_empty_conflict_refutes_everything() -> None:
    d = DisPlan(PATH3)
    d.learn(Conflict((), anchored_start=True, anchored_goal=False, horizon=2))
    assert d.plan(2) is None and d.plan(5) is None


def test_bad_graphs_and_conflicts_are_rejected() -> None:
    with pytest.raises(ValueError, match="symmetric"):
        RegionGraph(2, ((1,), ()), (0,), (1,))
    with pytest.raises(ValueError, match="lists"):
        RegionGraph(2, ((1,),), (0,), (1,))
    with pytest.raises(ValueError, match="outside"):
        Conflict(((5, 0),), anchored_start=True, anchored_goal=False, horizon=3)
    with pytest.raises(ValueError, match="unknown cardinality"):
        DisPlan(PATH3, cardinality="magic")


def test_bfs_bound() -> None:
    assert PATH3.horizon_lower_bound() == 2
    disconnected = RegionGraph(2, ((), ()), (0,), (1,))
    assert disconnected.horizon_lower_bound() == math.inf
    assert all(DisPlan(disconnected).plan(L) is None for L in range(4))


def test_status_has_no_truth_value() -> None:
    with pytest.raises(TypeError):
        bool(SatOutcome.SAT)


# ------------------------------------------------------------------ horizon windows


def line_graph() -> RegionGraph:
    return RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(2,))


def test_a_window_gives_a_plan_of_some_horizon_in_it() -> None:
    with DisPlan(line_graph()) as d:
        outcome, plan = d.solve(6, lowest=1)
        assert outcome is SatOutcome.SAT and plan is not None
        assert 2 <= len(plan) - 1 <= 6  # horizon 1 has no plan: 0 -> 1 -> 2 takes two steps
        assert plan[0] == 0 and plan[-1] == 2
        assert all(b == a or abs(b - a) == 1 for a, b in zip(plan, plan[1:]))


def test_a_clause_that_needs_later_states_spares_shorter_plans_in_the_window() -> None:
    """A start-anchored conflict proved with the states up to time 4 holds only for plans
    of horizon >= 4; in a window 2..5 the horizon-2 plan (0, 1, 2) must stay possible."""
    with DisPlan(line_graph()) as d:
        assert d.solve(5, lowest=2)[0] is SatOutcome.SAT
        d.learn(Conflict(((1, 1),), anchored_start=True, anchored_goal=False, horizon=4, last_time=4))
        assert d.solve(2, lowest=2) == (SatOutcome.SAT, (0, 1, 2))
        outcome, plan = d.solve(5, lowest=4)
        assert outcome is SatOutcome.SAT and plan is not None and plan[1] != 1


def test_closing_a_window_refutes_all_its_horizons() -> None:
    with DisPlan(line_graph()) as d:
        d.learn(Conflict(((1, 1),), anchored_start=True, anchored_goal=False, horizon=1))
        d.learn(Conflict(((2, 1),), anchored_start=True, anchored_goal=False, horizon=2))
        # region 1 is forbidden at times 1 and 2, so the goal needs horizon >= 4
        assert d.solve(3, lowest=2)[0] is SatOutcome.UNSAT
        for h in (2, 3):
            d.close(h)
        outcome, plan = d.solve(8, lowest=4)
        assert outcome is SatOutcome.SAT and plan is not None and len(plan) - 1 >= 4


def test_a_window_below_the_first_horizon_is_refused() -> None:
    with DisPlan(line_graph()) as d:
        d.solve(3)
        with pytest.raises(ValueError):
            d.solve(4, lowest=2)


def test_a_preferred_plan_is_proposed_whole_at_its_horizon() -> None:
    """Phases only steer: in a window, a preferred plan that satisfies every clause comes
    back as it is (its horizon first, not the window's shortest), and one that breaks a
    clause does not; without a preference the window's shortest plan comes first."""
    with DisPlan(line_graph()) as d:
        outcome, plan = d.solve(6, lowest=2)
        assert outcome is SatOutcome.SAT and plan == (0, 1, 2)
    with DisPlan(line_graph()) as d:
        d.solve(2)
        d.close(2)
        d.prefer((0, 0, 0, 1, 1, 2, 2))
        assert d.solve(6, lowest=3) == (SatOutcome.SAT, (0, 0, 0, 1, 1, 2, 2))
        d.learn(Conflict(((3, 1),), anchored_start=True, anchored_goal=False, horizon=6))
        outcome, plan = d.solve(6, lowest=3)
        assert outcome is SatOutcome.SAT and plan is not None and plan[3] != 1


@pytest.mark.parametrize("goal", [False, True])
def test_a_robot_that_can_wait_at_its_start_shifts_start_anchored_conflicts_earlier(goal: bool) -> None:
    """Region 1 at time 2 is impossible from the start (and, with ``goal``, in plans of
    horizon 3); a robot that can wait at the start could otherwise have been in region 1
    at time 1 (in a plan of horizon 2), so that is impossible too."""
    for waits in (False, True):
        with DisPlan(line_graph(), waits_at_start=waits) as d:
            d.learn(Conflict(((2, 1),), anchored_start=True, anchored_goal=goal, horizon=3))
            assert (d.plan(2) is None) == waits  # (0, 1, 2) has region 1 at time 1
            assert d.plan(4) is not None  # (0, 0, 0, 1, 2): region 1 only later

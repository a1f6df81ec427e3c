"""The linear BMC encoding of missions (plansynth.reach.mission.bmc) against the LTL
evaluator: on a region graph with one region per letter, every finite or lasso word,
fixed by assumptions after the lower horizons were built and closed (incremental),
satisfies the encoding exactly when the evaluator says the word satisfies the formula."""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st
from test_ltl import NAMES, formulas

from plansynth.reach.lazy.displan import RegionGraph, SatOutcome
from plansynth.reach.mission.bmc import MissionDisPlan, MissionPlan
from plansynth.reach.mission.ltl import Lasso, finite_word, holds, parse

LETTERS = [frozenset(c) for k in range(len(NAMES) + 1) for c in itertools.combinations(NAMES, k)]
N = len(LETTERS)
COMPLETE = RegionGraph(
    N, tuple(tuple(j for j in range(N) if j != i) for i in range(N)), tuple(range(N)), tuple(range(N))
)


def encoding_accepts(f, regions, loop_start, semantics="any"):
    d = MissionDisPlan(COMPLETE, LETTERS, f, semantics=semantics)
    L = len(regions) - 1
    for h in range(L):  # incremental: the lower horizons first, refuted
        d.solve(h)
        d.close(h)
    d._extend(L)
    d._boundary(L)
    sel = d.stay(L) if loop_start is None else d.loop(L, loop_start + 1)
    ok = d.solver.solve(assumptions=[d.act(L), sel] + [d.at(t, r) for t, r in enumerate(regions)])
    d.delete()
    return ok


@settings(max_examples=150, deadline=None)
@given(formulas(), st.lists(st.sampled_from(range(N)), min_size=1, max_size=5))
def test_finite_words(f, regions):
    word = finite_word([LETTERS[r] for r in regions])
    assert encoding_accepts(f, regions, None) == holds(f, word)


@settings(max_examples=150, deadline=None)
@given(
    formulas(),
    st.lists(st.sampled_from(range(N)), max_size=3),
    st.lists(st.sampled_from(range(N)), min_size=1, max_size=3),
)
def test_lasso_words(f, prefix, loop):
    word = Lasso(tuple(LETTERS[r] for r in prefix), tuple(LETTERS[r] for r in loop))
    regions = prefix + loop + [loop[0]]  # x_L = x_k with k = len(prefix)
    assert encoding_accepts(f, regions, len(prefix)) == holds(f, word)


@settings(max_examples=60, deadline=None)
@given(formulas(), st.sampled_from(["any", "finite", "lasso"]))
def test_every_plan_found_satisfies_the_formula(f, semantics):
    d = MissionDisPlan(COMPLETE, LETTERS, f, semantics=semantics)
    for L in range(5):
        out, plan = d.solve(L)
        if out is SatOutcome.SAT:
            assert isinstance(plan, MissionPlan) and plan.horizon == L
            ls = [LETTERS[r] for r in plan.regions]
            if plan.loop_start is None:
                assert semantics != "lasso" and holds(f, finite_word(ls))
            else:
                assert semantics != "finite" and ls[-1] == ls[plan.loop_start]
                assert holds(f, Lasso(tuple(ls[: plan.loop_start]), tuple(ls[plan.loop_start : -1])))
            break
        d.close(L)
    d.delete()


def test_patrol_needs_a_lasso():
    g = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (0, 1, 2))
    d = MissionDisPlan(g, [frozenset({"a"}), frozenset(), frozenset({"b"})], parse("G F a & G F b"))
    found = None
    for L in range(8):
        out, plan = d.solve(L)
        if out is SatOutcome.SAT:
            found = plan
            break
        d.close(L)
    assert found == MissionPlan((0, 1, 2, 1, 0), 0)


def test_conflicts_and_loop_clauses_carry_over_to_later_horizons_in_one_solver():
    """One CaDiCaL instance across horizons: a conflict learned at
    horizon 2 (region 1 followed by region 2, at any time shift) and a loop refuted
    without the start at horizon 2 still exclude their plans at horizon 4, where the
    solver is the same object and nothing was re-encoded."""
    from plansynth.reach.lazy.conflict import Conflict

    g = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (0, 1, 2))
    d = MissionDisPlan(g, [frozenset({"a"}), frozenset(), frozenset({"b"})], parse("F b"))
    solver = d.solver
    for L in range(2):
        assert d.solve(L)[0] is SatOutcome.UNSAT
        d.close(L)
    assert d.solve(2)[1] == MissionPlan((0, 1, 2), None)
    d.learn(Conflict(((1, 1), (2, 2)), anchored_start=False, anchored_goal=False, horizon=2))
    assert d.solve(2)[0] is SatOutcome.UNSAT  # 0 1 2 was the only plan of horizon 2
    d.close(2)
    # horizon 3: 1 -> 2 is refuted at every shift, so b is out of reach
    assert d.solve(3)[0] is SatOutcome.UNSAT
    d.close(3)
    assert d.solver is solver and d.clauses >= 3  # the shifted copies were added, not re-encoded

    e = MissionDisPlan(g, [frozenset({"a"}), frozenset(), frozenset({"b"})], parse("G F a & G F b"), semantics="lasso")
    for L in range(4):
        assert e.solve(L)[0] is SatOutcome.UNSAT
        e.close(L)
    assert e.solve(4)[1] == MissionPlan((0, 1, 2, 1, 0), 0)
    e.learn_loop(((0, 0), (2, 2)), 0, 4, shifted=True)  # the period-4 loop a . b . is refuted
    assert e.solve(4)[0] is SatOutcome.UNSAT
    e.close(4)
    out, plan = e.solve(5)  # the same loop one step later (and rotated) stays refuted
    assert out is SatOutcome.SAT and plan.horizon - plan.loop_start != 4
    assert e.solver.solve(assumptions=[e.act(5), e.loop(5, 2)]) is False  # period 4 at horizon 5
    assert e.solver.solve(assumptions=[e.act(5), e.loop(5, 1)]) is True  # period 5 is not refuted
    d.delete()
    e.delete()

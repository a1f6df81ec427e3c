"""The compiled core against its pure-Python references (STYLE.md, point 6)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.grid.native import fast
from plansynth.grid.native.conditions import _enumerate
from plansynth.grid.programs import evaluate


def test_the_core_is_built():
    assert fast.available()
    assert fast.core_version()


@settings(max_examples=120)
@given(
    st.integers(1, 4).flatmap(
        lambda nv: st.tuples(
            st.just(nv),
            st.lists(st.tuples(*[st.integers(-1, 5)] * nv), max_size=14),
        )
    ),
    st.integers(2, 4),
    st.one_of(st.none(), st.integers(1, 300)),
    st.integers(0, 5),
)
def test_condition_enumeration_matches_the_reference(vs, max_depth, limit, max_constant):
    nv, states = vs
    names = [f"v{i}" for i in range(nv)]
    ref = _enumerate(states, names, max_constant, max_depth, limit)
    got = fast.enumerate_conditions(states, names, max_constant, max_depth, limit)
    assert [(c.mask, str(c.term), c.depth) for c in got.conditions] == [
        (c.mask, str(c.term), c.depth) for c in ref.conditions
    ]
    assert got.complete_to == ref.complete_to
    # every condition's term really has its behaviour
    for c in got.conditions[:200]:
        for i, s in enumerate(states):
            assert bool(evaluate(c.term, dict(zip(names, s)))) == bool(c.mask >> i & 1)


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.tuples(st.integers(-1, 5), st.integers(-1, 5)), min_size=1, max_size=40, unique=True),
    st.data(),
    st.integers(1, 5),
)
def test_greedy_tree_matches_the_reference(states, data, n_moves):
    from plansynth.grid.native.synth import greedy_program, greedy_program_reference

    allowed = [
        data.draw(st.lists(st.integers(0, n_moves - 1), min_size=1, max_size=n_moves, unique=True)) for _ in states
    ]
    conds = _enumerate(states, ["a", "b"], 5, data.draw(st.integers(3, 4)), None).conditions
    got = greedy_program(allowed, conds, n_moves, use_rust=True)
    ref = greedy_program_reference(allowed, conds, n_moves)
    assert got == ref
    # the tree plays an allowed move in every state
    for s, a in zip(states, allowed):
        assert evaluate(got, {"a": s[0], "b": s[1]}) in a

"""Proofs of mission infeasibility (plansynth.reach.mission.proof): the tableau decides
LTL satisfiability over an alphabet; checked against brute force over short lassos, and
every witness it returns satisfies the formula by the fixpoint evaluator."""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st
from test_ltl import NAMES, formulas

from plansynth.reach.mission.ltl import Lasso, holds, parse
from plansynth.reach.mission.proof import geometry_letters, satisfiable, witness

ALL = frozenset(NAMES)
alphabets = st.lists(st.frozensets(st.sampled_from(NAMES)), min_size=1, max_size=3, unique=True)


def brute_force(f, alphabet, max_len: int = 4) -> bool:
    """Some lasso over the alphabet with prefix + loop of at most ``max_len`` letters satisfies f?"""
    for n in range(1, max_len + 1):
        for word in itertools.product(alphabet, repeat=n):
            for k in range(n):
                if holds(f, Lasso(word[:k], word[k:])):
                    return True
    return False


@settings(max_examples=300, deadline=None)
@given(formulas(depth=3), alphabets)
def test_the_tableau_agrees_with_brute_force_and_its_witnesses_hold(f, alphabet):
    letters = [(a, ALL - a) for a in alphabet]  # ordinary valuations: a literal holds or its negation does
    w = witness(f, letters)
    if w is not None:
        prefix, loop = w
        assert holds(f, Lasso(tuple(alphabet[i] for i in prefix), tuple(alphabet[i] for i in loop)))
    if brute_force(f, alphabet):
        assert w is not None
    assert satisfiable(f, letters) is (w is not None)


def test_may_hold_letters_are_monotone():
    """A boundary letter (both a and !a may hold) satisfies what either reading does."""
    both = (frozenset({"a"}), frozenset({"a"}))
    assert satisfiable(parse("a & !a"), [both])
    assert not satisfiable(parse("a & !a"), [(frozenset({"a"}), frozenset()), (frozenset(), frozenset({"a"}))])
    assert not satisfiable(parse("F a & G !a"), [(frozenset({"a"}), frozenset()), (frozenset(), frozenset({"a"}))])


def test_the_unsat_example_is_proved_by_its_geometry_and_a_touching_variant_is_not():
    from dataclasses import replace

    from plansynth.reach.fileformat import load_reach_problem
    from plansynth.reach.geometry import Box
    from plansynth.reach.mission.labels import label_abstraction

    p = load_reach_problem("examples/reach/mission-unsat.yaml")
    la = label_abstraction(p)
    letters = geometry_letters(la, p.mission_labels, margin=1e-5)
    assert letters is not None and not satisfiable(parse(p.mission), letters)
    # a vault that reaches the moat's edge: its boundary point is in the vault, not in the moat's interior
    q = replace(p, labels=(("moat", Box((4, 4), (8, 8))), ("vault", Box((5, 5), (8, 7)))))
    lq = label_abstraction(q)
    assert satisfiable(parse(q.mission), geometry_letters(lq, q.mission_labels, margin=1e-5))


@settings(max_examples=40, deadline=None)
@given(
    formulas(depth=3),
    st.integers(0, 10**6),
    st.lists(
        st.tuples(st.integers(0, 7), st.integers(0, 7), st.integers(1, 3), st.integers(1, 3)),
        min_size=len(NAMES),
        max_size=len(NAMES),
    ),
)
def test_label_proof_gives_the_verdict_of_the_whole_letter_set(f, seed, rects):
    """label_proof decides on the regions' interior letters first (a subset of
    geometry_letters: satisfiable there is satisfiable over all of them) and only then
    on the boundary letters: its verdict is the whole letter set's, on random rooms
    whose integer labels often share edges and corners (so boundary letters matter)."""
    from dataclasses import replace

    from plansynth.reach.families import random_workspace
    from plansynth.reach.geometry import Box
    from plansynth.reach.mission.labels import label_abstraction
    from plansynth.reach.mission.proof import label_proof

    try:
        base = random_workspace(seed % 50, seed % 3, order=1, dt=1.0, input_bound=1.5, polygons=False)
    except RuntimeError:
        base = random_workspace(7, 1, order=1, dt=1.0, input_bound=1.5, polygons=False)
    labels = tuple((n, Box((x, y), (x + w, y + h))) for n, (x, y, w, h) in zip(NAMES, rects))
    p = replace(base, goal=None, labels=labels, mission=str(f), max_horizon=3)
    la = label_abstraction(p)
    ws = p.workspace
    letters = geometry_letters(la, p.mission_labels, margin=1e-5 * max(1.0, max(h - l for l, h in zip(ws.lo, ws.hi))))
    verdict, _ = label_proof(p, la)
    assert verdict is (None if letters is None else not satisfiable(f, letters))

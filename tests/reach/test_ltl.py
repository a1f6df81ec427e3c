"""LTL syntax and semantics (plansynth.reach.ltl, reached through plansynth.reach.mission.ltl): the parser's precedence, negation
normal form, and the fixpoint evaluator against the textbook definitions over the
unrolled lasso, on random formulas and random finite and lasso words."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    Globally,
    Iff,
    Implies,
    Lasso,
    LtlSyntaxError,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    finite_word,
    holds,
    holds_at,
    holds_unrolled,
    nnf,
    parse,
    props,
)

NAMES = ("a", "b", "c")


def formulas(depth: int = 4) -> st.SearchStrategy:
    leaf = st.one_of(st.sampled_from([Prop(n) for n in NAMES]), st.sampled_from([Const(True), Const(False)]))

    def extend(inner: st.SearchStrategy) -> st.SearchStrategy:
        unary = st.sampled_from([Not, Next, Finally, Globally])
        binary = st.sampled_from([And, Or, Implies, Iff, Until, Release])
        return st.one_of(
            st.builds(lambda op, f: op(f), unary, inner), st.builds(lambda op, f, g: op(f, g), binary, inner, inner)
        )

    return st.recursive(leaf, extend, max_leaves=8)


letters = st.frozensets(st.sampled_from(NAMES))
lassos = st.builds(
    lambda p, l: Lasso(tuple(p), tuple(l)), st.lists(letters, max_size=4), st.lists(letters, min_size=1, max_size=4)
)


@settings(max_examples=400)
@given(formulas(), lassos)
def test_fixpoint_evaluation_agrees_with_the_unrolled_definitions(f, word):
    assert holds(f, word) == holds_unrolled(f, word)


@settings(max_examples=300)
@given(formulas(), st.lists(letters, min_size=1, max_size=6))
def test_finite_words_are_the_lasso_that_repeats_the_last_letter(f, letters_):
    w = finite_word(letters_)
    assert holds(f, w) == holds_unrolled(f, w)
    # the stutter reading: appending the last letter once more changes nothing
    assert holds(f, w) == holds(f, finite_word(letters_ + [letters_[-1]]))


@settings(max_examples=300)
@given(formulas(), lassos)
def test_negation_normal_form_keeps_the_meaning_and_has_negations_on_labels_only(f, word):
    g = nnf(f)
    assert holds(g, word) == holds(f, word)
    assert holds(nnf(f, negate=True), word) == (not holds(f, word))

    def only_literals(h):
        if isinstance(h, Not):
            return isinstance(h.arg, Prop)
        assert not isinstance(h, (Implies, Iff))
        for child in getattr(h, "__dict__", {}).values():
            if not isinstance(child, (str, bool)) and not only_literals(child):
                return False
        return True

    assert only_literals(g)


@settings(max_examples=200)
@given(formulas())
def test_printing_and_parsing_round_trip(f):
    assert parse(str(f)) == f


def test_precedence_and_associativity():
    assert parse("F a & G !b") == And(Finally(Prop("a")), Globally(Not(Prop("b"))))
    assert parse("a U b & c") == And(Until(Prop("a"), Prop("b")), Prop("c"))
    assert parse("a | b & c") == Or(Prop("a"), And(Prop("b"), Prop("c")))
    assert parse("a -> b -> c") == Implies(Prop("a"), Implies(Prop("b"), Prop("c")))
    assert parse("a <-> b -> c") == Iff(Prop("a"), Implies(Prop("b"), Prop("c")))
    assert parse("a U b U c") == Until(Prop("a"), Until(Prop("b"), Prop("c")))
    assert parse("!a R X b") == Release(Not(Prop("a")), Next(Prop("b")))
    assert parse("(true)") == Const(True)
    assert props(parse("F (kitchen & F lab) & G !stairs")) == {"kitchen", "lab", "stairs"}


@pytest.mark.parametrize("text, where", [("a &", 3), ("(a", 2), ("a b", 2), ("F", 1), ("a $ b", 2), ("U a", 0)])
def test_syntax_errors_say_where(text, where):
    with pytest.raises(LtlSyntaxError) as e:
        parse(text)
    assert e.value.position == where


def test_semantics_on_hand_made_words():
    patrol = parse("G F a & G F b")
    assert holds(patrol, Lasso((), ({"a"}, {"b"})))
    assert not holds(patrol, Lasso(({"b"},), ({"a"},)))
    assert not holds(patrol, finite_word([{"a"}, {"b"}]))  # a finite plan visits a only once
    assert holds(parse("!corridor U door"), finite_word([set(), set(), {"door", "corridor"}]))
    assert not holds(parse("!corridor U door"), finite_word([set(), {"corridor"}, {"door"}]))
    assert holds(parse("F (k & F l) & G !s"), finite_word([set(), {"k"}, {"l"}]))
    assert not holds(parse("F (k & F l)"), finite_word([{"l"}, {"k"}]))
    assert holds_at(parse("X a"), Lasso(({"a"},), (set(), {"a"}))) == [False, True, False]

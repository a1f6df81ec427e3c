"""LTL syntax and semantics (plansynth.reach.ltl, reached through plansynth.reach.mission.ltl): the parser's precedence, negation
normal form, and the fixpoint evaluator against the textbook definitions over the
unrolled lasso, on random formulas and random finite and lasso words; the bounded
operators against their unrolling, finite words with a free end (LTL on finite traces),
robustness against the boolean semantics, and formulas as deep as their length allows."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.mission.ltl import (
    MAX_BOUND,
    MAX_FORMULA_SIZE,
    NEG,
    And,
    Const,
    Finally,
    FinallyWithin,
    FiniteWord,
    Globally,
    GloballyWithin,
    Iff,
    Implies,
    Lasso,
    LtlSyntaxError,
    Next,
    Not,
    Or,
    Prop,
    Release,
    ReleaseWithin,
    Until,
    UntilWithin,
    WeakNext,
    children,
    finite_word,
    holds,
    holds_at,
    holds_unrolled,
    nnf,
    parse,
    props,
    robustness,
    subformulas,
    unroll,
    unrolled_size,
)

NAMES = ("a", "b", "c")


def formulas(depth: int = 4, *, bounded: bool = False) -> st.SearchStrategy:
    """Random formulas over :data:`NAMES`; ``bounded``: with the bounded operators (small
    bounds) too."""
    leaf = st.one_of(st.sampled_from([Prop(n) for n in NAMES]), st.sampled_from([Const(True), Const(False)]))
    windows = st.tuples(st.integers(0, 3), st.integers(0, 3)).map(lambda ab: (min(ab), max(ab)))

    def extend(inner: st.SearchStrategy) -> st.SearchStrategy:
        unary = st.sampled_from([Not, Next, Finally, Globally])
        binary = st.sampled_from([And, Or, Implies, Iff, Until, Release])
        out = [
            st.builds(lambda op, f: op(f), unary, inner),
            st.builds(lambda op, f, g: op(f, g), binary, inner, inner),
        ]
        if bounded:
            out += [
                st.builds(
                    lambda op, w, f: op(w[0], w[1], f), st.sampled_from([FinallyWithin, GloballyWithin]), windows, inner
                ),
                st.builds(
                    lambda op, w, f, g: op(w[0], w[1], f, g),
                    st.sampled_from([UntilWithin, ReleaseWithin]),
                    windows,
                    inner,
                    inner,
                ),
            ]
        return st.one_of(*out)

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


# ------------------------------------------------------------ bounded operators, free ends, robustness

finite_words = st.lists(letters, min_size=1, max_size=6).map(FiniteWord)
words = st.one_of(lassos, finite_words)


@settings(max_examples=400)
@given(formulas(bounded=True), words)
def test_bounded_operators_mean_their_unrolling(f, word):
    """F[a,b], G[a,b], U[a,b], R[a,b] read directly agree with their X-unrolling, on
    lassos and on finite words (free end), and with the reference definitions."""
    assert holds(f, word) == holds(unroll(f), word) == holds_unrolled(f, word)


@settings(max_examples=300)
@given(formulas(bounded=True), words)
def test_negation_normal_form_keeps_the_meaning_on_finite_words_too(f, word):
    """With a free end the dual of X is the weak next: !X a holds at the last position."""
    assert holds(nnf(f), word) == holds(f, word)
    assert holds(nnf(f, negate=True), word) == (not holds(f, word))
    assert holds(f, word) == holds_unrolled(f, word)


def test_finite_traces_read_as_the_bounded_horizon_literature():
    w = FiniteWord([set(), {"a"}, {"a"}])
    assert holds(parse("F a"), w) and holds(parse("F G a"), w) and not holds(parse("G a"), w)
    assert not holds(parse("X X X a"), w) and holds(parse("!X !(X X X a)"), FiniteWord([set()]))
    assert not holds(parse("F[3,5] a"), w)  # no position 3: no witness
    assert holds(parse("X G[0,5] a"), w)  # G speaks of the positions the word has
    assert not holds(parse("X (G[0,5] a & F[5,5] true)"), w)  # ... unless the window must exist
    assert holds(parse("X (G[0,1] a & F[1,1] true)"), w)
    assert holds(parse("a U[1,2] b"), FiniteWord([{"a"}, {"b"}])) and not holds(
        parse("a U[2,3] b"), FiniteWord([{"a"}, {"b"}])
    )
    assert holds(parse("!b U[0,3] c"), finite_word([set(), set(), {"c"}]))  # the rest end: an infinite word


@settings(max_examples=300)
@given(formulas(bounded=True), words, st.data())
def test_robustness_is_positive_exactly_where_the_formula_holds(f, word, data):
    """Margins per literal, drawn so that exactly one of a, !a is positive at each step
    (labels read with a margin): robustness > 0 iff the formula holds on the word the
    positive margins spell, and every uniform shift of the margins shifts it."""
    g = nnf(f)
    values = []
    for letter in word.letters:
        m = {}
        for n in NAMES:
            r = data.draw(st.sampled_from([0.5, 1.0, 2.0]))
            m[n], m[NEG + n] = (r, -r) if n in letter else (-r, r)
        values.append(m)
    valued = (
        FiniteWord(values)
        if isinstance(word, FiniteWord)
        else Lasso(tuple(values[: len(word.prefix)]), tuple(values[len(word.prefix) :]))
    )
    rho = robustness(g, valued)
    assert (rho > 0) == holds(f, word), rho
    shifted = [{k: v - 0.25 for k, v in m.items()} for m in values]
    again = (
        FiniteWord(shifted)
        if isinstance(word, FiniteWord)
        else Lasso(tuple(shifted[: len(word.prefix)]), tuple(shifted[len(word.prefix) :]))
    )
    if abs(rho) != float("inf"):
        assert robustness(g, again) == rho - 0.25


def test_deep_and_long_formulas_need_no_recursion():
    """Nesting as deep as the text allows: parentheses, negations, nexts, a long
    conjunction; printing, NNF, unrolling and evaluation all iterative."""
    deep = parse("(" * 20_000 + "a" + ")" * 20_000)
    assert deep is Prop("a")
    nots = parse("!" * 10_001 + "a")
    assert nnf(nots) is Not(Prop("a"))
    xs = parse("X " * 1000 + "a")
    assert len(subformulas(nnf(Not(xs)))) == 1002 and str(xs).count("X") == 1000
    w = Lasso((), ({"a"},))
    assert holds(xs, w) and not holds(Not(xs), w)
    long = parse(" & ".join(f"a{i}" for i in range(15_000)))
    assert len(props(long)) == 15_000 and holds(long, FiniteWord([{f"a{i}" for i in range(15_000)}]))
    assert parse(str(long)) is long and eval(repr(parse("F a & X b"))) is parse("F a & X b")
    big = parse(f"F[0,{MAX_BOUND}] a")
    assert unrolled_size(big) >= len(subformulas(unroll(big)))
    assert unrolled_size(parse("F[0,5000] a & G[0,5000] b & a U[0,5000] b")) > MAX_FORMULA_SIZE


@pytest.mark.parametrize(
    "text, reason",
    [
        ("F[5,2] a", "bounds"),
        (f"F[0,{MAX_BOUND + 1}] a", "bounds"),
        ("F[0 a", "expected bounds"),
        ("a U[1,x] b", "expected bounds"),
        ("X[1,2] a", "expected a formula"),
        ("F[1,2]", "expected a formula"),
    ],
)
def test_bad_bounds_are_syntax_errors(text, reason):
    with pytest.raises(LtlSyntaxError, match=reason):
        parse(text)


def test_formulas_are_interned_values():
    assert parse("F a & G !b") is And(Finally(Prop("a")), Globally(Not(Prop("b"))))
    assert hash(parse("a U[1,2] b")) == hash(UntilWithin(1, 2, Prop("a"), Prop("b")))
    assert WeakNext(Prop("a")) is not Next(Prop("a")) and children(WeakNext(Prop("a"))) == (Prop("a"),)
    assert str(nnf(parse("!X a"))) == "!X a" and nnf(parse("!X a")) is WeakNext(Not(Prop("a")))

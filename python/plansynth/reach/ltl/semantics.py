"""The semantics of LTL missions on the words plans give (Biere, Heljanko, Junttila,
Latvala, Schuppan, "Linear encoding of bounded LTL model checking", LMCS 2006, Section 2,
for infinite words; De Giacomo and Vardi, "Linear temporal logic and linear dynamic
logic on finite traces", IJCAI 2013, for finite ones); the formulas are those of
:mod:`plansynth.reach.ltl.syntax`.

A word is a sequence of letters, the labels true at each step:

* a *lasso* ``u v^omega`` (:class:`Lasso`): a prefix, then a loop repeated forever;
* a finite plan w_0..w_N **ending at rest** is read as ``w_0..w_{N-1} (w_N)^omega``
  (:func:`finite_word`): the robot stays at its last state, so the last step's labels
  hold forever (``F a``: a is visited; ``G !b``: b is never entered; ``F G c``: the plan
  ends in c);
* a finite plan with a **free end** is the finite word w_0..w_N itself
  (:class:`FiniteWord`), read as LTL on finite traces: ``X f`` is false at the last
  position (strong next) and its dual :class:`~plansynth.reach.ltl.syntax.WeakNext` true;
  ``F``, ``U`` need their witness within the word; ``G``, ``R`` speak of the positions the
  word has. Bounded operators likewise: ``F[a,b]`` and ``U[a,b]`` need a witness at a
  position the word has, ``G[a,b]`` and ``R[a,b]`` hold at the positions past the end.

The bounded operators, at position i: ``F[a,b] f`` when f holds at some i + a .. i + b;
``G[a,b] f`` when at every one; ``f U[a,b] g`` when g holds at some j in i + a .. i + b
and f at every i .. j - 1; ``f R[a,b] g`` is ``!(!f U[a,b] !g)``. A property test checks
them against their unrolling (:func:`~plansynth.reach.ltl.syntax.unroll`).

:func:`holds` evaluates by fixpoints over the word's positions (the least fixpoint for
``U``, the greatest for ``R``), bottom-up over the distinct subformulas (no recursion);
:func:`holds_unrolled` is an independent second formulation, the textbook definitions
with positions folded back into the lasso (the reference the property tests compare
:func:`holds` with; recursive, for small formulas). :func:`robustness` is the same
evaluation over real numbers with max for "or" and min for "and" (the quantitative
semantics of Fainekos and Pappas, TCS 2009, and of STL, Donze and Maler, FORMATS 2010):
given each literal's margin at each step, the largest margin at which the formula holds.

>>> from plansynth.reach.ltl.syntax import parse
>>> holds(parse("G F a & G F b"), Lasso(prefix=(), loop=({"a"}, set(), {"b"})))
True
>>> holds(parse("F G a"), finite_word([{"a"}, set(), {"a"}]))
True
>>> holds(parse("a U b"), finite_word([{"a"}, set(), {"b"}]))
False
>>> holds(parse("G a & F[2,2] true"), FiniteWord([{"a"}, {"a"}, {"a"}])), holds(parse("X a"), FiniteWord([{"a"}]))
(True, False)
>>> robustness(parse("F a & G !b"), FiniteWord([{"a": -1.0, "!b": 2.0}, {"a": 0.5, "!b": 1.0}]))
0.5
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from typing import Any

from plansynth.reach.ltl.syntax import (
    And,
    Const,
    Finally,
    FinallyWithin,
    Formula,
    Globally,
    GloballyWithin,
    Iff,
    Implies,
    Next,
    Not,
    Or,
    Prop,
    Release,
    ReleaseWithin,
    Until,
    UntilWithin,
    WeakNext,
    subformulas,
)

__all__ = [
    "Lasso",
    "FiniteWord",
    "Word",
    "finite_word",
    "holds",
    "holds_at",
    "holds_unrolled",
    "robustness",
    "robustness_at",
    "NEG",
]

#: A literal ``!a`` in a letter of margins (:func:`robustness`) is the key ``"!a"``.
NEG = "!"


# --------------------------------------------------------------------------- words


@dataclass(frozen=True)
class Lasso:
    """The infinite word ``prefix loop loop loop ...`` (``loop`` non-empty); each letter
    is the set of labels true at that step (or, for :func:`robustness`, a mapping from
    literals to margins)."""

    prefix: tuple[Any, ...]
    loop: tuple[Any, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "prefix", tuple(_letter(a) for a in self.prefix))
        object.__setattr__(self, "loop", tuple(_letter(a) for a in self.loop))
        if not self.loop:
            raise ValueError("a lasso needs a non-empty loop")

    @property
    def letters(self) -> tuple[Any, ...]:
        return self.prefix + self.loop

    def successor(self, i: int) -> int:
        """The position after position i (the last one returns to the loop's start)."""
        n = len(self.prefix) + len(self.loop)
        return i + 1 if i + 1 < n else len(self.prefix)

    def ahead(self, i: int, k: int) -> int | None:
        """The position k steps after position i."""
        p, n = len(self.prefix), len(self.prefix) + len(self.loop)
        j = i + k
        return j if j < n else p + (j - p) % (n - p)


@dataclass(frozen=True)
class FiniteWord:
    """The finite word w_0..w_N of a plan with a free end (read as LTL on finite traces;
    see the module doc)."""

    letters: tuple[Any, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "letters", tuple(_letter(a) for a in self.letters))
        if not self.letters:
            raise ValueError("a finite word needs at least one letter")

    @property
    def prefix(self) -> tuple[Any, ...]:
        return self.letters

    def successor(self, i: int) -> int | None:
        """The position after position i (None after the last)."""
        return i + 1 if i + 1 < len(self.letters) else None

    def ahead(self, i: int, k: int) -> int | None:
        j = i + k
        return j if j < len(self.letters) else None


Word = Lasso | FiniteWord


def _letter(a: Any) -> Any:
    return dict(a) if isinstance(a, Mapping) else frozenset(a)


def finite_word(letters: Sequence[Iterable[str]]) -> Lasso:
    """A finite plan's word w_0..w_N, ending at rest, as the lasso ``w_0..w_{N-1} (w_N)^omega``
    (the robot stays at its last state; see the module doc)."""
    ls = [_letter(a) for a in letters]
    if not ls:
        raise ValueError("a finite word needs at least one letter")
    return Lasso(prefix=tuple(ls[:-1]), loop=(ls[-1],))


# --------------------------------------------------------------------------- evaluation


@dataclass(frozen=True)
class _Algebra:
    join: Callable[[Any, Any], Any]  # "or"
    meet: Callable[[Any, Any], Any]  # "and"
    bottom: Any
    top: Any
    negate: Callable[[Any], Any] | None


_BOOL = _Algebra(lambda x, y: x or y, lambda x, y: x and y, False, True, lambda x: not x)
_REAL = _Algebra(max, min, -math.inf, math.inf, None)


def holds(f: Formula, word: Word) -> bool:
    """Does the word satisfy ``f`` (at position 0)?"""
    return holds_at(f, word)[0]


def holds_at(f: Formula, word: Word) -> list[bool]:
    """The truth of ``f`` at every position of the word (fixpoint evaluation: the least
    fixpoint of ``a U b = b | (a & X(a U b))``, the greatest of ``R``)."""

    def literal(name: str, negated: bool, letter: Any) -> bool:
        return (name not in letter) if negated else (name in letter)

    return _evaluate(f, word, _BOOL, literal)


def robustness_at(f: Formula, word: Word) -> list[float]:
    """:func:`robustness` at every position of the word."""

    def literal(name: str, negated: bool, letter: Any) -> float:
        return float(letter.get(NEG + name if negated else name, -math.inf))

    return _evaluate(f, word, _REAL, literal)


def robustness(f: Formula, word: Word) -> float:
    """The robustness of ``f`` (in negation normal form) on a word whose letters map each
    literal (``"a"``, ``"!a"``) to its margin at that step (a missing literal: -inf):
    literals read their margins, "or" is max and "and" min, ``F``/``U`` and ``G``/``R``
    their least and greatest fixpoints over the word, the bounded operators max and min
    over their windows. It is >= r exactly when the formula holds with every literal read
    as "holds" where its margin is >= r."""
    return robustness_at(f, word)[0]


def _evaluate(f: Formula, word: Word, alg: _Algebra, literal) -> list:
    letters = word.letters
    n = len(letters)
    succ = [word.successor(i) for i in range(n)]
    finite = isinstance(word, FiniteWord)
    val: dict[Formula, list] = {}
    join, meet, bot, top = alg.join, alg.meet, alg.bottom, alg.top
    for g in subformulas(f):
        if isinstance(g, Const):
            v = [top if g.value else bot] * n
        elif isinstance(g, Prop):
            v = [literal(g.name, False, a) for a in letters]
        elif isinstance(g, Not):
            if isinstance(g.arg, Prop):
                v = [literal(g.arg.name, True, a) for a in letters]
            elif alg.negate is not None:
                v = [alg.negate(x) for x in val[g.arg]]
            else:
                raise ValueError("robustness needs a formula in negation normal form")
        elif isinstance(g, (And, Or)):
            op = meet if isinstance(g, And) else join
            v = [op(x, y) for x, y in zip(val[g.left], val[g.right])]
        elif isinstance(g, (Implies, Iff)):
            if alg.negate is None:
                raise ValueError("robustness needs a formula in negation normal form")
            a, b = val[g.left], val[g.right]
            v = [((not x) or y) if isinstance(g, Implies) else (x == y) for x, y in zip(a, b)]
        elif isinstance(g, (Next, WeakNext)):
            a = val[g.arg]
            end = bot if isinstance(g, Next) else top
            v = [end if succ[i] is None else a[succ[i]] for i in range(n)]
        elif isinstance(g, (Finally, Until)):
            a = [top] * n if isinstance(g, Finally) else val[g.left]
            b = val[g.arg if isinstance(g, Finally) else g.right]
            v = _fixpoint(a, b, succ, alg, least=True)
        elif isinstance(g, (Globally, Release)):
            a = [bot] * n if isinstance(g, Globally) else val[g.left]
            b = val[g.arg if isinstance(g, Globally) else g.right]
            v = _fixpoint(a, b, succ, alg, least=False)
        elif isinstance(g, (FinallyWithin, GloballyWithin, UntilWithin, ReleaseWithin)):
            v = _window(g, word, n, finite, val, alg)
        else:
            raise TypeError(f"not a formula: {type(g).__name__}")
        val[g] = v
    return val[f]


def _fixpoint(a: list, b: list, succ: list, alg: _Algebra, *, least: bool) -> list:
    """``v_i = b_i | (a_i & v_{i+1})`` (least) or ``b_i & (a_i | v_{i+1})`` (greatest),
    the value past a finite word's end ``bottom`` (least: no witness) or ``top``. On a
    lasso the iteration from the bottom (top) settles within n + 1 rounds."""
    n = len(a)
    join, meet = alg.join, alg.meet
    start = alg.bottom if least else alg.top
    v = [start] * n
    for _ in range(n + 1):
        new = []
        for i in range(n):
            nxt = start if succ[i] is None else v[succ[i]]
            new.append(join(b[i], meet(a[i], nxt)) if least else meet(b[i], join(a[i], nxt)))
        if new == v:
            break
        v = new
    return v


def _window(g: Formula, word: Word, n: int, finite: bool, val: dict, alg: _Algebra) -> list:
    """A bounded operator at every position: its window i + lo .. i + hi, cut to one turn
    of the loop past i + lo (later positions repeat earlier ones, with the "until" side
    condition only harder) or to the end of a finite word."""
    join, meet, bot, top = alg.join, alg.meet, alg.bottom, alg.top
    lo, hi = g.lo, g.hi
    span = min(hi, lo + n)
    out = []
    if isinstance(g, (FinallyWithin, GloballyWithin)):
        a = val[g.arg]
        strong = isinstance(g, FinallyWithin)
        for i in range(n):
            acc = bot if strong else top
            for k in range(lo, span + 1):
                j = word.ahead(i, k)
                if j is None:
                    break  # past the end of a finite word: F has no witness there, G no duty
                acc = join(acc, a[j]) if strong else meet(acc, a[j])
            out.append(acc)
        return out
    a, b = val[g.left], val[g.right]
    strong = isinstance(g, UntilWithin)
    for i in range(n):
        acc = bot if strong else top
        side = top if strong else bot  # "a at every earlier position" (until), "some" (release)
        for k in range(0, span + 1):
            j = word.ahead(i, k)
            if j is None:
                break
            if k >= lo:
                acc = join(acc, meet(b[j], side)) if strong else meet(acc, join(b[j], side))
            side = meet(side, a[j]) if strong else join(side, a[j])
        out.append(acc)
    return out


# --------------------------------------------------------------------------- the reference


def holds_unrolled(f: Formula, word: Word) -> bool:
    """The second formulation: the definitions on the word (``a U b`` at i: some j >= i
    has b, and a holds at i..j-1; ``a R b``: b holds at every j >= i up to and including
    the first j with a; the bounded operators over their windows), positions j >=
    len(prefix) of a lasso folded into the loop. Only the first ``len(prefix) +
    len(loop)`` positions from i need looking at: after them the folded positions repeat.
    A finite word (free end) has no positions past its last. Recursive: a reference for
    small formulas (the tests)."""
    letters = word.letters
    n = len(letters)
    finite = isinstance(word, FiniteWord)
    p = len(word.prefix)

    def fold(j: int) -> int | None:
        if finite:
            return j if j < n else None
        return j if j < p else p + (j - p) % (n - p)

    def span(i: int) -> range:
        return range(i, n) if finite else range(i, i + n)

    @cache
    def at(g: Formula, i: int | None) -> bool:
        if i is None:  # past the end of a finite word
            raise AssertionError("no position")
        if isinstance(g, Const):
            return g.value
        if isinstance(g, Prop):
            return g.name in letters[i]
        if isinstance(g, Not):
            return not at(g.arg, i)
        if isinstance(g, And):
            return at(g.left, i) and at(g.right, i)
        if isinstance(g, Or):
            return at(g.left, i) or at(g.right, i)
        if isinstance(g, Implies):
            return (not at(g.left, i)) or at(g.right, i)
        if isinstance(g, Iff):
            return at(g.left, i) == at(g.right, i)
        if isinstance(g, (Next, WeakNext)):
            j = fold(i + 1)
            return (isinstance(g, WeakNext)) if j is None else at(g.arg, j)
        if isinstance(g, Finally):
            return any(at(g.arg, fold(j)) for j in span(i))
        if isinstance(g, Globally):
            return all(at(g.arg, fold(j)) for j in span(i))
        if isinstance(g, Until):
            for j in span(i):
                if at(g.right, fold(j)):
                    return True
                if not at(g.left, fold(j)):
                    return False
            return False
        if isinstance(g, Release):
            for j in span(i):
                if not at(g.right, fold(j)):
                    return False
                if at(g.left, fold(j)):
                    return True
            return True
        if isinstance(g, (FinallyWithin, GloballyWithin)):
            window = [fold(i + k) for k in range(g.lo, g.hi + 1)]
            window = [j for j in window if j is not None]
            if isinstance(g, FinallyWithin):
                return any(at(g.arg, j) for j in window)
            return all(at(g.arg, j) for j in window)
        if isinstance(g, (UntilWithin, ReleaseWithin)):
            until = isinstance(g, UntilWithin)
            for k in range(g.lo, g.hi + 1):
                j = fold(i + k)
                if j is None:
                    break
                before = [fold(i + m) for m in range(k)]
                if until and at(g.right, j) and all(at(g.left, q) for q in before):
                    return True
                if not until and not at(g.right, j) and not any(at(g.left, q) for q in before):
                    return False
            return not until
        raise TypeError(f"not a formula: {g!r}")

    return at(f, 0)

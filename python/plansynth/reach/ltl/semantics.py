"""The semantics of LTL missions on the two shapes of infinite words a plan gives
(Biere, Heljanko, Junttila, Latvala, Schuppan, "Linear encoding of bounded LTL model
checking", LMCS 2006, Section 2); the formulas are those of
:mod:`plansynth.reach.ltl.syntax`.

A word is a sequence of label sets (the labels true at each step):

* a *lasso* ``u v^omega`` (:class:`Lasso`): a prefix, then a loop repeated forever;
* a *finite* plan w_0..w_N is read as ``w_0..w_{N-1} (w_N)^omega``: the robot stops in
  its last region, so the last step's labels hold forever (the "stays put" reading; it
  makes ``F a`` mean "a is visited", ``G !b`` mean "b is never entered" and ``F G c``
  mean "the plan ends in c").

:func:`holds` evaluates by fixpoints over the lasso's positions (the least fixpoint
for ``U``, the greatest for ``R``); :func:`holds_unrolled` is an independent second
formulation, the textbook definitions over the infinite word with positions folded
back into the lasso (the reference the property tests compare :func:`holds` with).

>>> from plansynth.reach.ltl.syntax import parse
>>> holds(parse("G F a & G F b"), Lasso(prefix=(), loop=({"a"}, set(), {"b"})))
True
>>> holds(parse("F G a"), finite_word([{"a"}, set(), {"a"}]))
True
>>> holds(parse("a U b"), finite_word([{"a"}, set(), {"b"}]))
False
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import cache

from plansynth.reach.ltl.syntax import (
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Iff,
    Implies,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
)

__all__ = ["Lasso", "finite_word", "holds", "holds_at", "holds_unrolled"]


# --------------------------------------------------------------------------- words


@dataclass(frozen=True)
class Lasso:
    """The infinite word ``prefix loop loop loop ...`` (``loop`` non-empty); each letter
    is the set of labels true at that step."""

    prefix: tuple[frozenset[str], ...]
    loop: tuple[frozenset[str], ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "prefix", tuple(frozenset(a) for a in self.prefix))
        object.__setattr__(self, "loop", tuple(frozenset(a) for a in self.loop))
        if not self.loop:
            raise ValueError("a lasso needs a non-empty loop")

    @property
    def letters(self) -> tuple[frozenset[str], ...]:
        return self.prefix + self.loop

    def successor(self, i: int) -> int:
        """The position after position i (the last one returns to the loop's start)."""
        n = len(self.prefix) + len(self.loop)
        return i + 1 if i + 1 < n else len(self.prefix)


def finite_word(letters: Sequence[Iterable[str]]) -> Lasso:
    """A finite plan's word w_0..w_N as the lasso ``w_0..w_{N-1} (w_N)^omega`` (the
    robot stays in its last region; see the module doc)."""
    ls = [frozenset(a) for a in letters]
    if not ls:
        raise ValueError("a finite word needs at least one letter")
    return Lasso(prefix=tuple(ls[:-1]), loop=(ls[-1],))


def holds(f: Formula, word: Lasso) -> bool:
    """Does the word satisfy ``f`` (at position 0)?"""
    return holds_at(f, word)[0]


def holds_at(f: Formula, word: Lasso) -> list[bool]:
    """The truth of ``f`` at every position of the lasso (fixpoint evaluation: the least
    fixpoint of ``a U b = b | (a & X(a U b))``, the greatest of ``R``)."""
    letters = word.letters
    n = len(letters)
    succ = [word.successor(i) for i in range(n)]
    memo: dict[Formula, list[bool]] = {}

    def ev(g: Formula) -> list[bool]:
        if g in memo:
            return memo[g]
        if isinstance(g, Const):
            v = [g.value] * n
        elif isinstance(g, Prop):
            v = [g.name in a for a in letters]
        elif isinstance(g, Not):
            v = [not x for x in ev(g.arg)]
        elif isinstance(g, And):
            v = [x and y for x, y in zip(ev(g.left), ev(g.right))]
        elif isinstance(g, Or):
            v = [x or y for x, y in zip(ev(g.left), ev(g.right))]
        elif isinstance(g, Implies):
            v = [(not x) or y for x, y in zip(ev(g.left), ev(g.right))]
        elif isinstance(g, Iff):
            v = [x == y for x, y in zip(ev(g.left), ev(g.right))]
        elif isinstance(g, Next):
            a = ev(g.arg)
            v = [a[succ[i]] for i in range(n)]
        elif isinstance(g, (Finally, Until)):
            a = [True] * n if isinstance(g, Finally) else ev(g.left)
            b = ev(g.arg if isinstance(g, Finally) else g.right)
            v = _fixpoint(a, b, succ, least=True)
        elif isinstance(g, (Globally, Release)):
            a = [False] * n if isinstance(g, Globally) else ev(g.left)
            b = ev(g.arg if isinstance(g, Globally) else g.right)
            v = _fixpoint(a, b, succ, least=False)
        else:
            raise TypeError(f"not a formula: {g!r}")
        memo[g] = v
        return v

    return ev(f)


def _fixpoint(a: list[bool], b: list[bool], succ: list[int], *, least: bool) -> list[bool]:
    n = len(a)
    v = [not least] * n
    for _ in range(n + 1):
        new = [(b[i] or (a[i] and v[succ[i]])) if least else (b[i] and (a[i] or v[succ[i]])) for i in range(n)]
        if new == v:
            break
        v = new
    return v


def holds_unrolled(f: Formula, word: Lasso) -> bool:
    """The second formulation: the definitions on infinite words (``a U b`` at i: some
    j >= i has b, and a holds at i..j-1; ``a R b``: b holds at every j >= i up to and
    including the first j with a), positions j >= len(prefix) folded into the loop.
    Only the first ``len(prefix) + len(loop)`` positions from i need looking at: after
    them the folded positions repeat."""
    letters = word.letters
    p, n = len(word.prefix), len(letters)

    def fold(j: int) -> int:
        return j if j < p else p + (j - p) % (n - p)

    @cache
    def at(g: Formula, i: int) -> bool:
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
        if isinstance(g, Next):
            return at(g.arg, fold(i + 1))
        if isinstance(g, Finally):
            return any(at(g.arg, fold(j)) for j in range(i, i + n))
        if isinstance(g, Globally):
            return all(at(g.arg, fold(j)) for j in range(i, i + n))
        if isinstance(g, Until):
            for j in range(i, i + n):
                if at(g.right, fold(j)):
                    return True
                if not at(g.left, fold(j)):
                    return False
            return False
        if isinstance(g, Release):
            for j in range(i, i + n):
                if not at(g.right, fold(j)):
                    return False
                if at(g.left, fold(j)):
                    return True
            return True
        raise TypeError(f"not a formula: {g!r}")

    return at(f, 0)

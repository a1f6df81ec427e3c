"""Linear temporal logic over label names: syntax, negation normal form, semantics.

The missions of reach-avoid planning (Shoukry et al., CDC 2016, Sections I and IV name
LTL as the direct extension; the encoding is in :mod:`plansynth.reach.mission.bmc`).

**Syntax** (lowest binding first; binary operators of one level associate to the right)::

    f ::= f <-> f                    equivalence
        | f -> f                     implication
        | f | f                      disjunction
        | f & f                      conjunction
        | f U f | f R f              until, release
        | ! f | X f | F f | G f      not, next, eventually, always
        | ( f ) | true | false | name

``name`` is a label: a letter or ``_`` followed by letters, digits and ``_``; the
keywords ``X F G U R true false`` are not names. So ``F a & G !b`` is ``(F a) & (G !b)``
and ``a U b & c`` is ``(a U b) & c``, as in Spot and NuSMV.

>>> parse("F (kitchen & F lab) & G !stairs")
And(left=Finally(arg=And(left=Prop(name='kitchen'), right=Finally(arg=Prop(name='lab')))), right=Globally(arg=Not(arg=Prop(name='stairs'))))
>>> str(parse("a -> b -> c <-> !d"))
'((a -> (b -> c)) <-> !d)'

**Semantics.** A word is a sequence of label sets (the labels true at each step). Plans
are judged on infinite words in two shapes (Biere, Heljanko, Junttila, Latvala,
Schuppan, "Linear encoding of bounded LTL model checking", LMCS 2006, Section 2):

* a *lasso* ``u v^omega`` (:class:`Lasso`): a prefix, then a loop repeated forever;
* a *finite* plan w_0..w_N is read as ``w_0..w_{N-1} (w_N)^omega``: the robot stops in
  its last region, so the last step's labels hold forever (the "stays put" reading; it
  makes ``F a`` mean "a is visited", ``G !b`` mean "b is never entered" and ``F G c``
  mean "the plan ends in c").

:func:`holds` evaluates by fixpoints over the lasso's positions (the least fixpoint
for ``U``, the greatest for ``R``); :func:`holds_unrolled` is an independent second
formulation, the textbook definitions over the infinite word with positions folded
back into the lasso (used as the oracle of the property tests).

>>> holds(parse("G F a & G F b"), Lasso(prefix=(), loop=({"a"}, set(), {"b"})))
True
>>> holds(parse("F G a"), finite_word([{"a"}, set(), {"a"}]))
True
>>> holds(parse("a U b"), finite_word([{"a"}, set(), {"b"}]))
False
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Union

__all__ = [
    "Formula",
    "Const",
    "Prop",
    "Not",
    "And",
    "Or",
    "Implies",
    "Iff",
    "Next",
    "Finally",
    "Globally",
    "Until",
    "Release",
    "LtlSyntaxError",
    "parse",
    "nnf",
    "props",
    "subformulas",
    "Lasso",
    "finite_word",
    "holds",
    "holds_at",
    "holds_unrolled",
    "KEYWORDS",
]

KEYWORDS = frozenset({"X", "F", "G", "U", "R", "true", "false"})


# --------------------------------------------------------------------------- AST


@dataclass(frozen=True)
class Const:
    value: bool

    def __str__(self) -> str:
        return "true" if self.value else "false"


@dataclass(frozen=True)
class Prop:
    name: str

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class Not:
    arg: "Formula"

    def __str__(self) -> str:
        return f"!{self.arg}"


@dataclass(frozen=True)
class _Binary:
    left: "Formula"
    right: "Formula"
    symbol = "?"

    def __str__(self) -> str:
        return f"({self.left} {self.symbol} {self.right})"


@dataclass(frozen=True)
class And(_Binary):
    symbol = "&"


@dataclass(frozen=True)
class Or(_Binary):
    symbol = "|"


@dataclass(frozen=True)
class Implies(_Binary):
    symbol = "->"


@dataclass(frozen=True)
class Iff(_Binary):
    symbol = "<->"


@dataclass(frozen=True)
class Until(_Binary):
    symbol = "U"


@dataclass(frozen=True)
class Release(_Binary):
    symbol = "R"


@dataclass(frozen=True)
class Next:
    arg: "Formula"

    def __str__(self) -> str:
        return f"X {self.arg}"


@dataclass(frozen=True)
class Finally:
    arg: "Formula"

    def __str__(self) -> str:
        return f"F {self.arg}"


@dataclass(frozen=True)
class Globally:
    arg: "Formula"

    def __str__(self) -> str:
        return f"G {self.arg}"


Formula = Union[Const, Prop, Not, And, Or, Implies, Iff, Next, Finally, Globally, Until, Release]
_UNARY = {"!": Not, "X": Next, "F": Finally, "G": Globally}


# --------------------------------------------------------------------------- parser


class LtlSyntaxError(ValueError):
    """A mission string that is not a formula; ``position`` is the 0-based offset."""

    def __init__(self, text: str, position: int, reason: str) -> None:
        self.text, self.position, self.reason = text, position, reason
        super().__init__(f"{reason} at position {position} of {text!r}")


_TOKEN = re.compile(r"\s*(?:(<->|->|[!&|()])|([A-Za-z_][A-Za-z0-9_]*))")


def _tokens(text: str) -> list[tuple[str, int]]:
    out, pos = [], 0
    while pos < len(text):
        if text[pos:].strip() == "":
            break
        m = _TOKEN.match(text, pos)
        if m is None:
            at = pos + len(text[pos:]) - len(text[pos:].lstrip())
            raise LtlSyntaxError(text, at, f"unexpected character {text[at]!r}")
        tok = m.group(1) or m.group(2)
        out.append((tok, m.start(1) if m.group(1) else m.start(2)))
        pos = m.end()
    out.append(("<end>", len(text)))
    return out


def parse(text: str) -> Formula:
    """Parse a mission string into a :data:`Formula` (syntax in the module doc).

    >>> parse("!a U (b R c)")
    Until(left=Not(arg=Prop(name='a')), right=Release(left=Prop(name='b'), right=Prop(name='c')))
    >>> parse("a &")
    Traceback (most recent call last):
    ...
    plansynth.reach.mission.ltl.LtlSyntaxError: expected a formula, got end of input at position 3 of 'a &'
    """
    toks = _tokens(text)
    i = 0

    def peek() -> str:
        return toks[i][0]

    def take() -> tuple[str, int]:
        nonlocal i
        t = toks[i]
        i += 1
        return t

    def binary(level: int) -> Formula:
        ops = _LEVELS[level]
        left = binary(level + 1) if level + 1 < len(_LEVELS) else unary()
        if peek() in ops:
            op = take()[0]
            right = binary(level)  # right-associative
            return ops[op](left, right)
        return left

    def unary() -> Formula:
        tok, at = toks[i]
        if tok in _UNARY:
            take()
            return _UNARY[tok](unary())
        if tok == "(":
            take()
            f = binary(0)
            if peek() != ")":
                raise LtlSyntaxError(text, toks[i][1], f"expected ')', got {_show(peek())}")
            take()
            return f
        if tok in ("true", "false"):
            take()
            return Const(tok == "true")
        if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", tok) and tok not in KEYWORDS:
            take()
            return Prop(tok)
        raise LtlSyntaxError(text, at, f"expected a formula, got {_show(tok)}")

    f = binary(0)
    if peek() != "<end>":
        raise LtlSyntaxError(text, toks[i][1], f"unexpected {_show(peek())} after a complete formula")
    return f


_LEVELS: list[dict[str, type]] = [{"<->": Iff}, {"->": Implies}, {"|": Or}, {"&": And}, {"U": Until, "R": Release}]


def _show(tok: str) -> str:
    return "end of input" if tok == "<end>" else repr(tok)


# --------------------------------------------------------------------------- transformations


def props(f: Formula) -> frozenset[str]:
    """The label names a formula mentions.

    >>> sorted(props(parse("F a & (b U !a)")))
    ['a', 'b']
    """
    if isinstance(f, Prop):
        return frozenset({f.name})
    if isinstance(f, Const):
        return frozenset()
    if isinstance(f, (Not, Next, Finally, Globally)):
        return props(f.arg)
    return props(f.left) | props(f.right)


def nnf(f: Formula, negate: bool = False) -> Formula:
    """Negation normal form: only ``Not(Prop)``; no ``->``/``<->``; ``X F G U R & |``
    otherwise (``!X a = X !a``, ``!(a U b) = !a R !b``, ``!F a = G !a``).

    >>> str(nnf(parse("!(a U (b -> X c))")))
    '(!a R (b & X !c))'
    """
    if isinstance(f, Const):
        return Const(f.value != negate)
    if isinstance(f, Prop):
        return Not(f) if negate else f
    if isinstance(f, Not):
        return nnf(f.arg, not negate)
    if isinstance(f, And):
        return (Or if negate else And)(nnf(f.left, negate), nnf(f.right, negate))
    if isinstance(f, Or):
        return (And if negate else Or)(nnf(f.left, negate), nnf(f.right, negate))
    if isinstance(f, Implies):
        return nnf(Or(Not(f.left), f.right), negate)
    if isinstance(f, Iff):
        return nnf(Or(And(f.left, f.right), And(Not(f.left), Not(f.right))), negate)
    if isinstance(f, Next):
        return Next(nnf(f.arg, negate))
    if isinstance(f, Finally):
        return (Globally if negate else Finally)(nnf(f.arg, negate))
    if isinstance(f, Globally):
        return (Finally if negate else Globally)(nnf(f.arg, negate))
    if isinstance(f, Until):
        return (Release if negate else Until)(nnf(f.left, negate), nnf(f.right, negate))
    if isinstance(f, Release):
        return (Until if negate else Release)(nnf(f.left, negate), nnf(f.right, negate))
    raise TypeError(f"not a formula: {f!r}")


def subformulas(f: Formula) -> list[Formula]:
    """Every distinct subformula, children before parents (so bottom-up passes can run
    in list order)."""
    out: list[Formula] = []
    seen: set[Formula] = set()

    def walk(g: Formula) -> None:
        if g in seen:
            return
        for child in _children(g):
            walk(child)
        seen.add(g)
        out.append(g)

    walk(f)
    return out


def _children(f: Formula) -> tuple[Formula, ...]:
    if isinstance(f, (Const, Prop)):
        return ()
    if isinstance(f, (Not, Next, Finally, Globally)):
        return (f.arg,)
    return (f.left, f.right)


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

    @lru_cache(maxsize=None)
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

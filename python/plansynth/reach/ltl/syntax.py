"""Linear temporal logic over label names: the formulas, their parser and negation
normal form (the mission language of reach-avoid problems: Shoukry et al., CDC 2016,
Sections I and IV name LTL as the direct extension of the planner; the encoding is in
:mod:`plansynth.reach.mission.bmc`, the semantics in :mod:`plansynth.reach.ltl.semantics`).

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
"""

from __future__ import annotations

import re
from dataclasses import dataclass

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
    "children",
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
    arg: Formula

    def __str__(self) -> str:
        return f"!{self.arg}"


@dataclass(frozen=True)
class _Binary:
    left: Formula
    right: Formula
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
    arg: Formula

    def __str__(self) -> str:
        return f"X {self.arg}"


@dataclass(frozen=True)
class Finally:
    arg: Formula

    def __str__(self) -> str:
        return f"F {self.arg}"


@dataclass(frozen=True)
class Globally:
    arg: Formula

    def __str__(self) -> str:
        return f"G {self.arg}"


Formula = Const | Prop | Not | And | Or | Implies | Iff | Next | Finally | Globally | Until | Release
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
    plansynth.reach.ltl.syntax.LtlSyntaxError: expected a formula, got end of input at position 3 of 'a &'
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
        for child in children(g):
            walk(child)
        seen.add(g)
        out.append(g)

    walk(f)
    return out


def children(f: Formula) -> tuple[Formula, ...]:
    """The direct subformulas of ``f`` (none for a constant or a label)."""
    if isinstance(f, (Const, Prop)):
        return ()
    if isinstance(f, (Not, Next, Finally, Globally)):
        return (f.arg,)
    return (f.left, f.right)

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
        | f U[a,b] f | f R[a,b] f    until within steps a..b, its dual
        | ! f | X f | F f | G f      not, next, eventually, always
        | F[a,b] f | G[a,b] f        eventually within steps a..b, always over them
        | ( f ) | true | false | name

``name`` is a label: a letter or ``_`` followed by letters, digits and ``_``; the
keywords ``X F G U R true false`` are not names. So ``F a & G !b`` is ``(F a) & (G !b)``
and ``a U b & c`` is ``(a U b) & c``, as in Spot and NuSMV. The bounds of the bounded
operators (metric temporal logic's discrete-time intervals, as STL planners write them:
``F[0,25] goal`` "within 25 steps", ``G[0,4] dwell`` "for 5 steps") are whole numbers of
steps ``0 <= a <= b <= MAX_BOUND``, counted from the position where the operator is read.

**Limits** (checked at the door by the problem value, documented in the format's
reference): a mission text of at most :data:`MAX_MISSION_CHARS` characters, bounds of at
most :data:`MAX_BOUND` steps, and at most :data:`MAX_FORMULA_SIZE` distinct subformulas
once the bounded operators are unrolled (:func:`unrolled_size`). Every function here is
iterative, so a legal formula may nest as deep as its length allows (10,000 ``!``, 1,000
``X``, parentheses 100,000 deep).

**Formulas are shared values.** Equal formulas are the same object (each node is
interned when it is made), so equality is identity and hashing is constant time, however
deep the formula: a dictionary keyed by subformulas never walks a tree.

>>> parse("F (kitchen & F lab) & G !stairs")
And(left=Finally(arg=And(left=Prop(name='kitchen'), right=Finally(arg=Prop(name='lab')))), right=Globally(arg=Not(arg=Prop(name='stairs'))))
>>> str(parse("a -> b -> c <-> !d"))
'((a -> (b -> c)) <-> !d)'
>>> str(parse("F[0,25] goal & G[2,6] (a U[0,3] b)"))
'(F[0,25] goal & G[2,6] (a U[0,3] b))'
>>> parse("a & b") is parse("(a) & ((b))")
True
"""

from __future__ import annotations

import functools
import itertools
import re
import weakref
from dataclasses import dataclass, fields
from typing import Any, ClassVar

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
    "WeakNext",
    "Finally",
    "Globally",
    "Until",
    "Release",
    "FinallyWithin",
    "GloballyWithin",
    "UntilWithin",
    "ReleaseWithin",
    "LtlSyntaxError",
    "parse",
    "nnf",
    "unroll",
    "unrolled_size",
    "props",
    "subformulas",
    "children",
    "KEYWORDS",
    "MAX_MISSION_CHARS",
    "MAX_BOUND",
    "MAX_FORMULA_SIZE",
]

KEYWORDS = frozenset({"X", "F", "G", "U", "R", "true", "false"})

#: Longest mission text, in characters (a longer one is refused at the door).
MAX_MISSION_CHARS = 100_000
#: Largest bound b of ``F[a,b]``, ``G[a,b]``, ``U[a,b]``, ``R[a,b]`` (steps; the largest
#: horizon a problem may ask for).
MAX_BOUND = 10_000
#: Most distinct subformulas of a mission once its bounded operators are unrolled
#: (:func:`unrolled_size`): the encodings have one variable per subformula and step.
MAX_FORMULA_SIZE = 20_000


# --------------------------------------------------------------------------- AST

_TABLE: weakref.WeakValueDictionary = weakref.WeakValueDictionary()
_SERIAL = itertools.count()


class _Node:
    """Interned formula nodes: ``Cls(*fields)`` returns the one live node with these
    fields (children compared by identity, which interning makes structural equality),
    with its hash computed once from its children's. Equality is identity."""

    _fields: ClassVar[tuple[str, ...]] = ()

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        if kwargs:
            names = cls._fields or tuple(f.name for f in fields(cls))
            args = args + tuple(kwargs[n] for n in names[len(args) :])
        key = (cls, *(id(a) if isinstance(a, _Node) else a for a in args))
        node = _TABLE.get(key)
        if node is None:
            node = object.__new__(cls)
            object.__setattr__(node, "_hash", hash((cls.__name__, *(hash(a) for a in args))))
            object.__setattr__(node, "_serial", next(_SERIAL))
            _TABLE[key] = node
        return node

    def __hash__(self) -> int:
        return self._hash  # type: ignore[attr-defined]

    def __eq__(self, other: object) -> bool:
        return self is other

    def __reduce__(self) -> tuple:
        return (type(self), tuple(getattr(self, f.name) for f in fields(self)))  # type: ignore[arg-type]

    def __repr__(self) -> str:
        return _render(self, _repr_parts)

    def __str__(self) -> str:
        return _render(self, _str_parts)

    @property
    def order(self) -> int:
        """A creation number: a deterministic sort key within a process (where ``repr``
        would walk the tree)."""
        return self._serial  # type: ignore[attr-defined]


@dataclass(frozen=True, eq=False, repr=False)
class Const(_Node):
    value: bool


@dataclass(frozen=True, eq=False, repr=False)
class Prop(_Node):
    name: str


@dataclass(frozen=True, eq=False, repr=False)
class Not(_Node):
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class _Binary(_Node):
    left: Formula
    right: Formula
    symbol: ClassVar[str] = "?"


@dataclass(frozen=True, eq=False, repr=False)
class And(_Binary):
    symbol: ClassVar[str] = "&"


@dataclass(frozen=True, eq=False, repr=False)
class Or(_Binary):
    symbol: ClassVar[str] = "|"


@dataclass(frozen=True, eq=False, repr=False)
class Implies(_Binary):
    symbol: ClassVar[str] = "->"


@dataclass(frozen=True, eq=False, repr=False)
class Iff(_Binary):
    symbol: ClassVar[str] = "<->"


@dataclass(frozen=True, eq=False, repr=False)
class Until(_Binary):
    symbol: ClassVar[str] = "U"


@dataclass(frozen=True, eq=False, repr=False)
class Release(_Binary):
    symbol: ClassVar[str] = "R"


@dataclass(frozen=True, eq=False, repr=False)
class Next(_Node):
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class WeakNext(_Node):
    """``X`` that also holds at the last position of a finite word (the dual of the
    strong ``X``: ``!X a`` is ``WeakNext(!a)``). On infinite words it is ``X``. It is
    written ``!X !a``; negation normal form makes it."""

    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class Finally(_Node):
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class Globally(_Node):
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class FinallyWithin(_Node):
    """``F[lo,hi] arg``: arg holds at some position i + lo .. i + hi."""

    lo: int
    hi: int
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class GloballyWithin(_Node):
    """``G[lo,hi] arg``: arg holds at every position i + lo .. i + hi (of those a finite
    word has)."""

    lo: int
    hi: int
    arg: Formula


@dataclass(frozen=True, eq=False, repr=False)
class UntilWithin(_Node):
    """``left U[lo,hi] right``: right holds at some j in i + lo .. i + hi, and left at
    every position i .. j - 1."""

    lo: int
    hi: int
    left: Formula
    right: Formula
    symbol: ClassVar[str] = "U"


@dataclass(frozen=True, eq=False, repr=False)
class ReleaseWithin(_Node):
    """``left R[lo,hi] right``, the dual: ``!(!left U[lo,hi] !right)``."""

    lo: int
    hi: int
    left: Formula
    right: Formula
    symbol: ClassVar[str] = "R"


Formula = (
    Const
    | Prop
    | Not
    | And
    | Or
    | Implies
    | Iff
    | Next
    | WeakNext
    | Finally
    | Globally
    | Until
    | Release
    | FinallyWithin
    | GloballyWithin
    | UntilWithin
    | ReleaseWithin
)
_UNARY = {"!": Not, "X": Next, "F": Finally, "G": Globally}
_UNARY_WITHIN = {"F": FinallyWithin, "G": GloballyWithin}
_BINARY_WITHIN = {"U": UntilWithin, "R": ReleaseWithin}
_ONE_CHILD = (Not, Next, WeakNext, Finally, Globally)
_BOUNDED = (FinallyWithin, GloballyWithin, UntilWithin, ReleaseWithin)


def children(f: Formula) -> tuple[Formula, ...]:
    """The direct subformulas of ``f`` (none for a constant or a label)."""
    if isinstance(f, (Const, Prop)):
        return ()
    if isinstance(f, (*_ONE_CHILD, FinallyWithin, GloballyWithin)):
        return (f.arg,)
    return (f.left, f.right)


# --------------------------------------------------------------------------- printing


def _repr_parts(f: Formula) -> tuple[list[str], list[Formula]]:
    """``repr`` as text pieces around the children (the dataclass layout)."""
    name = type(f).__name__
    if isinstance(f, Const):
        return [f"Const(value={f.value!r})"], []
    if isinstance(f, Prop):
        return [f"Prop(name={f.name!r})"], []
    if isinstance(f, (FinallyWithin, GloballyWithin)):
        return [f"{name}(lo={f.lo!r}, hi={f.hi!r}, arg=", ")"], [f.arg]
    if isinstance(f, (UntilWithin, ReleaseWithin)):
        return [f"{name}(lo={f.lo!r}, hi={f.hi!r}, left=", ", right=", ")"], [f.left, f.right]
    if isinstance(f, _ONE_CHILD):
        return [f"{name}(arg=", ")"], [f.arg]
    return [f"{name}(left=", ", right=", ")"], [f.left, f.right]


def _str_parts(f: Formula) -> tuple[list[str], list[Formula]]:
    """The formula's text (parsed back by :func:`parse` to the same formula)."""
    if isinstance(f, Const):
        return ["true" if f.value else "false"], []
    if isinstance(f, Prop):
        return [f.name], []
    if isinstance(f, Not):
        return ["!", ""], [f.arg]
    if isinstance(f, Next):
        return ["X ", ""], [f.arg]
    if isinstance(f, WeakNext):  # written as the dual of X: !X !f (and !X g for f = !g)
        return (["!X ", ""], [f.arg.arg]) if isinstance(f.arg, Not) else (["!X !", ""], [f.arg])
    if isinstance(f, Finally):
        return ["F ", ""], [f.arg]
    if isinstance(f, Globally):
        return ["G ", ""], [f.arg]
    if isinstance(f, FinallyWithin):
        return [f"F[{f.lo},{f.hi}] ", ""], [f.arg]
    if isinstance(f, GloballyWithin):
        return [f"G[{f.lo},{f.hi}] ", ""], [f.arg]
    if isinstance(f, (UntilWithin, ReleaseWithin)):
        return ["(", f" {f.symbol}[{f.lo},{f.hi}] ", ")"], [f.left, f.right]
    return ["(", f" {f.symbol} ", ")"], [f.left, f.right]


def _render(f: Formula, parts) -> str:
    """Text of ``f`` from ``parts(node) -> (pieces, children)`` (pieces interleave the
    children's texts), without recursion."""
    out: list[str] = []
    stack: list[Any] = [f]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.append(item)
            continue
        pieces, kids = parts(item)
        seq: list[Any] = [pieces[0]]
        for k, child in enumerate(kids):
            seq += [child, pieces[k + 1]]
        stack.extend(reversed(seq))
    return "".join(out)


# --------------------------------------------------------------------------- parser


class LtlSyntaxError(ValueError):
    """A mission string that is not a formula; ``position`` is the 0-based offset."""

    def __init__(self, text: str, position: int, reason: str) -> None:
        self.text, self.position, self.reason = text, position, reason
        shown = text if len(text) <= 80 else text[:77] + "..."
        super().__init__(f"{reason} at position {position} of {shown!r}")


_TOKEN = re.compile(r"\s*(?:(<->|->|[!&|()\[\],])|([A-Za-z_][A-Za-z0-9_]*)|([0-9]+)|(\S))")
_LEVEL = {"<->": 0, "->": 1, "|": 2, "&": 3, "U": 4, "R": 4}
_BINARY = {"<->": Iff, "->": Implies, "|": Or, "&": And, "U": Until, "R": Release}
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _tokens(text: str) -> list[tuple[str, int]]:
    """The tokens and their offsets, in one linear scan."""
    out = []
    for m in _TOKEN.finditer(text):
        if m.group(4) is not None:
            raise LtlSyntaxError(text, m.start(4), f"unexpected character {m.group(4)!r}")
        k = next(i for i in (1, 2, 3) if m.group(i) is not None)
        out.append((m.group(k), m.start(k)))
    out.append(("<end>", len(text)))
    return out


def _show(tok: str) -> str:
    return "end of input" if tok == "<end>" else repr(tok)


def parse(text: str) -> Formula:
    """Parse a mission string into a :data:`Formula` (syntax in the module doc), in one
    pass with explicit stacks (operator precedence), so nesting depth costs no recursion.
    The last few texts' formulas are kept (a problem value checks its mission each time it
    is made, and the planners and the checker read it again).

    >>> parse("!a U (b R c)")
    Until(left=Not(arg=Prop(name='a')), right=Release(left=Prop(name='b'), right=Prop(name='c')))
    >>> parse("F[2,5] a")
    FinallyWithin(lo=2, hi=5, arg=Prop(name='a'))
    >>> parse("a &")
    Traceback (most recent call last):
    ...
    plansynth.reach.ltl.syntax.LtlSyntaxError: expected a formula, got end of input at position 3 of 'a &'
    >>> parse("F[5,2] a")
    Traceback (most recent call last):
    ...
    plansynth.reach.ltl.syntax.LtlSyntaxError: bounds [5,2]: expected 0 <= a <= b <= 10000 at position 1 of 'F[5,2] a'
    """
    return _parse(text)


@functools.lru_cache(maxsize=32)
def _parse(text: str) -> Formula:
    toks = _tokens(text)
    i = 0
    operands: list[Formula] = []
    # operators: ("un", make) for prefix operators, ("bin", level, make), ("(", offset)
    ops: list[tuple] = []

    def bounds(at: int) -> tuple[int, int] | None:
        """``[a,b]`` right after an operator token (i points past the operator)."""
        nonlocal i
        if toks[i][0] != "[":
            return None
        start = toks[i][1]
        got = [t for t, _ in toks[i : i + 5]]
        if len(got) < 5 or got[2] != "," or got[4] != "]" or not got[1].isdigit() or not got[3].isdigit():
            raise LtlSyntaxError(text, start, "expected bounds [a,b] of whole numbers of steps")
        lo, hi = (int(g) if len(g) <= 9 else MAX_BOUND + 1 for g in (got[1], got[3]))
        if not 0 <= lo <= hi <= MAX_BOUND:
            raise LtlSyntaxError(text, start, f"bounds [{got[1]},{got[3]}]: expected 0 <= a <= b <= {MAX_BOUND}")
        i += 5
        return lo, hi

    def reduce_binary() -> None:
        _, _, make = ops.pop()
        right = operands.pop()
        left = operands.pop()
        operands.append(make(left, right))

    def reduce_unary_ops() -> None:
        while ops and ops[-1][0] == "un":
            operands.append(ops.pop()[1](operands.pop()))

    expect_operand = True
    while True:
        tok, at = toks[i]
        if expect_operand:
            i += 1
            if tok in _UNARY:
                b = bounds(at) if tok in _UNARY_WITHIN else None
                if b is None:
                    ops.append(("un", _UNARY[tok]))
                else:
                    lo, hi, make = b[0], b[1], _UNARY_WITHIN[tok]
                    ops.append(("un", lambda f, lo=lo, hi=hi, make=make: make(lo, hi, f)))
            elif tok == "(":
                ops.append(("(", at))
            elif tok in ("true", "false"):
                operands.append(Const(tok == "true"))
                expect_operand = False
            elif _NAME.fullmatch(tok) and tok not in KEYWORDS:
                operands.append(Prop(tok))
                expect_operand = False
            else:
                raise LtlSyntaxError(text, at, f"expected a formula, got {_show(tok)}")
            if not expect_operand:
                reduce_unary_ops()
            continue
        # after a complete operand: a binary operator, ')' or the end
        if tok in _BINARY:
            i += 1
            level = _LEVEL[tok]
            make: Any = _BINARY[tok]
            if tok in _BINARY_WITHIN:
                b = bounds(at)
                if b is not None:
                    make = lambda f, g, lo=b[0], hi=b[1], cls=_BINARY_WITHIN[tok]: cls(lo, hi, f, g)  # noqa: E731
            # right-associative: reduce only operators that bind tighter
            while ops and ops[-1][0] == "bin" and ops[-1][1] > level:
                reduce_binary()
            ops.append(("bin", level, make))
            expect_operand = True
            continue
        if tok == ")":
            while ops and ops[-1][0] == "bin":
                reduce_binary()
            if not ops:
                raise LtlSyntaxError(text, at, f"unexpected {_show(tok)} after a complete formula")
            ops.pop()  # the "("
            i += 1
            reduce_unary_ops()
            continue
        opened = [o for o in ops if o[0] == "("]
        if tok != "<end>" or opened:
            if opened:
                raise LtlSyntaxError(text, at, f"expected ')', got {_show(tok)}")
            raise LtlSyntaxError(text, at, f"unexpected {_show(tok)} after a complete formula")
        while ops:
            reduce_binary()
        return operands[0]


# --------------------------------------------------------------------------- transformations


def subformulas(f: Formula) -> list[Formula]:
    """Every distinct subformula, children before parents (so bottom-up passes can run
    in list order); iterative."""
    out: list[Formula] = []
    seen: set[Formula] = set()
    stack: list[tuple[Formula, bool]] = [(f, False)]
    while stack:
        g, expanded = stack.pop()
        if g in seen:
            continue
        if expanded:
            seen.add(g)
            out.append(g)
            continue
        stack.append((g, True))
        for child in reversed(children(g)):
            if child not in seen:
                stack.append((child, False))
    return out


def props(f: Formula) -> frozenset[str]:
    """The label names a formula mentions.

    >>> sorted(props(parse("F a & (b U !a)")))
    ['a', 'b']
    """
    return frozenset(g.name for g in subformulas(f) if isinstance(g, Prop))


def _bottom_up(f: Formula, rebuild) -> Formula:
    """``rebuild(node, new_children)`` applied from the leaves up (iterative)."""
    done: dict[Formula, Formula] = {}
    for g in subformulas(f):
        done[g] = rebuild(g, [done[c] for c in children(g)])
    return done[f]


def nnf(f: Formula, negate: bool = False) -> Formula:
    """Negation normal form: only ``Not(Prop)``; no ``->``/``<->``; ``X``, its weak dual,
    ``F G U R``, their bounded forms, ``& |`` otherwise (``!X a = WeakNext(!a)`` (the
    same as ``X !a`` on infinite words), ``!(a U b) = !a R !b``, ``!F a = G !a``,
    ``!F[a,b] f = G[a,b] !f``). Iterative: one pass per polarity over the distinct
    subformulas.

    >>> str(nnf(parse("!(a U (b -> X c))")))
    '(!a R (b & !X c))'
    >>> str(nnf(parse("!F[0,5] a")))
    'G[0,5] !a'
    """
    memo: dict[tuple[Formula, bool], Formula] = {}
    stack: list[tuple[Formula, bool, bool]] = [(f, negate, False)]
    while stack:
        g, neg, ready = stack.pop()
        if (g, neg) in memo:
            continue
        parts = _nnf_parts(g, neg)
        if not ready:
            todo = [(c, n) for c, n in parts[1] if (c, n) not in memo]
            if todo:
                stack.append((g, neg, True))
                stack.extend((c, n, False) for c, n in todo)
                continue
        memo[(g, neg)] = parts[0]([memo[(c, n)] for c, n in parts[1]])
    return memo[(f, negate)]


def _nnf_parts(g: Formula, neg: bool):
    """(build from the children's NNFs, [(child, its polarity)]) for one node."""
    if isinstance(g, Const):
        return (lambda _: Const(g.value != neg)), []
    if isinstance(g, Prop):
        return (lambda _: Not(g) if neg else g), []
    if isinstance(g, Not):
        return (lambda c: c[0]), [(g.arg, not neg)]
    if isinstance(g, (And, Or)):
        op = {(And, False): And, (And, True): Or, (Or, False): Or, (Or, True): And}[(type(g), neg)]
        return (lambda c: op(c[0], c[1])), [(g.left, neg), (g.right, neg)]
    if isinstance(g, Implies):  # !a | b
        op = And if neg else Or
        return (lambda c: op(c[0], c[1])), [(g.left, not neg), (g.right, neg)]
    if isinstance(g, Iff):  # (a & b) | (!a & !b); negated: (a & !b) | (!a & b)
        if neg:
            return (lambda c: Or(And(c[0], c[3]), And(c[1], c[2]))), [
                (g.left, False),
                (g.left, True),
                (g.right, False),
                (g.right, True),
            ]
        return (lambda c: Or(And(c[0], c[2]), And(c[1], c[3]))), [
            (g.left, False),
            (g.left, True),
            (g.right, False),
            (g.right, True),
        ]
    if isinstance(g, Next):
        return (lambda c: (WeakNext if neg else Next)(c[0])), [(g.arg, neg)]
    if isinstance(g, WeakNext):
        return (lambda c: (Next if neg else WeakNext)(c[0])), [(g.arg, neg)]
    if isinstance(g, (Finally, Globally)):
        dual = {Finally: Globally, Globally: Finally}[type(g)] if neg else type(g)
        return (lambda c: dual(c[0])), [(g.arg, neg)]
    if isinstance(g, (Until, Release)):
        dual = {Until: Release, Release: Until}[type(g)] if neg else type(g)
        return (lambda c: dual(c[0], c[1])), [(g.left, neg), (g.right, neg)]
    if isinstance(g, (FinallyWithin, GloballyWithin)):
        dual = {FinallyWithin: GloballyWithin, GloballyWithin: FinallyWithin}[type(g)] if neg else type(g)
        return (lambda c: dual(g.lo, g.hi, c[0])), [(g.arg, neg)]
    if isinstance(g, (UntilWithin, ReleaseWithin)):
        dual = {UntilWithin: ReleaseWithin, ReleaseWithin: UntilWithin}[type(g)] if neg else type(g)
        return (lambda c: dual(g.lo, g.hi, c[0], c[1])), [(g.left, neg), (g.right, neg)]
    raise TypeError(f"not a formula: {type(g).__name__}")


def unroll(f: Formula) -> Formula:
    """The bounded operators written with ``X`` (strong) and :class:`WeakNext`, the
    textbook unrolling that the BMC and the MILP encode and that the semantics' property
    tests compare the bounded operators with::

        F[a,b] f  = X^a (f | X (f | ... X f))          (b - a + 1 copies of f)
        G[a,b] f  = Xw^a (f & Xw (f & ... Xw f))
        f U[0,0] g = g;  f U[0,b] g = g | (f & X (f U[0,b-1] g));  f U[a,b] g = f & X (f U[a-1,b-1] g)
        f R[0,0] g = g;  f R[0,b] g = g & (f | Xw (f R[0,b-1] g)); f R[a,b] g = f | Xw (f R[a-1,b-1] g)

    (``Xw``: :class:`WeakNext`; on infinite words both nexts are ``X``.) The copies share
    their subformula, so the result has about 2 (b + 1) new nodes per bounded operator.

    >>> str(unroll(parse("F[1,2] a")))
    'X (a | X a)'
    >>> str(unroll(parse("a U[1,1] b")))
    '(a & X b)'
    """

    def rebuild(g: Formula, kids: list[Formula]) -> Formula:
        if isinstance(g, FinallyWithin):
            body = kids[0]
            for _ in range(g.hi - g.lo):
                body = Or(kids[0], Next(body))
            for _ in range(g.lo):
                body = Next(body)
            return body
        if isinstance(g, GloballyWithin):
            body = kids[0]
            for _ in range(g.hi - g.lo):
                body = And(kids[0], WeakNext(body))
            for _ in range(g.lo):
                body = WeakNext(body)
            return body
        if isinstance(g, UntilWithin):
            a, b = kids
            body = b
            for _ in range(g.hi - g.lo):
                body = Or(b, And(a, Next(body)))
            for _ in range(g.lo):
                body = And(a, Next(body))
            return body
        if isinstance(g, ReleaseWithin):
            a, b = kids
            body = b
            for _ in range(g.hi - g.lo):
                body = And(b, Or(a, WeakNext(body)))
            for _ in range(g.lo):
                body = Or(a, WeakNext(body))
            return body
        if not kids:
            return g
        if isinstance(g, (*_ONE_CHILD,)):
            return type(g)(kids[0])
        return type(g)(kids[0], kids[1])

    return _bottom_up(f, rebuild)


def unrolled_size(f: Formula) -> int:
    """An upper bound on the number of distinct subformulas of :func:`unroll` of ``f``,
    computed without unrolling (the door's check against :data:`MAX_FORMULA_SIZE`)."""
    total = 0
    for g in subformulas(f):
        if isinstance(g, (FinallyWithin, GloballyWithin)):
            total += 2 * (g.hi - g.lo) + g.lo + 1
        elif isinstance(g, (UntilWithin, ReleaseWithin)):
            total += 3 * (g.hi - g.lo) + 2 * g.lo + 1
        else:
            total += 1
    return total

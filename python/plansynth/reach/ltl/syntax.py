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
import re
from typing import Any

from plansynth.reach.ltl.formulas import (
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
    children,
)
from plansynth.reach.ltl.transform import nnf, props, subformulas, unroll, unrolled_size

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

_UNARY = {"!": Not, "X": Next, "F": Finally, "G": Globally}
_UNARY_WITHIN = {"F": FinallyWithin, "G": GloballyWithin}
_BINARY_WITHIN = {"U": UntilWithin, "R": ReleaseWithin}


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

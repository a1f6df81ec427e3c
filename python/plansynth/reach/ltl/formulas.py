"""The formulas of the mission language (:mod:`plansynth.reach.ltl.syntax` gives the
syntax, the parser and the limits; Shoukry et al., CDC 2016, Sections I and IV): one
value class per operator, how they print, and their direct subformulas.

**Formulas are shared values.** Equal formulas are the same object (each node is
interned when it is made), so equality is identity and hashing is constant time, however
deep the formula: a dictionary keyed by subformulas never walks a tree.
"""

from __future__ import annotations

import itertools
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
    "children",
]

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

"""The terms of the controller grammar (Listing 1 of Chasins & Newcomb, SYNT 2016; the
grammar, parser and evaluation are :mod:`plansynth.grid.programs`): constants, inputs
and applications, and their measures: the paper's depth (a coordinate, written
``(get-x p)`` in the paper, has depth 2), size, subterms and the inputs read.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

# -- AST -------------------------------------------------------------------------------


@dataclass(frozen=True)
class Const:
    """An integer literal: a move number in Start position, a constant in T position."""

    value: int

    def __str__(self) -> str:
        return f"(- {-self.value})" if self.value < 0 else str(self.value)


@dataclass(frozen=True)
class Var:
    """A coordinate input: ``rx``, ``ry``, ``o0x``, ``o0y``, ..."""

    name: str

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class App:
    """An operator application: ``ite``, ``and``, ``or``, ``not``, ``<=``, ``=``, ``+``, ``-``."""

    op: str
    args: tuple[Term, ...]

    def __str__(self) -> str:
        return f"({self.op} {' '.join(str(a) for a in self.args)})"


Term = Const | Var | App

#: Operator -> (argument sorts, result sort); sorts are "S" (Start), "B", "T".
SIGNATURES: dict[str, tuple[tuple[str, ...], str]] = {
    "ite": (("B", "S", "S"), "S"),
    "and": (("B", "B"), "B"),
    "or": (("B", "B"), "B"),
    "not": (("B",), "B"),
    "<=": (("T", "T"), "B"),
    "=": (("T", "T"), "B"),
    "+": (("T", "T"), "T"),
    "-": (("T", "T"), "T"),
}


def ite(c: Term, t: Term, e: Term) -> App:
    return App("ite", (c, t, e))


# -- measures --------------------------------------------------------------------------


def depth(t: Term) -> int:
    """The paper's depth: literal 1, coordinate 2, application 1 + deepest argument."""
    if isinstance(t, Const):
        return 1
    if isinstance(t, Var):
        return 2
    return 1 + max(depth(a) for a in t.args)


def size(t: Term) -> int:
    """Number of AST nodes."""
    if isinstance(t, App):
        return 1 + sum(size(a) for a in t.args)
    return 1


def subterms(t: Term) -> Iterator[Term]:
    yield t
    if isinstance(t, App):
        for a in t.args:
            yield from subterms(a)


def variables_of(t: Term) -> frozenset[str]:
    return frozenset(s.name for s in subterms(t) if isinstance(s, Var))


def reads_obstacles(t: Term) -> bool:
    """True when the program looks at some obstacle coordinate."""
    return any(v.startswith("o") for v in variables_of(t))

"""The compiled core (``plansynth._core``), behind the same signatures as the pure-Python
references it replaces (STYLE.md, point 6). Property tests compare the two.

>>> available()
True
>>> e = enumerate_conditions([(0, 0), (1, 0), (2, 0)], ("rx", "ry"), 2, 3, None)
>>> [str(c.term) for c in e.conditions if c.mask == 0b001]
['(= 0 rx)']
"""

from __future__ import annotations

from collections.abc import Sequence

from plansynth.grid.native.conditions import Condition, Enumeration
from plansynth.grid.programs import App, Const, Term, Var

try:
    from plansynth import _core
except ImportError:  # pragma: no cover - the package is always built with its core
    _core = None

_CMP = {0: "<=", 1: "="}
_BOOL = {3: "and", 4: "or"}


def available() -> bool:
    return _core is not None and hasattr(_core, "enumerate_conditions")


def core_version() -> str:
    return _core.core_version() if _core is not None else "none"


def enumerate_conditions(
    states: Sequence[Sequence[int]], variables: Sequence[str], max_constant: int, max_depth: int, limit: int | None
) -> Enumeration:
    """:func:`plansynth.grid.native.conditions._enumerate`, compiled."""
    rows = [list(s) for s in states]
    terms_raw, conds_raw, complete_to = _core.enumerate_conditions(rows, len(variables), max_constant, max_depth, limit)
    terms: list[Term] = []
    for kind, a, b, _ in terms_raw:
        if kind == 0:
            terms.append(Const(a))
        elif kind == 1:
            terms.append(Var(variables[a]))
        else:
            terms.append(App("+" if kind == 2 else "-", (terms[a], terms[b])))
    conds: list[Condition] = []
    for mask, op, a, b, d in conds_raw:
        if op in _CMP:
            term: Term = App(_CMP[op], (terms[a], terms[b]))
        elif op == 2:
            term = App("not", (conds[a].term,))
        else:
            term = App(_BOOL[op], (conds[a].term, conds[b].term))
        conds.append(Condition(int.from_bytes(mask, "little"), term, d))
    return Enumeration(tuple(conds), complete_to)


def greedy_tree(
    conds: Sequence[Condition], allowed: Sequence[Sequence[int]], n_moves: int, max_nodes: int
) -> list[tuple[int, int]] | None:
    """The pre-order nodes of :func:`plansynth.grid.native.synth.greedy_program`'s tree,
    compiled: ``(0, k)`` a leaf playing move k, ``(1, j)`` a split on ``conds[j]``; None
    when more than ``max_nodes`` splits are needed."""
    nbytes = max(1, (len(allowed) + 7) // 8)
    masks = [c.mask.to_bytes(nbytes, "little") if c.mask >= 0 else b"" for c in conds]
    keys = [(c.depth, n) for c, n in zip(conds, term_sizes([c.term for c in conds]))]
    bitmasks = [sum(1 << k for k in set(a)) for a in allowed]
    return _core.greedy_tree(masks, keys, bitmasks, n_moves, max_nodes)


def term_sizes(terms: Sequence[Term]) -> list[int]:
    """:func:`plansynth.grid.programs.size` of each term, sharing the work over common
    subterm objects (enumerated conditions are built from shared subterms)."""
    memo: dict[int, int] = {}

    def size_of(t: Term) -> int:
        got = memo.get(id(t))
        if got is None:
            got = 1 + sum(size_of(a) for a in t.args) if isinstance(t, App) else 1
            memo[id(t)] = got
        return got

    return [size_of(t) for t in terms]

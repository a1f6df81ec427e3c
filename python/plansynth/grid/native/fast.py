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


def greedy_from_enumeration(
    states: Sequence[Sequence[int]],
    variables: Sequence[str],
    max_constant: int,
    max_depth: int,
    limit: int | None,
    allowed: Sequence[Sequence[int]],
    n_moves: int,
    max_nodes: int,
) -> Term | None:
    """:func:`~plansynth.grid.native.synth.greedy_program` over every condition up to
    ``max_depth``, without building a term for each condition: the behaviours stay raw
    between the enumeration and the tree, and only the conditions the tree splits on
    become terms (an enumeration to depth 4 has tens of thousands of conditions; their
    terms would cost more than the tree). None when the tree needs more than
    ``max_nodes`` splits."""
    rows = [list(s) for s in states]
    terms_raw, conds_raw, _ = _core.enumerate_conditions(rows, len(variables), max_constant, max_depth, limit)
    tsize: list[int] = []
    for kind, a, b, _ in terms_raw:
        tsize.append(1 if kind in (0, 1) else 1 + tsize[a] + tsize[b])
    csize: list[int] = []
    for _, op, a, b, _ in conds_raw:
        csize.append(1 + (tsize[a] + tsize[b] if op in _CMP else csize[a] if op == 2 else csize[a] + csize[b]))
    nbytes = max(1, (len(allowed) + 7) // 8)
    masks = [m.ljust(nbytes, b"\0")[:nbytes] if len(m) != nbytes else m for m, *_ in conds_raw]
    keys = [(d, sz) for (_, _, _, _, d), sz in zip(conds_raw, csize)]
    bitmasks = [sum(1 << k for k in set(a)) for a in allowed]
    nodes = _core.greedy_tree(masks, keys, bitmasks, n_moves, max_nodes)
    if nodes is None:
        return None
    term_memo: dict[int, Term] = {}

    def term(i: int) -> Term:
        t = term_memo.get(i)
        if t is None:
            kind, a, b, _ = terms_raw[i]
            t = (
                Const(a)
                if kind == 0
                else Var(variables[a])
                if kind == 1
                else App("+" if kind == 2 else "-", (term(a), term(b)))
            )
            term_memo[i] = t
        return t

    cond_memo: dict[int, Term] = {}

    def cond(i: int) -> Term:
        t = cond_memo.get(i)
        if t is None:
            _, op, a, b, _ = conds_raw[i]
            if op in _CMP:
                t = App(_CMP[op], (term(a), term(b)))
            elif op == 2:
                t = App("not", (cond(a),))
            else:
                t = App(_BOOL[op], (cond(a), cond(b)))
            cond_memo[i] = t
        return t

    it = iter(nodes)

    def build() -> Term:
        kind, x = next(it)
        if kind == 0:
            return Const(x)
        then, other = build(), build()
        return then if then == other else App("ite", (cond(x), then, other))

    return build()

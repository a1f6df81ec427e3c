"""The touches of a label's boundary, read one way per step: whether some consistent
reading of the "may hold" word satisfies the mission, by a SAT encoding of the semantics
(CaDiCaL), for the independent mission checker (:mod:`plansynth.reach.mission.check`,
whose docstring says when it is asked).
"""

from __future__ import annotations

from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    FiniteWord,
    Formula,
    Globally,
    Lasso,
    Next,
    Or,
    Prop,
    Release,
    Until,
    WeakNext,
    holds,
    subformulas,
    unroll,
)
from plansynth.reach.mission.word import NEG

__all__ = ["consistent_reading"]


def consistent_reading(f: Formula, word: Lasso | FiniteWord) -> Lasso | FiniteWord | None:
    """A consistent reading of the "may hold" word that satisfies ``f`` (NNF, with
    ``!a`` as the proposition "!a", as :func:`~plansynth.reach.mission.word.literal_form` writes it), or None when
    there is none. A reading keeps, at each position, exactly one of ``a`` and ``!a``
    for every label the letter has both of (and the letter's other literals); the
    result's letters are those readings, so :func:`holds` can confirm it.

    No ambiguous letter: the word itself (when f holds on it). Otherwise the two uniform
    readings (every touch in, every touch out), then SAT over one variable per
    ambiguous (position, label), on the formula with its bounded operators unrolled:
    each subformula gets one literal per position, defined by exact (two-sided) Tseitin
    gates; ``a U b`` on a loop position i is ``OR_j (b_{i+j} & a_i & ... & a_{i+j-1})``
    over one turn of the loop (a witness that exists lies within one turn), on a prefix
    position ``b_i | (a_i & (a U b)_{i+1})``, past the end of a finite word false;
    ``a R b`` is ``!(!a U !b)``, ``F`` and ``G`` are ``U`` and ``R`` with a constant; ``X``
    is false past the end of a finite word, its weak dual true.

    >>> from plansynth.reach.mission.ltl import nnf, parse
    >>> from plansynth.reach.mission.word import literal_form
    >>> w = Lasso((), (frozenset({"a", "!a"}),))   # the robot rests on a's boundary
    >>> consistent_reading(literal_form(nnf(parse("F a & G !a"))), w) is None
    True
    >>> consistent_reading(literal_form(nnf(parse("F a"))), w).loop
    (frozenset({'a'}),)
    """
    letters = word.letters
    ambiguous = sorted(
        {(i, n[len(NEG) :]) for i, a in enumerate(letters) for n in a if n.startswith(NEG) and n[len(NEG) :] in a}
    )
    if not ambiguous:
        return word if holds(f, word) else None
    finite = isinstance(word, FiniteWord)

    def reading(value) -> Lasso | FiniteWord:
        out = [set(a) for a in letters]
        for i, n in ambiguous:
            out[i].discard(NEG + n if value(i, n) else n)
        if finite:
            return FiniteWord(tuple(out))
        k = len(word.prefix)
        return Lasso(tuple(out[:k]), tuple(out[k:]))

    for uniform in (True, False):
        w = reading(lambda i, n, u=uniform: u)
        if holds(f, w):
            return w
    from pysat.solvers import Solver

    n_pos = len(letters)
    k = n_pos if finite else len(word.prefix)
    m = n_pos - k
    TRUE = 1
    clauses: list[list[int]] = [[TRUE]]
    top = [TRUE]

    def new() -> int:
        top[0] += 1
        return top[0]

    var = {key: new() for key in ambiguous}

    def gate(xs: list[int], conj: bool) -> int:
        xs = [x for x in xs if x != (TRUE if conj else -TRUE)]
        if (-TRUE if conj else TRUE) in xs:
            return -TRUE if conj else TRUE
        if not xs:
            return TRUE if conj else -TRUE
        if len(xs) == 1:
            return xs[0]
        v = new()
        s = 1 if conj else -1  # conj: v -> x for all x, (all x) -> v; disj: the dual
        clauses.extend([-s * v, s * x] for x in xs)
        clauses.append([s * v] + [-s * x for x in xs])
        return v

    def until(a: list[int], b: list[int]) -> list[int]:
        out = [0] * n_pos
        for i in range(k, n_pos):
            terms, chain = [], TRUE
            for j in range(m):
                p = k + (i - k + j) % m
                terms.append(gate([chain, b[p]], True))
                chain = gate([chain, a[p]], True)
            out[i] = gate(terms, False)
        for i in range(k - 1, -1, -1):
            later = out[i + 1] if i + 1 < n_pos else -TRUE  # past a finite word's end: no witness
            out[i] = gate([b[i], gate([a[i], later], True)], False)
        return out

    enc: dict[Formula, list[int]] = {}
    for g in subformulas(unroll(f)):
        if isinstance(g, Const):
            v = [TRUE if g.value else -TRUE] * n_pos
        elif isinstance(g, Prop):
            neg = g.name.startswith(NEG)
            name = g.name[len(NEG) :] if neg else g.name
            v = []
            for i, a in enumerate(letters):
                lit = var[(i, name)] if (i, name) in var else (TRUE if g.name in a else -TRUE)
                v.append(-lit if neg and (i, name) in var else lit)
        elif isinstance(g, (And, Or)):
            v = [gate([x, y], isinstance(g, And)) for x, y in zip(enc[g.left], enc[g.right])]
        elif isinstance(g, (Next, WeakNext)):
            a = enc[g.arg]
            past = -TRUE if isinstance(g, Next) else TRUE
            v = [past if word.successor(i) is None else a[word.successor(i)] for i in range(n_pos)]
        elif isinstance(g, (Finally, Until)):
            a = [TRUE] * n_pos if isinstance(g, Finally) else enc[g.left]
            v = until(a, enc[g.arg if isinstance(g, Finally) else g.right])
        elif isinstance(g, (Globally, Release)):
            a = [-TRUE] * n_pos if isinstance(g, Globally) else enc[g.left]
            b = enc[g.arg if isinstance(g, Globally) else g.right]
            v = [-x for x in until([-x for x in a], [-x for x in b])]
        else:
            raise TypeError(f"not in negation normal form: {type(g).__name__}")
        enc[g] = v
    clauses.append([enc[unroll(f)][0]])
    with Solver(name="cadical195", bootstrap_with=clauses) as solver:
        if not solver.solve():
            return None
        model = set(solver.get_model())
    return reading(lambda i, n: var[(i, n)] in model)

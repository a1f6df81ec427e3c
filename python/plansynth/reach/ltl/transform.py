"""What is computed of a formula of the mission language
(:mod:`plansynth.reach.ltl.syntax`): its distinct subformulas, its label names, its
negation normal form, its unrolling of the bounded operators and the size of that
unrolling (the limit the door checks). Every function is iterative, so a legal formula
may nest as deep as its length allows.
"""

from __future__ import annotations

from plansynth.reach.ltl.formulas import (
    _ONE_CHILD,
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

__all__ = ["nnf", "props", "subformulas", "unroll", "unrolled_size"]


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

    >>> from plansynth.reach.ltl.syntax import parse
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

    >>> from plansynth.reach.ltl.syntax import parse
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

    >>> from plansynth.reach.ltl.syntax import parse
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
    computed without unrolling (the door's check against :data:`~plansynth.reach.ltl.syntax.MAX_FORMULA_SIZE`)."""
    total = 0
    for g in subformulas(f):
        if isinstance(g, (FinallyWithin, GloballyWithin)):
            total += 2 * (g.hi - g.lo) + g.lo + 1
        elif isinstance(g, (UntilWithin, ReleaseWithin)):
            total += 3 * (g.hi - g.lo) + 2 * g.lo + 1
        else:
            total += 1
    return total

"""Bottom-up enumeration of the grammar's conditions, up to observational equivalence.

This is the idea of the Enumerative SyGuS solver (Alur et al., used by Chasins &
Newcomb, SYNT 2016, Section 4): build terms by increasing depth and keep one term per
*behaviour* on the states that matter. Two conditions that agree on every state a
controller can meet are interchangeable, so keeping the first (shallowest, then
smallest) one per behaviour loses nothing: the enumeration up to a depth is complete
for those states.

A condition's behaviour is an ``int`` bitset over the list of states (bit i: true in
state i). Depths are the paper's (spec, Controller programs): a constant 1, a
coordinate 2, an application 1 + its deepest argument.

>>> conds = enumerate_conditions([(0, 0), (1, 0), (2, 0)], ("rx", "ry"), 2, 3)
>>> [(str(c.term), bin(c.mask), c.depth) for c in conds if c.mask == 0b001]
[('(= 0 rx)', '0b1', 3)]
>>> len({c.mask for c in conds}) == len(conds)
True
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.programs import App, Const, Term, Var, depth, size


@dataclass(frozen=True)
class Condition:
    """One condition per behaviour: its bitset over the states, a term, its depth."""

    mask: int
    term: Term
    depth: int


@dataclass(frozen=True)
class Enumeration:
    """Conditions found, and whether each depth level was enumerated completely."""

    conditions: tuple[Condition, ...]
    complete_to: int  # every behaviour of a condition of depth <= this is present


def _values(
    term_vals: dict[tuple[int, ...], Term], new: dict[tuple[int, ...], Term], vec: tuple[int, ...], t: Term
) -> None:
    if vec not in term_vals and vec not in new:
        new[vec] = t


def arithmetic_terms(
    states: Sequence[Sequence[int]], variables: Sequence[str], max_constant: int, max_depth: int
) -> list[tuple[int, tuple[int, ...], Term]]:
    """Integer terms up to ``max_depth``, one per value vector: (depth, values, term)."""
    seen: dict[tuple[int, ...], Term] = {}
    out: list[tuple[int, tuple[int, ...], Term]] = []
    n = len(states)
    for c in range(-1, max_constant + 1):
        vec = (c,) * n
        if vec not in seen:
            seen[vec] = Const(c)
            out.append((1, vec, Const(c)))
    if max_depth >= 2:
        for j, v in enumerate(variables):
            vec = tuple(s[j] for s in states)
            if vec not in seen:
                seen[vec] = Var(v)
                out.append((2, vec, Var(v)))
    for d in range(3, max_depth + 1):
        prev = list(out)
        level: list[tuple[int, tuple[int, ...], Term]] = []
        for ia, (da, va, ta) in enumerate(prev):
            for ib, (db, vb, tb) in enumerate(prev):
                if max(da, db) != d - 1:
                    continue
                if ia <= ib:
                    vec = tuple(x + y for x, y in zip(va, vb))
                    if vec not in seen:
                        seen[vec] = App("+", (ta, tb))
                        level.append((d, vec, seen[vec]))
                vec = tuple(x - y for x, y in zip(va, vb))
                if vec not in seen:
                    seen[vec] = App("-", (ta, tb))
                    level.append((d, vec, seen[vec]))
        out.extend(level)
    return out


def enumerate_conditions(
    states: Sequence[Sequence[int]],
    variables: Sequence[str],
    max_constant: int,
    max_depth: int,
    *,
    limit: int | None = None,
) -> list[Condition]:
    """Every condition behaviour of depth <= ``max_depth`` on ``states`` (pure Python).

    The reference implementation: :func:`plansynth.grid.native.fast.enumerate_conditions`
    must return the same behaviours with terms of the same depth. ``limit`` caps the
    number kept (the result is then incomplete at the last depth reached; see
    :func:`plansynth.grid.native.run.conditions_upto`).
    """
    return list(_enumerate(states, variables, max_constant, max_depth, limit).conditions)


def _enumerate(states, variables, max_constant, max_depth, limit) -> Enumeration:
    n = len(states)
    full = (1 << n) - 1
    terms = arithmetic_terms(states, variables, max_constant, max(1, max_depth - 1))
    found: dict[int, Condition] = {}
    order: list[Condition] = []
    complete_to = 1

    def add(mask: int, t: Term, d: int) -> bool:
        if mask in found:
            return True
        c = Condition(mask, t, d)
        found[mask] = c
        order.append(c)
        return limit is None or len(order) < limit

    for d in range(2, max_depth + 1):
        before = list(order)
        ok = True
        # atoms (<= a b), (= a b) whose deeper argument has depth d - 1
        for ia, (da, va, ta) in enumerate(terms):
            if not ok:
                break
            if da > d - 1:
                continue
            for ib, (db, vb, tb) in enumerate(terms):
                if db > d - 1 or max(da, db) != d - 1:
                    continue
                le = 0
                eq = 0
                for i in range(n):
                    if va[i] <= vb[i]:
                        le |= 1 << i
                        if va[i] == vb[i]:
                            eq |= 1 << i
                if not add(le, App("<=", (ta, tb)), d):
                    ok = False
                    break
                if ia < ib and not add(eq, App("=", (ta, tb)), d):
                    ok = False
                    break
        # boolean combinations whose deeper argument has depth d - 1
        if ok:
            for ia, ca in enumerate(before):
                if ca.depth != d - 1:
                    continue
                if not add(full & ~ca.mask, App("not", (ca.term,)), d):
                    ok = False
                    break
                for ib, cb in enumerate(before):
                    if cb.depth == d - 1 and ib < ia:
                        continue  # the pair was met the other way round
                    if not add(ca.mask & cb.mask, App("and", (ca.term, cb.term)), d) or not add(
                        ca.mask | cb.mask, App("or", (ca.term, cb.term)), d
                    ):
                        ok = False
                        break
                if not ok:
                    break
        if not ok:
            break
        complete_to = d
    return Enumeration(tuple(order), complete_to)


#: Behaviour cells (condition x program state) the compiled condition enumeration
#: computes per second, conservatively (2.6e8 measured on a loaded 2-core machine): the
#: enumeration is refused when its estimate does not fit the time left.
CONDITION_CELLS_PER_SECOND = 1e8


def condition_limit(n_states: int) -> int:
    """Conditions kept when enumerating over ``n_states`` states: their behaviours cost
    ``n_states`` bits each, which bounds their memory and time."""
    return min(200_000, max(5_000, 40_000_000 // max(1, n_states)))


def check_enumeration_fits(n_states: int, n_vars: int, max_constant: int, clock: Clock, memory_mb: int) -> None:
    """The condition enumeration cannot be interrupted: refuse it
    (:class:`~plansynth.budget.BudgetExhausted`) when its estimated work (comparisons of
    the depth-2 terms over every state) does not fit the time left on ``clock``, or its
    behaviours ``memory_mb``."""
    limit = condition_limit(n_states)
    terms = max_constant + 2 + n_vars
    work = min(limit, 2 * terms * terms) * n_states
    need = work / CONDITION_CELLS_PER_SECOND
    nbytes = min(limit, 2 * terms * terms) * (n_states // 8 + 64) + terms * n_states * 8
    if need > clock.remaining():
        raise BudgetExhausted(
            "enumerating conditions",
            "time",
            f"enumerating conditions over {n_states} program states would take about "
            f"{need:.0f} s ({max(0.0, clock.remaining()):.1f} s left)",
        )
    if nbytes > (memory_mb << 20):
        raise BudgetExhausted(
            "enumerating conditions",
            "memory",
            f"enumerating conditions over {n_states} program states needs about "
            f"{nbytes >> 20} MB (memory budget {memory_mb} MB)",
        )


def smallest(term: Term) -> tuple[int, int]:
    return depth(term), size(term)

"""From a winning strategy to the smallest program of the grammar.

A program of the grammar (Chasins & Newcomb, SYNT 2016, Listing 1) is a decision tree:
``(ite B S S)`` nodes over conditions B and move numbers at the leaves. Its depth is
the paper's: a tree node whose condition has depth c and whose subtrees have depth
at most e has depth ``1 + max(c, e)``; a move has depth 1. So a program of depth at
most D is a complete binary tree of ``D - 3`` levels of conditions (depth 4 needs a
comparison of coordinates or constants, which has depth 3), where a condition at level
i has depth at most ``D - 1 - i``. Depths 2 and 3 add nothing over depth 1: an ``ite``
of depth 3 can only test constants.

:func:`tree_program` decides, with SAT, whether such a tree maps every state to one of
its allowed moves. The conditions come from :mod:`conditions` (one per behaviour on the
states), so the answer is exact for conditions up to the depth they were enumerated
completely. :func:`greedy_program` is the fallback when the SAT instance would be too
large: a top-down tree that always exists (any two distinct states are told apart by an
``=`` test of one coordinate).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.conditions import Condition
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.sat import SAT_SOLVER, ConflictLimit, solve_sliced
from plansynth.grid.programs import App, Const, Term, depth, size


#: Valid program depths in increasing order (2 and 3 cannot beat 1).
def program_depths(max_depth: int) -> list[int]:
    return [1] + list(range(4, max_depth + 1))


def tree_levels(d: int) -> int:
    """Levels of conditions in a tree program of depth ``d``."""
    return max(0, d - 3)


@dataclass
class TreeEncoding:
    """The SAT variables of a decision tree over conditions, linked to per-state moves.

    Nodes are numbered heap-style: node n has children 2n+1, 2n+2; internal nodes are
    ``0 .. 2**levels - 2``, leaves follow. ``out(s, k)`` literals say "the tree answers k
    in state s"; callers constrain them (allowed moves, or winning-strategy clauses).
    """

    levels: int
    conds_at: list[list[Condition]]
    n_states: int
    n_moves: int
    next_var: int
    clauses: list[list[int]]

    def __post_init__(self) -> None:
        self.sel: dict[tuple[int, int], int] = {}
        self.at: dict[tuple[int, int], int] = {}
        self.leaf: dict[tuple[int, int], int] = {}

    def new(self) -> int:
        self.next_var += 1
        return self.next_var

    @property
    def n_internal(self) -> int:
        return 2**self.levels - 1

    def build(self, out_lit, clock: Clock | None = None) -> None:
        """Emit the tree's clauses; ``out_lit(s, k)`` gives the literal 'state s plays k'.
        With ``clock``, the build (pure Python, seconds on thousands of states and
        conditions) raises :class:`~plansynth.budget.BudgetExhausted` when the budget runs out."""
        self.structure()
        for s in range(self.n_states):
            self.add_state(s, out_lit)
            check_clock(clock, "building the tree SAT instance")

    def structure(self) -> None:
        """Every node picks exactly one condition, every leaf a move."""
        internal = self.n_internal
        for n in range(internal):
            sels = [self._sel(n, j) for j in range(len(self.conds_at[_level(n)]))]
            self.clauses.append(sels)
            # at most one (sequential counter): a state's branch is then read off the
            # chosen condition with two clauses per node instead of one per condition
            prev = None
            for x in sels:
                cur = self.new()
                self.clauses.append([-x, cur])
                if prev is not None:
                    self.clauses.append([-prev, cur])
                    self.clauses.append([-prev, -x])
                prev = cur
        for n in range(internal, 2 * internal + 1):
            self.clauses.append([self._leaf(n, k) for k in range(self.n_moves)])

    def add_state(self, s: int, out_lit) -> None:
        """Route state ``s`` through the tree and constrain the move at its leaf."""
        internal = self.n_internal
        self.clauses.append([self._at(0, s)])
        for n in range(internal):
            conds = self.conds_at[_level(n)]
            a = self._at(n, s)
            val = self.new()  # the chosen condition holds in state s
            self.clauses.append([-val] + [self._sel(n, j) for j, c in enumerate(conds) if c.mask >> s & 1])
            self.clauses.append([val] + [self._sel(n, j) for j, c in enumerate(conds) if not c.mask >> s & 1])
            self.clauses.append([-a, -val, self._at(2 * n + 1, s)])
            self.clauses.append([-a, val, self._at(2 * n + 2, s)])
        for n in range(internal, 2 * internal + 1):
            a = self._at(n, s)
            for k in range(self.n_moves):
                lit = out_lit(s, k)
                if lit is True:
                    continue
                if lit is False:
                    self.clauses.append([-a, -self._leaf(n, k)])
                else:
                    self.clauses.append([-a, -self._leaf(n, k), lit])

    def leaves_of(self, model) -> list[tuple[int, int]]:
        """For a model: (mask of states reaching the leaf, its move), per leaf."""
        truth = set(v for v in model if v > 0)
        full = (1 << self.n_states) - 1
        out = []

        def walk(n: int, mask: int) -> None:
            if n >= self.n_internal:
                k = next(k for k in range(self.n_moves) if self._leaf(n, k) in truth)
                out.append((mask, k))
                return
            conds = self.conds_at[_level(n)]
            c = next(c for j, c in enumerate(conds) if self._sel(n, j) in truth)
            walk(2 * n + 1, mask & c.mask)
            walk(2 * n + 2, mask & ~c.mask & full)

        walk(0, full)
        return out

    def _sel(self, n: int, j: int) -> int:
        key = (n, j)
        v = self.sel.get(key)
        if v is None:
            v = self.sel[key] = self.new()
        return v

    def _at(self, n: int, s: int) -> int:
        key = (n, s)
        v = self.at.get(key)
        if v is None:
            v = self.at[key] = self.new()
        return v

    def _leaf(self, n: int, k: int) -> int:
        key = (n, k)
        v = self.leaf.get(key)
        if v is None:
            v = self.leaf[key] = self.new()
        return v

    def program(self, model: Sequence[int]) -> Term:
        truth = set(v for v in model if v > 0)

        def node(n: int) -> Term:
            if n >= self.n_internal:
                for k in range(self.n_moves):
                    if self._leaf(n, k) in truth:
                        return Const(k)
                raise AssertionError("a leaf without a move")
            conds = self.conds_at[_level(n)]
            for j, c in enumerate(conds):
                if self._sel(n, j) in truth:
                    return simplify_ite(c, node(2 * n + 1), node(2 * n + 2), self.n_states)
            raise AssertionError("a node without a condition")

        return node(0)


def _level(n: int) -> int:
    return (n + 1).bit_length() - 1


def simplify_ite(c: Condition, then: Term, other: Term, n_states: int) -> Term:
    full = (1 << n_states) - 1
    if c.mask == full or then == other:
        return then
    if c.mask == 0:
        return other
    return App("ite", (c.term, then, other))


def conditions_by_level(conds: Sequence[Condition], d: int, n_states: int | None = None) -> list[list[Condition]]:
    """For a tree of depth d, the conditions allowed at each level (depth <= d - 1 - i).

    With ``n_states``, a condition whose complement is already listed at no greater
    depth is left out: ``(ite c a b)`` and ``(ite (not c) b a)`` are the same tree.
    """
    if n_states is not None:
        full = (1 << n_states) - 1
        kept: dict[int, Condition] = {}
        for c in sorted(conds, key=lambda c: c.depth):
            if c.mask not in kept and (full ^ c.mask) not in kept:
                kept[c.mask] = c
        conds = list(kept.values())
    return [[c for c in conds if c.depth <= d - 1 - i] for i in range(tree_levels(d))]


def tree_program(
    allowed: Sequence[Sequence[int]],
    conds: Sequence[Condition],
    d: int,
    n_moves: int,
    clock: Clock | None = None,
    max_clauses: int = 3_000_000,
    max_conflicts: int | None = None,
    max_seconds: float | None = None,
) -> Term | None:
    """A program of depth <= ``d`` choosing an allowed move in every state, or None.

    ``allowed[s]`` are the moves permitted in state s; ``conds`` the condition
    behaviours over the same states. Exact relative to ``conds``. Raises
    :class:`~plansynth.budget.BudgetExhausted` if the instance grows beyond ``max_clauses`` literals or
    the clock runs out.
    """
    n = len(allowed)
    if d < 4:
        common = set(range(n_moves))
        for a in allowed:
            common &= set(a)
        return Const(min(common)) if common else None
    by_level = conditions_by_level(conds, d, n)
    per_state = sum(len(by_level[_level(i)]) for i in range(2 ** tree_levels(d) - 1)) + 2 ** tree_levels(d) * n_moves
    sets = [set(a) for a in allowed]
    enc = TreeEncoding(tree_levels(d), by_level, n, n_moves, 0, [])
    out_lit = lambda s, k: k in sets[s]  # noqa: E731
    enc.structure()
    # Counterexample-guided: start from one state per distinct allowed set, add the
    # states the candidate tree gets wrong. UNSAT on a subset is UNSAT on all states.
    seen: dict[frozenset[int], int] = {}
    for i, a in enumerate(sets):
        seen.setdefault(frozenset(a), i)
    # size first, then build: a deep tree over many conditions is refused before any work
    if per_state * len(seen) > max_clauses:
        raise BudgetExhausted(
            "building the tree SAT instance", "clauses", f"tree SAT instance of about {per_state * len(seen)} literals"
        )
    t0 = time.perf_counter()
    for i in seen.values():
        enc.add_state(i, out_lit)
        check_clock(clock, "building the tree SAT instance")
        if max_seconds is not None and time.perf_counter() - t0 > max_seconds:
            raise ConflictLimit(
                "building the tree SAT instance", "time", f"tree SAT instance not built within {max_seconds:.2f} s"
            )
    added = set(seen.values())
    from pysat.solvers import Solver  # here: a program found without tree SAT never loads it

    with Solver(name=SAT_SOLVER) as solver:
        while True:
            for c in enc.clauses:
                solver.add_clause(c)
            enc.clauses.clear()
            left = None if max_seconds is None else max_seconds - (time.perf_counter() - t0)
            model = solve_sliced(solver, clock, max_conflicts, left)
            if model is None:
                return None
            wrong = [s for mask, k in enc.leaves_of(model) for s in _bits(mask) if k not in sets[s]]
            if not wrong:
                return enc.program(model)
            for s in wrong[:8]:
                if s not in added:
                    added.add(s)
                    enc.add_state(s, out_lit)
            if per_state * len(added) > max_clauses:
                raise BudgetExhausted(
                    "building the tree SAT instance", "clauses", f"tree SAT instance beyond {max_clauses} literals"
                )


def useful_conditions(
    allowed: Sequence[Sequence[int]], conds: Sequence[Condition], n_moves: int, keep: int
) -> list[Condition]:
    """The ``keep`` conditions that best split the states by a shared allowed move:
    score = states served by the best move on each side (the greedy tree's measure).
    Used to keep the tree SAT small when exactness is not asked for."""
    n = len(allowed)
    full = (1 << n) - 1
    by_move = [0] * n_moves
    for s, a in enumerate(allowed):
        for k in a:
            by_move[k] |= 1 << s
    scored = []
    for c in conds:
        inside, outside = c.mask & full, full & ~c.mask
        if not inside or not outside:
            continue
        score = max((inside & m).bit_count() for m in by_move) + max((outside & m).bit_count() for m in by_move)
        scored.append((-score, c.depth, size(c.term), len(scored), c))
    scored.sort()
    return [x[-1] for x in scored[:keep]]


def greedy_program(
    states_allowed: Sequence[Sequence[int]],
    conds: Sequence[Condition],
    n_moves: int,
    max_nodes: int = 10_000,
    use_rust: bool | None = None,
) -> Term:
    """A top-down decision tree (always exists; not minimal): pick, at each node, the
    condition after which most states can share a move on each side.

    The compiled core (``crates/plansynth-core/src/tree.rs``) when available, else
    :func:`greedy_program_reference`; both build the same tree."""
    if use_rust is not False:
        from plansynth.grid.native import fast

        if fast.available() and hasattr(fast._core, "greedy_tree"):
            nodes = fast.greedy_tree(conds, states_allowed, n_moves, max_nodes)
            if nodes is None:
                raise BudgetExhausted("the greedy tree", "nodes", "greedy tree too large")
            return _tree_from_nodes(nodes, conds, len(states_allowed))
    return greedy_program_reference(states_allowed, conds, n_moves, max_nodes)


def _tree_from_nodes(nodes: Sequence[tuple[int, int]], conds: Sequence[Condition], n: int) -> Term:
    it = iter(nodes)

    def build() -> Term:
        kind, x = next(it)
        if kind == 0:
            return Const(x)
        then = build()
        other = build()
        return simplify_ite(conds[x], then, other, n)

    return build()


def greedy_program_reference(
    states_allowed: Sequence[Sequence[int]], conds: Sequence[Condition], n_moves: int, max_nodes: int = 10_000
) -> Term:
    """:func:`greedy_program` in pure Python (the reference of the compiled tree).

    A node whose states share a move is a leaf; otherwise the states are labelled by
    greedy set cover over their allowed moves and split by the condition of best Gini
    purity over those labels (ties: shallower, then smaller, then earlier condition)."""
    n = len(states_allowed)
    by_move = [0] * n_moves
    for i, a in enumerate(states_allowed):
        for k in a:
            by_move[k] |= 1 << i
    budget = [max_nodes]
    sizes = [size(c.term) for c in conds]

    def best_common(members: int) -> tuple[int, int]:
        return max(((members & m).bit_count(), -k) for k, m in enumerate(by_move))

    def grow(members: int) -> Term:
        total = members.bit_count()
        c, negk = best_common(members)
        if c == total:
            return Const(-negk)
        budget[0] -= 1
        if budget[0] < 0:
            raise BudgetExhausted("the greedy tree", "nodes", "greedy tree too large")
        # label the members by greedy set cover over their allowed moves
        rest, labels = members, []
        while rest:
            c, negk = best_common(rest)
            if c == 0:
                break
            lab = rest & by_move[-negk]
            rest &= ~lab
            labels.append(lab)
        lab_count = [m.bit_count() for m in labels]
        best = None
        for cond, sz in zip(conds, sizes):
            left = members & cond.mask
            nl = left.bit_count()
            if not nl or nl == total:
                continue
            nr = total - nl
            sl = sr = 0
            for m, cnt in zip(labels, lab_count):
                x = (cond.mask & m).bit_count()
                sl += x * x
                sr += (cnt - x) * (cnt - x)
            num, den, tie = sl * nr + sr * nl, nl * nr, (-cond.depth, -sz)
            if best is None or num * best[1] > best[0] * den or (num * best[1] == best[0] * den and tie > best[2]):
                best = (num, den, tie, cond, left, members & ~cond.mask)
        if best is None:
            raise AssertionError("no condition separates states with disjoint allowed moves")
        cond, left, right = best[3], best[4], best[5]
        return simplify_ite(cond, grow(left), grow(right), n)

    return grow((1 << n) - 1)


def _bits(mask: int):
    while mask:
        low = mask & -mask
        yield low.bit_length() - 1
        mask ^= low


def program_depth(t: Term) -> int:
    return depth(t)

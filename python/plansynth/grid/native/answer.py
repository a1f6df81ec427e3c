"""From a stationary winning strategy to a program, answer first (Chasins & Newcomb,
SYNT 2016, Listing 1: an ``ite`` tree over conditions with moves at the leaves).

The greedy tree over the enumerated conditions is correct by construction; it is
checked on the game at once and simplified against the check, and is the answer. Then,
within a small effort, smaller depths are sought with tree SAT and, on small games, the
exact depth search (:mod:`exact_depth`), keeping the best program the check accepts.
"""

from __future__ import annotations

import time

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native import fast
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.check import ArenaCheck, GameGraph, program_checker, simplify
from plansynth.grid.native.conditions import Enumeration, condition_limit
from plansynth.grid.native.exact_depth import minimal_program
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.run import RunState
from plansynth.grid.native.stationary import Strategy
from plansynth.grid.native.synth import greedy_program, program_depths, tree_program, useful_conditions
from plansynth.grid.programs import Term, depth

__all__ = ["answer_program", "effort", "tree_within", "DEFAULT_EFFORT"]

#: Default seconds spent making the first program smaller (answer-first mode). On the
#: shared reactive suite's 28 realizable problems 0.05 s gives the same depth against the
#: label's witness (median 0, largest +2) as 0.3 s (median -0.5, largest +2) and as 0.1 s,
#: and the same depths on doors, patrols and the paper's families, while 0.3 s was spent
#: in full on half of them: more than the whole start-up of ``plansynth grid solve``.
DEFAULT_EFFORT = 0.05


def effort(run: RunState, clock: Clock) -> float:
    """Seconds the answer-first mode may spend improving a program: the ``effort``
    option, else :data:`DEFAULT_EFFORT` or 10% of the budget, whichever is smaller."""
    if run.o.effort is not None:
        want = float(run.o.effort)
    else:
        b = run.budget_seconds
        want = DEFAULT_EFFORT if b is None else min(DEFAULT_EFFORT, 0.1 * b)
    return max(0.0, min(want, clock.remaining() - 0.05))


def tree_within(run: RunState, allowed, useful, d: int, n_moves: int, clock: Clock, left: float) -> Term | None:
    """Tree SAT at depth ``d`` within ``left`` seconds and the run's clause and conflict
    limits: a program, or None when there is none or the attempt ran out of its own
    limits (the run's budget running out raises)."""
    try:
        return tree_program(
            allowed,
            useful,
            d,
            n_moves,
            clock,
            max_clauses=run.o.max_clauses,
            max_conflicts=run.o.conflicts,
            max_seconds=left,
        )
    except BudgetExhausted:
        if clock.exhausted():
            raise
        return None


def answer_program(
    run: RunState, arena: Arena, strategy: Strategy, clock: Clock, depth_bound: int | None
) -> Term | None:
    """A small program choosing an allowed move in every state the strategy reaches.

    Answer first: the greedy tree over the enumerated conditions is correct by
    construction, is checked on the game graph (:class:`GameGraph`) at once and
    simplified against it. Then, within the effort (:func:`effort`), smaller
    depths are sought with tree SAT (each attempt bounded by the effort left),
    keeping the best program the checker accepts.
    """
    run.check_conditions_fit(len(strategy.allowed), len(arena.variables()), arena.problem, clock)
    states = sorted(strategy.allowed)
    allowed = [strategy.allowed[s] for s in states]
    inputs = [arena.inputs(r, oc) for r, oc in states]
    run.counters["program_states"] = len(states)
    n_moves = len(arena.robot.moves)
    # Conditions of depth <= 3 (comparisons of coordinates and constants) give the
    # shallowest greedy trees on the reactive suite, and are cheap to enumerate.
    enum = run.conditions(inputs, arena.variables(), arena.problem, min(3, run.o.condition_depth), clock)
    check_clock(clock, "enumerating conditions")
    program = greedy_program(allowed, enum.conditions, n_moves, use_rust=run.o.use_rust)
    graph = program_checker(arena, clock, use_rust=run.o.use_rust)
    run.counters["game_graph_pairs"] = graph.n_pairs
    if graph.check(program) is not None:
        raise AssertionError(f"native engine bug: greedy program {program} does not win on the game graph")
    run.counters["greedy_depth"] = depth(program)
    if run.o.simplify:  # cheap (one compiled check per candidate): part of the answer
        program = simplify(program, graph, time.perf_counter() + max(0.0, clock.remaining() - 0.05))
    run.counters["first_depth"] = depth(program)
    run.phase("answer")
    seconds = effort(run, clock) if run.o.improve else 0.0
    run.counters["effort_seconds"] = round(seconds, 3)
    deadline = time.perf_counter() + seconds
    if seconds > 0 and depth(program) > 1:
        program = _smaller(run, arena, allowed, enum, graph, program, clock, deadline)
    program = _keep_smaller(run, arena, allowed, inputs, graph, program, clock)
    run.counters["program_checks"] = graph.checks
    run.phase("improve")
    if depth_bound is not None and depth(program) > depth_bound:
        return None
    # the engine's own exact check (the solve loop then runs the independent verifier)
    if graph.check(program) is not None:
        raise AssertionError(f"native engine bug: synthesized program {program} does not win")
    run.phase("check")
    run.counters["program_depth"] = depth(program)
    return program


def _keep_smaller(
    run: RunState, arena: Arena, allowed, inputs, graph: GameGraph | ArenaCheck, program: Term, clock: Clock
) -> Term:
    """The default answer or a plain greedy tree over the same strategy, whichever is
    shallower (both checked on the game graph): the greedy tree over every condition up
    to ``condition_depth`` (the answer's own tree uses depth <= 3, which is shallowest
    on the reactive suite but not on every problem), simplified. Skipped when that
    enumeration does not fit the budget or the states are too many for a quick tree."""
    if not run.o.improve or run.o.condition_depth <= 3 or len(allowed) > run.o.improve_states:
        return program
    try:
        run.check_conditions_fit(len(inputs), len(arena.variables()), arena.problem, clock)
        if run.o.use_rust is not False and fast.available():
            plain = fast.greedy_from_enumeration(
                inputs,
                arena.variables(),
                arena.problem.max_constant,
                run.o.condition_depth,
                condition_limit(len(inputs)),
                allowed,
                len(arena.robot.moves),
                10_000,
            )
        else:
            enum = run.conditions(inputs, arena.variables(), arena.problem, run.o.condition_depth, clock)
            plain = greedy_program(allowed, enum.conditions, len(arena.robot.moves), use_rust=False)
    except BudgetExhausted:
        if clock.exhausted():
            raise
        return program
    if plain is None:
        return program
    if graph.check(plain) is not None:
        raise AssertionError(f"native engine bug: greedy program {plain} does not win on the game graph")
    if run.o.simplify:
        plain = simplify(plain, graph, time.perf_counter() + max(0.0, min(clock.remaining() - 0.05, DEFAULT_EFFORT)))
    run.counters["plain_greedy_depth"] = depth(plain)
    if depth(plain) < depth(program):
        run.counters["kept"] = "plain greedy"
        return plain
    return program


def _smaller(
    run: RunState,
    arena: Arena,
    allowed,
    enum: Enumeration,
    graph: GameGraph | ArenaCheck,
    program: Term,
    clock: Clock,
    deadline: float,
) -> Term:
    """Tree SAT at depths below the current program's, largest first, until one
    fails or the effort is spent; every program kept passes the game-graph check."""
    n_moves = len(arena.robot.moves)
    if len(allowed) > run.o.improve_states or deadline - time.perf_counter() <= 0.01:
        return program  # tree SAT over this many states does not fit a small effort
    useful = useful_conditions(allowed, enum.conditions, n_moves, run.o.tree_conditions)
    while depth(program) > 1:
        left = deadline - time.perf_counter()
        if left <= 0.01:
            break
        d = max(dd for dd in program_depths(depth(program) - 1))
        if d > run.o.max_tree_depth:
            break  # a tree SAT this deep does not fit a small effort
        better = tree_within(run, allowed, useful, d, n_moves, clock, left)
        if better is None or graph.check(better) is not None:
            break
        if run.o.simplify:
            better = simplify(better, graph, deadline)
        program = better
    left = deadline - time.perf_counter()
    if depth(program) > 4 and left > 0.01 and graph.n_states <= run.o.exact_states:
        # any winning strategy will do, not only this one: the exact depth search over
        # the whole game when it is small (its encoding is built before any clock check)
        try:
            found, _, _ = minimal_program(
                arena,
                clock,
                depth(program) - 1,
                run,
                arena.problem,
                cond_depth=3,
                max_clauses=run.o.max_clauses,
                max_conflicts=run.o.conflicts,
                max_seconds=left,
                total_seconds=left,
                skip_hard=True,
            )
        except BudgetExhausted:
            if clock.exhausted():
                raise
            found = None
        if found is not None and depth(found) < depth(program) and graph.check(found) is None:
            program = simplify(found, graph, deadline) if run.o.simplify else found
    return program

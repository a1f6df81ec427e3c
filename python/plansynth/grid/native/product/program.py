"""A program of the grammar (Chasins & Newcomb, SYNT 2016, Listing 1) that plays an
allowed move in every state it reaches, learnt from the product game's strategy.

A program wins iff every state of its closed loop (the states it reaches from the start
against every obstacle behaviour) plays one of that state's allowed moves
(:class:`~.strategy.RobotMoves`: any choice among them wins). :class:`ProductCheck`
decides exactly that, by exploring the closed loop; the independent verifier
(:mod:`plansynth.grid.verify`) checks the answer again.

The program is learnt by counterexample-guided rounds: a greedy decision tree
(:func:`~plansynth.grid.native.synth.greedy_program`) over the conditions that the
sample's states tell apart (:mod:`plansynth.grid.native.conditions`) maps every sampled
state to an allowed move; its closed loop is explored; the states it reaches join the
sample, and the rounds end when the closed loop plays only allowed moves. Unlike the
time-expanded game of the paper's objective, where the strategy's whole closure is the
sample, the product game's winning region can be most of the state space (the
moving-obstacle family), so the sample is what the program itself visits.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.check import ops_program, simplify
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.product.strategy import RobotMoves
from plansynth.grid.native.run import RunState
from plansynth.grid.native.synth import greedy_program, program_depths, useful_conditions
from plansynth.grid.programs import Const, Term, compile_program, depth
from plansynth.grid.result import GridStatus

__all__ = ["ProductCheck", "learn_program", "beyond_bound", "SIMPLIFY_SECONDS"]

#: Seconds (beyond the effort) the simplifier may spend on a learnt program: each of its
#: checks explores the program's closed loop (milliseconds on the robot_grid maps, so a
#: second covers a few hundred candidates).
SIMPLIFY_SECONDS = 1.0

StateKey = tuple[int, int]  # (robot cell index, node)


class ProductCheck:
    """The exact check of a program on the product game (the engine's own): its closed
    loop from the start must play an allowed move in every non-final state."""

    def __init__(self, moves: RobotMoves, clock: Clock | None = None, horizon: int | None = None) -> None:
        self.moves = moves
        self.horizon = horizon  # exact objective: the closed loop ends after this many steps
        self.space = moves.space
        self.variables = self.space.problem.variables
        self.n_moves = len(self.space.robot.moves)
        self.clock = clock
        self.checks = 0
        self._allowed: dict[StateKey, tuple[int, ...]] = {}
        self._inputs: dict[StateKey, tuple[int, ...]] = {}

    def allowed(self, s: StateKey) -> tuple[int, ...]:
        got = self._allowed.get(s)
        if got is None:
            got = self._allowed[s] = self.moves.allowed(*s)
        return got

    def inputs(self, s: StateKey) -> tuple[int, ...]:
        got = self._inputs.get(s)
        if got is None:
            got = self._inputs[s] = self.space.inputs(*s)
        return got

    def closure(self, f: Callable[..., int]) -> tuple[list[StateKey], list[StateKey]]:
        """(every non-final state the program reaches, those where it plays a move that
        is not allowed; their successors are not followed)."""
        start = self.space.start()
        seen = {(0, start)}
        order: list[StateKey] = []
        listed: set[StateKey] = set()
        bad: list[StateKey] = []
        queue = deque([(0, start)])
        space = self.space
        timed = self.horizon is not None
        while queue:
            t, s = queue.popleft()
            if self.moves.terminal(*s) or (timed and t == self.horizon):
                continue
            if s in listed:
                if not timed:
                    continue
            else:
                listed.add(s)
                order.append(s)
            k = f(*self.inputs(s))
            if not isinstance(k, int) or isinstance(k, bool) or k not in self.allowed(s):
                bad.append(s)
                continue
            t2 = t + 1 if timed else 0
            for nxt_state in space.successors(s[0], s[1], k):
                nxt = (t2, nxt_state)
                if nxt not in seen:
                    seen.add(nxt)
                    queue.append(nxt)
            if len(order) % 4096 == 0:
                check_clock(self.clock, "exploring the program's closed loop", f" ({len(order)} states)")
        return order, bad

    def check(self, program: Term) -> StateKey | None:
        self.checks += 1
        _, bad = self.closure(compile_program(program, self.variables))
        return bad[0] if bad else None

    def check_ops(self, ops: list[tuple[int, int, int, int]]) -> StateKey | None:
        return self.check(ops_program(ops, self.variables))


def beyond_bound(program: Term, depth_bound: int | None) -> tuple | None:
    """The ``unknown`` answer (status, program, message, witness) when ``program`` is
    deeper than ``depth_bound``: the product game's objectives search no smaller
    programs, so they cannot say that none exists. None within the bound."""
    if depth_bound is None or depth(program) <= depth_bound:
        return None
    return (
        GridStatus.UNKNOWN,
        None,
        f"a winning program of depth {depth(program)} was found; smaller ones are not searched for this objective",
        None,
    )


def learn_program(
    moves: RobotMoves, run: RunState, clock: Clock, *, max_rounds: int = 200, horizon: int | None = None
) -> tuple[Term, ProductCheck]:
    """A program whose closed loop plays only allowed moves (see the module docstring),
    simplified against :class:`ProductCheck`, then made smaller with tree SAT within the
    run's effort. Raises :class:`~plansynth.budget.BudgetExhausted` past the budget."""
    space = moves.space
    problem = space.problem
    check = ProductCheck(moves, clock, horizon)
    sample: dict[StateKey, tuple[int, ...]] = {}
    start = space.start()
    if moves.terminal(*start):
        return Const(0), check  # the play is over before the first move
    sample[start] = check.allowed(start)
    assert sample[start], "learning a program from a state that does not win"
    program: Term | None = None
    for rnd in range(max_rounds):
        states = list(sample)
        allowed = [sample[s] for s in states]
        inputs = [check.inputs(s) for s in states]
        enum = run.conditions(inputs, problem.variables, problem, min(3, run.o.condition_depth), clock)
        check_clock(clock, "enumerating conditions")
        program = greedy_program(allowed, enum.conditions, check.n_moves, max_nodes=1_000_000, use_rust=run.o.use_rust)
        reached, bad = check.closure(compile_program(program, problem.variables))
        grew = 0
        for s in reached:
            if s not in sample:
                sample[s] = check.allowed(s)
                grew += 1
        run.counters["learning_rounds"] = rnd + 1
        run.counters["program_states"] = len(sample)
        if not bad:
            break
        if not grew:
            raise AssertionError("native engine bug: a learnt tree misplays a sampled state")
    else:
        raise BudgetExhausted("learning a program", "iterations", f"no program closed in {max_rounds} rounds")
    assert program is not None
    run.counters["greedy_depth"] = depth(program)
    if run.o.simplify:
        # every check explores the closed loop: the simplifier gets a second beyond the effort
        from plansynth.grid.native.answer import effort

        program = simplify(program, check, time.perf_counter() + SIMPLIFY_SECONDS + effort(run, clock))
    run.counters["first_depth"] = depth(program)
    run.phase("answer")
    program = _improve(run, check, sample, program, clock)
    run.phase("improve")
    if check.check(program) is not None:
        raise AssertionError(f"native engine bug: program {program} does not win the product game")
    run.counters["program_checks"] = check.checks
    run.counters["program_depth"] = depth(program)
    return program, check


def _improve(
    run: RunState, check: ProductCheck, sample: dict[StateKey, tuple[int, ...]], program: Term, clock: Clock
) -> Term:
    """Tree SAT at depths below the program's, on the final sample, within the effort;
    each candidate must pass :class:`ProductCheck` (its own closed loop may differ)."""
    from plansynth.grid.native.answer import effort, tree_within

    seconds = effort(run, clock) if run.o.improve else 0.0
    run.counters["effort_seconds"] = round(seconds, 3)
    deadline = time.perf_counter() + seconds
    if seconds <= 0.01 or depth(program) <= 1 or len(sample) > run.o.improve_states:
        return program
    states = list(sample)
    allowed = [sample[s] for s in states]
    enum = run.conditions(
        [check.inputs(s) for s in states], check.variables, check.space.problem, min(3, run.o.condition_depth), clock
    )
    useful = useful_conditions(allowed, enum.conditions, check.n_moves, run.o.tree_conditions)
    while depth(program) > 1:
        left = deadline - time.perf_counter()
        if left <= 0.01:
            break
        d = max(program_depths(depth(program) - 1))
        if d > run.o.max_tree_depth:
            break
        better = tree_within(run, allowed, useful, d, check.n_moves, clock, left)
        if better is None or check.check(better) is not None:
            break
        program = simplify(better, check, deadline) if run.o.simplify else better
    return program

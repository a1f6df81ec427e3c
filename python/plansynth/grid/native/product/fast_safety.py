"""The safety objective on the compiled product game (:mod:`.compiled`): solve, then
learn a program on its own closed loop or certify the "no" with the obstacles' rank
strategy, all in the core; Python keeps the stages and builds the answer.

The stages and their guarantees are those of :mod:`.solve` (the pure-Python path, its
reference): a program leaves only when its closed loop plays allowed moves only; its
closed loop's states go with it as the witness, so that the solve loop's independent
verifier can check them as an inductive invariant
(:func:`plansynth.grid.verify.invariant.check_invariant`) instead of searching; an
``unrealizable`` leaves only with a rank strategy the core's check accepts from the
start (every robot move meets a collision or a reply of smaller rank).
"""

from __future__ import annotations

import time

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.check import simplify
from plansynth.grid.native.product.compiled import CompiledCheck, CompiledSafety
from plansynth.grid.native.product.program import beyond_bound
from plansynth.grid.native.run import RunState
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, depth
from plansynth.grid.result import GridStatus

__all__ = ["solve_safety_compiled", "ENUM_STATES", "MAX_ROUNDS", "SEED_STATES", "CENTRAL_STATES", "TREE_STATES"]

#: The learner enumerates conditions on at most this many sampled states.
ENUM_STATES = 20_000
#: The learner starts from every winning state of its (glitch-projected) game when they
#: are at most this many (the 32 x 32 moving-obstacle game has 1.5 million, the 48 x 48
#: one some 8 million, the 64 x 64 one 32.5 million): one round then closes, where
#: growing the sample from the start took 8 rounds of closures of most of the game
#: (24 x 24: 11 s of learning instead of 2.5 s; 64 x 64: a program in one round of
#: 283 s, where the growing sample did not close in 600 s). Past it the sample grows
#: round by round.
SEED_STATES = 40_000_000
#: On games whose seeded sample has at least this many states, the learner's labels keep
#: only the allowed moves that end nearest the middle of the grid (the core's
#: ``prefer_central``): the program then keeps to fewer states, and its closed loop,
#: which the check and the verifier go through, is 6-8 times smaller on the
#: moving-obstacle games (24 x 24: 361 thousand states instead of 2.2 million; 32 x 32:
#: 1.4 million instead of 10.3 million), for a deeper tree (33 instead of 28, 36 instead
#: of 32). Below it the tree is the shallower one over every allowed move.
CENTRAL_STATES = 100_000
#: On a larger sample the learner may grow its tree on an evenly spaced part of about
#: this many states, then refine it on the whole sample (each leaf some state reaching it
#: may not follow is replaced by the tree over the states that reach it); None: the
#: tree over the whole sample. Off: on the 48 x 48 moving-obstacle game a part of 1
#: million states (a tenth) saved 15% of the tree's time for a deeper program (46
#: instead of 41), the refinement regrowing large leaves.
TREE_STATES: int | None = None
#: Rounds of the learner before it gives up.
MAX_ROUNDS = 200


def solve_safety_compiled(run: RunState, problem: GridProblem, clock: Clock, depth_bound: int | None):
    game = CompiledSafety(problem, clock, run.memory_mb)
    run.counters["configurations"] = game.n_configs
    run.phase("explore")
    won = game.solve()
    run.counters["fixpoint_rounds"] = game.rounds()
    run.phase("game")
    if won:
        run.counters["decided_seconds"] = _elapsed(run)
    if not won:
        valid, states, why = game.certify()
        run.phase("certify")
        if not valid:
            return (
                GridStatus.UNKNOWN,
                None,
                f"NATIVE ENGINE INTERNAL ERROR: the obstacles' rank strategy fails: {why}",
                None,
            )
        run.counters["certificate_states"] = states
        run.counters["decided_seconds"] = _elapsed(run)
        run.counters["certified_by"] = "the obstacles' rank strategy"
        from plansynth.grid.native.product.compiled_witness import CompiledRefutation

        ref = CompiledRefutation(game, states)
        return GridStatus.UNREALIZABLE, None, f"{ref.detail} (certified: {ref.reason})", ref
    try:
        program, reached, closure_seconds = _learn(run, game, problem, clock)
    except BudgetExhausted as exc:
        raise BudgetExhausted(
            exc.phase,
            exc.resource,
            (
                f"the robot wins the safety game (its winning region holds the start: decided in "
                f"{sum(run.counters['phase_seconds'].values()):.3g} s, {game.rounds()} rounds), but no program was found "
                f"within the budget ({exc})"
            ),
        ) from None
    check = CompiledCheck(game)
    # the last round's closure is the program's (its states stay marked in the core for
    # the witness): it played allowed moves only
    bad: list = []
    if run.o.simplify:
        # each check explores the program's closed loop: the simplifier gets the effort,
        # and is skipped when one check alone costs more
        from plansynth.grid.native.answer import effort

        seconds = effort(run, clock)
        if closure_seconds < seconds:
            program = simplify(program, check, time.perf_counter() + seconds)
            reached, bad, _ = game.closure(program)
    run.counters["first_depth"] = depth(program)
    run.phase("answer")
    if bad:
        raise AssertionError(f"native engine bug: program {program} misplays state {bad[0]}")
    run.counters["program_checks"] = check.checks + 1
    run.counters["program_depth"] = depth(program)
    run.counters["program_closed_loop_states"] = reached
    run.counters["stage"] = "product"
    run.counters["depth_minimal"] = "not proved"
    run.phase("check")
    too_deep = beyond_bound(program, depth_bound)
    if too_deep is not None:
        return too_deep
    return GridStatus.REALIZABLE, program, "safety objective won on the product game", game.reached_sets()


def _elapsed(run: RunState) -> float:
    """Seconds of the run's phases so far."""
    return round(sum(run.counters.get("phase_seconds", {}).values()), 6)


def _learn(run: RunState, game: CompiledSafety, problem: GridProblem, clock: Clock) -> tuple[Term, int, float]:
    """The first program whose closed loop plays allowed moves only, the states its
    closed loop reached and the seconds that closure took."""
    if any(o.glitching for o in problem.obstacles):
        game.core.project_glitches()  # labels from the hardest level: programs that need not read glitches
        run.counters["glitches_projected"] = 1
    seeded = game.core.seed_winning(SEED_STATES)
    if seeded is not None:
        run.counters["seeded_states"] = seeded
        if seeded >= CENTRAL_STATES:
            game.core.prefer_central(True)
            run.counters["central_labels"] = 1
    for rnd in range(MAX_ROUNDS):
        t0 = time.perf_counter()
        closed, sample, reached, program, steps = game.learn_round(
            min(3, run.o.condition_depth), 1_000_000, ENUM_STATES, TREE_STATES
        )
        run.counters["last_round_steps"] = steps
        run.counters["learning_rounds"] = rnd + 1
        run.counters["program_states"] = sample
        run.counters["last_round_seconds"] = round(time.perf_counter() - t0, 4)
        if closed:
            run.counters["greedy_depth"] = depth(program)
            return program, reached, steps["closure"]
    raise BudgetExhausted("learning a program", "iterations", f"no program closed in {MAX_ROUNDS} rounds")

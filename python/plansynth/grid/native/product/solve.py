"""The product engine's stages for one problem (and one path length for ``exact`` and
``reach``): explore the obstacles' configurations, solve the objective's fixpoint,
then either learn a program from the robot's allowed moves or certify the "no" with the
obstacles' strategy.

Every answer is exact and checked before it leaves: a program must pass the engine's
own closed-loop check (:class:`~.program.ProductCheck`; the solve loop then runs the
independent verifier), and an ``unrealizable`` must come with an obstacle strategy that
:func:`~.certify.check_refutation` accepts against every robot move. A certificate
that fails, or a positional strategy the ``exact`` read-off cannot find, gives
``unknown`` with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.budget import Clock
from plansynth.grid.native.product import fixpoints
from plansynth.grid.native.product.certify import Certificate, ObstacleStrategy, check_refutation
from plansynth.grid.native.product.exact import ExactGame
from plansynth.grid.native.product.program import beyond_bound, learn_program
from plansynth.grid.native.product.space import ProductSpace
from plansynth.grid.native.product.strategy import ObstacleReplies, RobotMoves
from plansynth.grid.native.run import RunState
from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term
from plansynth.grid.result import GridStatus

__all__ = ["ProductRefutation", "solve_product"]


@dataclass(frozen=True)
class ProductRefutation:
    """Why no controller exists: the obstacles' strategy and its checked certificate."""

    kind: str
    steps: int | None
    strategy: ObstacleStrategy
    certificate: Certificate
    detail: str


def solve_product(
    run: RunState, problem: GridProblem, steps: int | None, clock: Clock, depth_bound: int | None
) -> tuple[GridStatus, Term | None, str, ProductRefutation | None]:
    """(status, program, message, refutation) for ``problem`` (``steps``: the path
    length of ``exact`` and ``reach``). A safety game runs in the compiled core when it
    is built (:mod:`.compiled`); the realizable answer then hands the verifier the states
    the program keeps (an inductive invariant) as its witness."""
    if problem.objective is ObjectiveKind.SAFETY and run.o.use_rust is not False:
        from plansynth.grid.native.product.compiled import available

        if available():
            from plansynth.grid.native.product.fast_safety import solve_safety_compiled

            return solve_safety_compiled(run, problem, clock, depth_bound)
    space = ProductSpace.explore(problem, clock, run.o.max_configs)
    run.counters["configurations"] = space.n_configs
    run.counters["nodes"] = space.n_nodes
    run.phase("explore")
    kind = problem.objective
    r0, n0 = space.start()
    if kind is ObjectiveKind.EXACT:
        assert steps is not None
        game = ExactGame(space, steps, clock)
        run.phase("game")
        if not game.won:
            return _refuted(
                run, problem, steps, game, clock, "the obstacles win even against controllers that see the time"
            )
        if game.choice is None:
            return (
                GridStatus.UNKNOWN,
                None,
                (
                    "controllers that see the time win, and no positional strategy was read "
                    "off the game (the exact positional question is implemented for the "
                    "paper's model only)"
                ),
                None,
            )
        moves = game
        horizon = steps
    else:
        if kind is ObjectiveKind.SAFETY:
            sol = fixpoints.safety(space, clock)
        elif kind is ObjectiveKind.REACH:
            assert steps is not None
            sol = fixpoints.reach(space, steps, clock)
        else:
            sol = fixpoints.recurrence(space, clock)
        run.counters["fixpoint_rounds"] = sol.rounds
        run.phase("game")
        run.counters["decided_seconds"] = round(sum(run.counters["phase_seconds"].values()), 6)
        if not sol.wins(r0, n0):
            dual = fixpoints.recurrence_dual(space, clock) if kind is ObjectiveKind.RECURRENCE else None
            if dual is not None and not dual[0][n0] >> r0 & 1:
                raise AssertionError("native engine bug: the two sides of the recurrence game disagree")
            return _refuted(run, problem, steps, ObstacleReplies(sol, dual), clock, _why(problem, steps))
        moves = RobotMoves(sol)
        horizon = None
    program, _ = learn_program(moves, run, clock, horizon=horizon)
    too_deep = beyond_bound(program, depth_bound)
    if too_deep is not None:
        return too_deep
    run.counters["stage"] = "product"
    run.counters["depth_minimal"] = "not proved"
    return GridStatus.REALIZABLE, program, f"{kind.value} objective won on the product game", None


def _why(problem: GridProblem, steps: int | None) -> str:
    kind = problem.objective
    if kind is ObjectiveKind.SAFETY:
        return "the obstacles force a collision"
    if kind is ObjectiveKind.REACH:
        return f"the obstacles keep the robot off the goal for {steps} steps or force a collision"
    fair = " while every obstacle keeps moving" if problem.fair else ""
    return f"the obstacles keep the robot from visiting the goals in turn forever{fair}"


def _refuted(run: RunState, problem: GridProblem, steps: int | None, replies, clock: Clock, detail: str):
    strategy = ObstacleStrategy(replies)
    cert = check_refutation(problem, strategy, steps, clock)
    run.counters["certificate_states"] = cert.states
    run.phase("certify")
    run.counters["decided_seconds"] = round(sum(run.counters["phase_seconds"].values()), 6)
    if not cert.valid:
        return (
            GridStatus.UNKNOWN,
            None,
            f"NATIVE ENGINE INTERNAL ERROR: the obstacles' strategy fails: {cert.reason}",
            None,
        )
    run.counters["certified_by"] = "the obstacles' strategy"
    ref = ProductRefutation("game", steps, strategy, cert, detail)
    return GridStatus.UNREALIZABLE, None, f"{detail} (certified: {cert.reason}, {cert.states} states)", ref

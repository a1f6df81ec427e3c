"""The native engine for one path length: cone, blind plan, game, stationary SAT, program.

Stages, cheapest first (each exact for what it claims):

1. **Cone of influence** (:mod:`cone`): drop obstacles that can never meet the robot.
2. **Blind controller**: a program that reads no obstacle must avoid every cell any
   relevant obstacle may sweep at each step; deciding whether one exists is a small
   stationary SAT over robot cells. The paper's four families are all solved here.
3. **Game**: explore the joint states of the robot and the relevant obstacles and
   decide the time-dependent game by backward induction. Losing it proves that no
   controller exists (the witness is the obstacles' winning strategy, :mod:`explain`).
4. **Stationary SAT** (:mod:`stationary`): exact existence of a position-only strategy.
5. **Program** (:mod:`synth`): the smallest decision tree over enumerated conditions
   that picks an allowed move in every state the strategy reaches; it is checked on the
   game graph (:func:`program_wins`) before it is returned.

Obstacles outside the cone may still work as a *clock* when the adversary cannot keep
them still (a program could read their coordinates to learn the time). Dropping them is
exact when each one can stay on its start cell; otherwise an ``unrealizable`` from step
4 is re-checked with strategies that may depend on the time until all of them can park
(see :func:`~plansynth.grid.native.cone.clock_label`), and the answer is ``unknown``
if that check does not close.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from plansynth.budget import Budget, BudgetExhausted, Clock
from plansynth.grid.native.answer import answer_program
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.check import program_wins
from plansynth.grid.native.cone import Cone, clock_label, influence_cone
from plansynth.grid.native.exact_depth import minimal_program
from plansynth.grid.native.options import InvalidOption, NativeOptions
from plansynth.grid.native.run import RunState
from plansynth.grid.native.stationary import stationary_strategy
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, depth
from plansynth.grid.result import GridStatus, LengthOutcome

__all__ = ["Engine", "Refutation", "program_wins"]


@dataclass(frozen=True)
class Refutation:
    """Why no controller exists at this length: ``kind`` is ``goal`` (the goal cannot
    be reached in exactly l steps even without obstacles), ``game`` (the obstacles win
    even against time-dependent strategies; the arena holds their strategy) or
    ``stationary`` (time-dependent strategies win, position-only ones do not)."""

    kind: str
    steps: int
    arena: Arena | None = None
    detail: str = ""


class Engine:
    """The native engine: maps a problem, a path length and a budget to a
    :class:`~plansynth.grid.result.LengthOutcome`. Its options are one frozen
    :class:`~plansynth.grid.native.options.NativeOptions` (or its fields as keywords);
    what a run did (counters, phase times) is in the outcome, never on the engine.

    By default the engine answers first: the greedy decision tree over the enumerated
    conditions, checked on the game graph and simplified against it
    (:func:`~plansynth.grid.native.check.simplify`), is a correct program at once; then
    at most ``effort`` seconds (default
    :data:`~plansynth.grid.native.answer.DEFAULT_EFFORT` or 10% of the budget,
    whichever is smaller) go to making it smaller with tree SAT at smaller depths,
    keeping the best verified program. ``minimize`` instead proves the smallest depth.
    The counters say which (``depth_minimal``: ``proved`` or ``not proved``) and time
    each phase (``phase_seconds``).
    """

    def __init__(self, options: NativeOptions | None = None, **values: Any) -> None:
        if options is not None and values:
            raise InvalidOption(
                "native", "options", "give the native options as one NativeOptions or as keywords, not both"
            )
        self.options = options if options is not None else NativeOptions.parse(**values)

    def solve_length(
        self, problem: GridProblem, steps: int | None, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        """Decide length ``steps`` within ``budget`` (a fresh run: nothing is kept);
        ``steps`` is None for the objectives without a path length."""
        return _Run(self.options).solve_length(problem, steps, budget, depth_bound=depth_bound)


class _Run(RunState):
    """One solve of one length through the stages (the module docstring), on the state
    of the run (:class:`~plansynth.grid.native.run.RunState`)."""

    def solve_length(
        self, problem: GridProblem, steps: int | None, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        clock = budget.clock()
        t0 = time.perf_counter()
        self.start(budget, t0)
        try:
            status, program, message, witness = self._solve(problem, steps, clock, depth_bound)
        except BudgetExhausted as exc:
            status, program, message, witness = GridStatus.UNKNOWN, None, f"budget exhausted: {exc}", None
        except AssertionError as exc:  # an engine bug must never become an answer
            status, program, message, witness = GridStatus.UNKNOWN, None, f"NATIVE ENGINE INTERNAL ERROR: {exc}", None
        if status is GridStatus.REALIZABLE and depth_bound is not None and depth(program) > depth_bound:
            # (a path that builds its program without the bound, e.g. reading clock obstacles):
            # the question was "a program of depth <= D", and this one does not answer it
            status, program, message = (
                GridStatus.UNKNOWN,
                None,
                (f"a winning program of depth {depth(program)} was found, none of depth <= {depth_bound}"),
            )
        if status is GridStatus.REALIZABLE:
            self.counters["depth_minimal"] = "proved" if self.counters.get("minimal_depth_proved") else "not proved"
        return LengthOutcome(
            status=status,
            steps=steps,
            program=program,
            seconds=time.perf_counter() - t0,
            counters=dict(self.counters),
            message=message,
            witness=witness,
        )

    def _solve(self, problem: GridProblem, steps: int | None, clock: Clock, depth_bound: int | None):
        if not problem.paper_model:
            # another objective, or obstacles with a block, a period or glitches: the product game
            from plansynth.grid.native.product.solve import solve_product

            return solve_product(self, problem, steps, clock, depth_bound)
        cone = influence_cone(problem, steps, clock)
        self.counters["relevant_obstacles"] = len(cone.relevant)
        self.counters["dropped_obstacles"] = len(problem.obstacles) - len(cone.relevant)
        if not cone.goal_reachable:
            ref = Refutation(
                "goal", steps, detail=f"the goal cannot be reached in exactly {steps} steps even without obstacles"
            )
            return GridStatus.UNREALIZABLE, None, ref.detail, ref
        exact_bound = self.o.minimize or depth_bound is not None

        # Stage 2: a controller that reads no obstacle.
        blind = Arena.build(problem, steps, cone, (), clock, use_rust=self.o.use_rust)
        blind_program = None
        if blind.layers[0] and blind.solve_game(clock):
            strategy = stationary_strategy(blind, clock, quick=self.o.quick)
            self.phase("blind")
            if strategy is not None:
                self.counters["stage"] = "blind"
                program = answer_program(self, blind, strategy, clock, depth_bound)
                if program is not None and not exact_bound:
                    return GridStatus.REALIZABLE, program, "obstacle-blind controller", None
                if (
                    program is not None
                    and depth_bound is not None
                    and not self.o.minimize
                    and depth(program) <= depth_bound
                ):
                    return GridStatus.REALIZABLE, program, "obstacle-blind controller", None
                if self.o.minimize:
                    blind_program = self._blind_minimal(problem, blind, clock, program)
                    if blind_program is not None and depth(blind_program) <= 4:
                        # Depth 1 is a constant move, which reads nothing: the blind
                        # search refuted it exactly, so depth 4 (or 1) is minimal.
                        self.counters["program_depth"] = depth(blind_program)
                        self.counters["minimal_depth_proved"] = True
                        return (
                            GridStatus.REALIZABLE,
                            blind_program,
                            f"depth {depth(blind_program)} is minimal (proved)",
                            None,
                        )

        # Stages 3-4: the joint game over the relevant obstacles.
        try:
            self.phase("blind")
            arena = Arena.build(
                problem,
                steps,
                cone,
                cone.relevant,
                clock,
                self.o.max_configs,
                memory_mb=self.memory_mb,
                use_rust=self.o.use_rust,
            )
            self.counters["configurations"] = arena.config_count()
            self.counters["states"] = arena.state_count()
            won = arena.start_alive() and arena.solve_game(clock)
            self.phase("game")
            if not won:
                ref = Refutation("game", steps, arena, "the obstacles win even against controllers that see the time")
                return GridStatus.UNREALIZABLE, None, ref.detail, ref
            if exact_bound:
                if stationary_strategy(arena, clock, quick=self.o.quick) is None:
                    # No positional strategy at all: no program of any depth exists, and
                    # the depth search below could only give up (it would say unknown).
                    self.phase("stationary")
                    return self._stationary_refuted(problem, arena, cone, clock)
                return self._bounded(problem, arena, cone, clock, depth_bound)
        except BudgetExhausted as exc:
            if blind_program is None:
                raise
            self.counters["program_depth"] = depth(blind_program)
            self.counters["minimal_depth_proved"] = False
            return (
                GridStatus.REALIZABLE,
                blind_program,
                (
                    f"obstacle-blind controller of depth {depth(blind_program)}; smaller programs reading obstacles "
                    f"not excluded ({exc})"
                ),
                None,
            )
        strategy = stationary_strategy(arena, clock, quick=self.o.quick)
        self.phase("stationary")
        if strategy is None:
            return self._stationary_refuted(problem, arena, cone, clock)
        self.counters["stage"] = "joint"
        self.counters.update(strategy.counters)
        program = answer_program(self, arena, strategy, clock, None)
        assert program is not None
        return GridStatus.REALIZABLE, program, "controller reads obstacles" if arena.read else "", None

    def _blind_minimal(self, problem: GridProblem, blind: Arena, clock: Clock, program: Term | None) -> Term | None:
        """The smallest obstacle-blind program (exact over blind programs when it ends)."""
        top = depth(program) if program is not None else self.o.max_tree_depth
        try:
            found, _, _ = minimal_program(blind, clock, top, self, problem)
        except BudgetExhausted:
            if clock.exhausted():
                raise
            found = None
        best = found if found is not None else program
        if best is not None and not program_wins(problem, blind.steps, best, clock):
            raise AssertionError(f"native engine bug: program {best} does not win")
        return best

    # -- no stationary strategy --------------------------------------------------------
    def _stationary_refuted(self, problem: GridProblem, arena: Arena, cone: Cone, clock: Clock):
        label = clock_label(problem, cone)
        if label is not None and stationary_strategy(arena, clock, label) is not None:
            # Obstacles outside the cone that cannot stay put might tell a controller the
            # time. Decide exactly by reading them too (they never collide).
            clocks = tuple(i for i in range(len(problem.obstacles)) if i not in cone.relevant and not cone.parkable[i])
            read = tuple(sorted(cone.relevant + clocks))
            full = Arena.build(
                problem,
                arena.steps,
                cone,
                read,
                clock,
                self.o.max_configs,
                memory_mb=self.memory_mb,
                use_rust=self.o.use_rust,
            )
            self.counters["clock_obstacles"] = len(clocks)
            if full.layers[0] and full.solve_game(clock):
                strategy = stationary_strategy(full, clock, quick=self.o.quick)
                if strategy is not None:
                    self.counters["stage"] = "joint+clock"
                    program = answer_program(self, full, strategy, clock, None)
                    return (
                        GridStatus.REALIZABLE,
                        program,
                        "controller reads obstacles outside the cone as a clock",
                        None,
                    )
        ref = Refutation(
            "stationary",
            arena.steps,
            arena,
            "controllers that see the time would win, but no controller that sees only positions does",
        )
        return GridStatus.UNREALIZABLE, None, ref.detail, ref

    # -- programs ----------------------------------------------------------------------
    def _bounded(self, problem: GridProblem, arena: Arena, cone: Cone, clock: Clock, depth_bound: int | None):
        """Smallest program depth over all stationary winning strategies (exact when the
        conditions are enumerated completely to the depths that matter)."""
        found, proved, d_used = minimal_program(arena, clock, depth_bound, self, problem)
        parkable = all(cone.parkable[i] for i in range(len(problem.obstacles)) if i not in cone.relevant)
        if found is not None:
            if not program_wins(problem, arena.steps, found, clock):
                raise AssertionError(f"native engine bug: program {found} does not win")
            self.counters["program_depth"] = depth(found)
            self.counters["minimal_depth_proved"] = bool(proved and parkable)
            msg = (
                f"depth {depth(found)} is minimal (proved)"
                if proved and parkable
                else f"depth {depth(found)}; smaller depths not excluded"
            )
            return GridStatus.REALIZABLE, found, msg, None
        if proved and parkable:
            return GridStatus.UNREALIZABLE, None, f"no program of depth <= {d_used} wins", None
        return (
            GridStatus.UNKNOWN,
            None,
            f"no program of depth <= {d_used} found; conditions not enumerated completely",
            None,
        )

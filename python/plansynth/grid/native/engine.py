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
(see :func:`_clock_label`), and the answer is ``unknown`` if that check does not close.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from plansynth.budget import DEFAULT_MEMORY_MB, Budget, BudgetExhausted, Clock
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.bitgrid import bits, cell_mask
from plansynth.grid.native.check import GameGraph, program_checker, simplify
from plansynth.grid.native.conditions import Enumeration, conditions_upto
from plansynth.grid.native.cone import Cone, influence_cone
from plansynth.grid.native.options import CONDITION_DEPTH, MAX_TREE_DEPTH, InvalidOption, NativeOptions
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.sat import ConflictLimit, solve_clauses
from plansynth.grid.native.stationary import (
    Strategy,
    encode_stationary,
    stationary_strategy,
    winning_forward,
)
from plansynth.grid.native.synth import (
    TreeEncoding,
    conditions_by_level,
    greedy_program,
    program_depths,
    tree_levels,
    tree_program,
    useful_conditions,
)
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, compile_program, depth
from plansynth.grid.result import GridStatus, LengthOutcome

#: Behaviour cells (condition x program state) the compiled condition enumeration
#: computes per second, conservatively (2.6e8 measured on a loaded 2-core machine): the
#: enumeration is refused when its estimate does not fit the time left.
CONDITION_CELLS_PER_SECOND = 1e8
#: Default seconds spent making the first program smaller (answer-first mode). On the
#: shared reactive suite's 28 realizable problems 0.05 s gives the same depth against the
#: label's witness (median 0, largest +2) as 0.3 s (median -0.5, largest +2) and as 0.1 s,
#: and the same depths on doors, patrols and the paper's families, while 0.3 s was spent
#: in full on half of them: more than the whole start-up of ``plansynth grid solve``.
DEFAULT_EFFORT = 0.05


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
    at most ``effort`` seconds (default :data:`DEFAULT_EFFORT` or 10% of the budget,
    whichever is smaller) go to making it smaller with tree SAT at smaller depths,
    keeping the best verified program. ``minimize`` instead proves the smallest depth.
    The counters say which (``depth_minimal``: ``proved`` or ``not proved``) and time
    each phase (``phase_seconds``).
    """

    def __init__(self, options: NativeOptions | None = None, **values: Any) -> None:
        if options is not None and values:
            raise InvalidOption("native", "options", "give the native options as one NativeOptions or as keywords, not both")
        self.options = options if options is not None else NativeOptions.parse(**values)

    def solve_length(self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None) -> LengthOutcome:
        """Decide length ``steps`` within ``budget`` (a fresh run: nothing is kept)."""
        return _Run(self.options).solve_length(problem, steps, budget, depth_bound=depth_bound)


class _Run:
    """One solve of one length: the options (read only) and the counters of this run."""

    def __init__(self, options: NativeOptions) -> None:
        self.o = options
        self.counters: dict[str, Any] = {}

    # -- the entry point -------------------------------------------------------------
    def solve_length(self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None) -> LengthOutcome:
        clock = budget.clock()
        t0 = time.perf_counter()
        self.counters = {"phase_seconds": {}}
        self._t_phase = t0
        self._budget_seconds = budget.seconds
        # the joint game is explored until it would outgrow this or the time runs out;
        # ``max_configs`` adds an explicit cap on obstacle configurations
        self._memory_mb = budget.memory_mb or DEFAULT_MEMORY_MB
        try:
            status, program, message, witness = self._solve(problem, steps, clock, depth_bound)
        except BudgetExhausted as exc:
            status, program, message, witness = GridStatus.UNKNOWN, None, f"budget exhausted: {exc}", None
        except AssertionError as exc:  # an engine bug must never become an answer
            status, program, message, witness = GridStatus.UNKNOWN, None, f"NATIVE ENGINE INTERNAL ERROR: {exc}", None
        if status is GridStatus.REALIZABLE and depth_bound is not None and depth(program) > depth_bound:
            # (a path that builds its program without the bound, e.g. reading clock obstacles):
            # the question was "a program of depth <= D", and this one does not answer it
            status, program, message = GridStatus.UNKNOWN, None, (
                f"a winning program of depth {depth(program)} was found, none of depth <= {depth_bound}")
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

    def _phase(self, name: str) -> None:
        """Close the current phase: add its seconds to ``phase_seconds[name]``."""
        now = time.perf_counter()
        ph = self.counters.setdefault("phase_seconds", {})
        ph[name] = round(ph.get(name, 0.0) + now - self._t_phase, 6)
        self._t_phase = now

    def _effort(self, clock: Clock) -> float:
        """Seconds the answer-first mode may spend improving a program."""
        if self.o.effort is not None:
            want = float(self.o.effort)
        else:
            b = self._budget_seconds
            want = DEFAULT_EFFORT if b is None else min(DEFAULT_EFFORT, 0.1 * b)
        return max(0.0, min(want, clock.remaining() - 0.05))

    def _solve(self, problem: GridProblem, steps: int, clock: Clock, depth_bound: int | None):
        cone = influence_cone(problem, steps, clock)
        self.counters["relevant_obstacles"] = len(cone.relevant)
        self.counters["dropped_obstacles"] = len(problem.obstacles) - len(cone.relevant)
        if not cone.goal_reachable:
            ref = Refutation("goal", steps, detail=f"the goal cannot be reached in exactly {steps} steps even without obstacles")
            return GridStatus.UNREALIZABLE, None, ref.detail, ref
        exact_bound = self.o.minimize or depth_bound is not None

        # Stage 2: a controller that reads no obstacle.
        blind = Arena.build(problem, steps, cone, (), clock, use_rust=self.o.use_rust)
        blind_program = None
        if blind.layers[0] and blind.solve_game(clock):
            strategy = stationary_strategy(blind, clock, quick=self.o.quick)
            self._phase("blind")
            if strategy is not None:
                self.counters["stage"] = "blind"
                program = self._program(blind, strategy, clock, depth_bound)
                if program is not None and not exact_bound:
                    return GridStatus.REALIZABLE, program, "obstacle-blind controller", None
                if program is not None and depth_bound is not None and not self.o.minimize and depth(program) <= depth_bound:
                    return GridStatus.REALIZABLE, program, "obstacle-blind controller", None
                if self.o.minimize:
                    blind_program = self._blind_minimal(problem, blind, clock, program)
                    if blind_program is not None and depth(blind_program) <= 4:
                        # Depth 1 is a constant move, which reads nothing: the blind
                        # search refuted it exactly, so depth 4 (or 1) is minimal.
                        self.counters["program_depth"] = depth(blind_program)
                        self.counters["minimal_depth_proved"] = True
                        return GridStatus.REALIZABLE, blind_program, f"depth {depth(blind_program)} is minimal (proved)", None

        # Stages 3-4: the joint game over the relevant obstacles.
        try:
            self._phase("blind")
            arena = Arena.build(problem, steps, cone, cone.relevant, clock, self.o.max_configs, memory_mb=self._memory_mb,
                                use_rust=self.o.use_rust)
            self.counters["configurations"] = arena.config_count()
            self.counters["states"] = arena.state_count()
            won = arena.start_alive() and arena.solve_game(clock)
            self._phase("game")
            if not won:
                ref = Refutation("game", steps, arena, "the obstacles win even against controllers that see the time")
                return GridStatus.UNREALIZABLE, None, ref.detail, ref
            if exact_bound:
                if stationary_strategy(arena, clock, quick=self.o.quick) is None:
                    # No positional strategy at all: no program of any depth exists, and
                    # the depth search below could only give up (it would say unknown).
                    self._phase("stationary")
                    return self._stationary_refuted(problem, arena, cone, clock)
                return self._bounded(problem, arena, cone, clock, depth_bound)
        except BudgetExhausted as exc:
            if blind_program is None:
                raise
            self.counters["program_depth"] = depth(blind_program)
            self.counters["minimal_depth_proved"] = False
            return GridStatus.REALIZABLE, blind_program, (
                f"obstacle-blind controller of depth {depth(blind_program)}; smaller programs reading obstacles "
                f"not excluded ({exc})"), None
        strategy = stationary_strategy(arena, clock, quick=self.o.quick)
        self._phase("stationary")
        if strategy is None:
            return self._stationary_refuted(problem, arena, cone, clock)
        self.counters["stage"] = "joint"
        self.counters.update(strategy.counters)
        program = self._program(arena, strategy, clock, None)
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
        label = _clock_label(problem, cone)
        if label is not None and stationary_strategy(arena, clock, label) is not None:
            # Obstacles outside the cone that cannot stay put might tell a controller the
            # time. Decide exactly by reading them too (they never collide).
            clocks = tuple(i for i in range(len(problem.obstacles)) if i not in cone.relevant and not cone.parkable[i])
            read = tuple(sorted(cone.relevant + clocks))
            full = Arena.build(problem, arena.steps, cone, read, clock, self.o.max_configs, memory_mb=self._memory_mb,
                               use_rust=self.o.use_rust)
            self.counters["clock_obstacles"] = len(clocks)
            if full.layers[0] and full.solve_game(clock):
                strategy = stationary_strategy(full, clock, quick=self.o.quick)
                if strategy is not None:
                    self.counters["stage"] = "joint+clock"
                    program = self._program(full, strategy, clock, None)
                    return GridStatus.REALIZABLE, program, "controller reads obstacles outside the cone as a clock", None
        ref = Refutation("stationary", arena.steps, arena,
                         "controllers that see the time would win, but no controller that sees only positions does")
        return GridStatus.UNREALIZABLE, None, ref.detail, ref

    # -- programs ----------------------------------------------------------------------
    def _conditions(self, states: list[tuple[int, ...]], variables, problem: GridProblem, max_depth: int,
                    clock: Clock | None = None) -> Enumeration:
        # the behaviours cost len(states) bits each: bound their memory and time
        limit = min(200_000, max(5_000, 40_000_000 // max(1, len(states))))
        if clock is not None:
            self._conditions_fit(len(states), len(variables), problem, clock)
        e = conditions_upto(states, variables, problem.max_constant, max_depth, limit=limit, use_rust=self.o.use_rust)
        self.counters["conditions"] = len(e.conditions)
        return e

    def _conditions_fit(self, n_states: int, n_vars: int, problem: GridProblem, clock: Clock) -> None:
        """The condition enumeration cannot be interrupted: refuse it (BudgetExhausted)
        when its estimated work (comparisons of the depth-2 terms over every state)
        does not fit the time left, or its behaviours the memory budget."""
        limit = min(200_000, max(5_000, 40_000_000 // max(1, n_states)))
        terms = problem.max_constant + 2 + n_vars
        work = min(limit, 2 * terms * terms) * n_states
        need = work / CONDITION_CELLS_PER_SECOND
        nbytes = min(limit, 2 * terms * terms) * (n_states // 8 + 64) + terms * n_states * 8
        if need > clock.remaining():
            raise BudgetExhausted("enumerating conditions", "time",
                                  f"enumerating conditions over {n_states} program states would take about "
                                  f"{need:.0f} s ({max(0.0, clock.remaining()):.1f} s left)")
        if nbytes > (self._memory_mb << 20):
            raise BudgetExhausted("enumerating conditions", "memory",
                                  f"enumerating conditions over {n_states} program states needs about "
                                  f"{nbytes >> 20} MB (memory budget {self._memory_mb} MB)")

    def _program(self, arena: Arena, strategy: Strategy, clock: Clock, depth_bound: int | None) -> Term | None:
        """A small program choosing an allowed move in every state the strategy reaches.

        Answer first: the greedy tree over the enumerated conditions is correct by
        construction, is checked on the game graph (:class:`GameGraph`) at once and
        simplified against it. Then, within the effort (:meth:`_effort`), smaller
        depths are sought with tree SAT (each attempt bounded by the effort left),
        keeping the best program the checker accepts.
        """
        self._conditions_fit(len(strategy.allowed), len(arena.variables()), arena.problem, clock)
        states = sorted(strategy.allowed)
        allowed = [strategy.allowed[s] for s in states]
        inputs = [arena.inputs(r, oc) for r, oc in states]
        self.counters["program_states"] = len(states)
        n_moves = len(arena.robot.moves)
        # Conditions of depth <= 3 (comparisons of coordinates and constants) give the
        # shallowest greedy trees on the reactive suite, and are cheap to enumerate.
        enum = self._conditions(inputs, arena.variables(), arena.problem, min(3, self.o.condition_depth), clock)
        check_clock(clock, "enumerating conditions")
        program = greedy_program(allowed, enum.conditions, n_moves, use_rust=self.o.use_rust)
        graph = program_checker(arena, clock, use_rust=self.o.use_rust)
        self.counters["game_graph_pairs"] = graph.n_pairs
        if graph.check(program) is not None:
            raise AssertionError(f"native engine bug: greedy program {program} does not win on the game graph")
        self.counters["greedy_depth"] = depth(program)
        if self.o.simplify:  # cheap (one compiled check per candidate): part of the answer
            program = simplify(program, graph, time.perf_counter() + max(0.0, clock.remaining() - 0.05))
        self.counters["first_depth"] = depth(program)
        self._phase("answer")
        effort = self._effort(clock) if self.o.improve else 0.0
        self.counters["effort_seconds"] = round(effort, 3)
        deadline = time.perf_counter() + effort
        if effort > 0 and depth(program) > 1:
            program = self._smaller(arena, allowed, enum, graph, program, clock, deadline)
        self.counters["program_checks"] = graph.checks
        self._phase("improve")
        if depth_bound is not None and depth(program) > depth_bound:
            return None
        # the engine's own exact check (the solve loop then runs the independent verifier)
        if graph.check(program) is not None:
            raise AssertionError(f"native engine bug: synthesized program {program} does not win")
        self._phase("check")
        self.counters["program_depth"] = depth(program)
        return program

    def _smaller(self, arena: Arena, allowed, enum: Enumeration, graph: GameGraph, program: Term, clock: Clock,
                 deadline: float) -> Term:
        """Tree SAT at depths below the current program's, largest first, until one
        fails or the effort is spent; every program kept passes the game-graph check."""
        n_moves = len(arena.robot.moves)
        if len(allowed) > self.o.improve_states or deadline - time.perf_counter() <= 0.01:
            return program  # tree SAT over this many states does not fit a small effort
        useful = useful_conditions(allowed, enum.conditions, n_moves, self.o.tree_conditions)
        while depth(program) > 1:
            left = deadline - time.perf_counter()
            if left <= 0.01:
                break
            d = max(dd for dd in program_depths(depth(program) - 1))
            if d > self.o.max_tree_depth:
                break  # a tree SAT this deep does not fit a small effort
            try:
                better = tree_program(allowed, useful, d, n_moves, clock, max_clauses=self.o.max_clauses,
                                      max_conflicts=self.o.conflicts, max_seconds=left)
            except BudgetExhausted:
                if clock.exhausted():
                    raise
                break
            if better is None or graph.check(better) is not None:
                break
            if self.o.simplify:
                better = simplify(better, graph, deadline)
            program = better
        left = deadline - time.perf_counter()
        if depth(program) > 4 and left > 0.01 and graph.n_states <= self.o.exact_states:
            # any winning strategy will do, not only this one: the exact depth search over
            # the whole game when it is small (its encoding is built before any clock check)
            try:
                found, _, _ = minimal_program(arena, clock, depth(program) - 1, self, arena.problem, cond_depth=3,
                                              max_clauses=self.o.max_clauses, max_conflicts=self.o.conflicts,
                                              max_seconds=left, total_seconds=left, skip_hard=True)
            except BudgetExhausted:
                if clock.exhausted():
                    raise
                found = None
            if found is not None and depth(found) < depth(program) and graph.check(found) is None:
                program = simplify(found, graph, deadline) if self.o.simplify else found
        return program

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
            msg = f"depth {depth(found)} is minimal (proved)" if proved and parkable else f"depth {depth(found)}; smaller depths not excluded"
            return GridStatus.REALIZABLE, found, msg, None
        if proved and parkable:
            return GridStatus.UNREALIZABLE, None, f"no program of depth <= {d_used} wins", None
        return GridStatus.UNKNOWN, None, f"no program of depth <= {d_used} found; conditions not enumerated completely", None


def minimal_program(arena: Arena, clock: Clock, depth_bound: int | None, engine: "_Run", problem: GridProblem,
                    cond_depth: int | None = None, max_clauses: int | None = None, max_conflicts: int | None = None,
                    max_seconds: float | None = None, total_seconds: float | None = None, skip_hard: bool = False):
    """Search program depths 1, 4, 5, ... for a winning program over the whole game.

    Returns ``(program or None, proved, last depth tried)``; ``proved`` is True when
    every smaller depth was refuted with a complete condition enumeration.
    """
    fwd = winning_forward(arena)
    states = sorted({(r, oc) for layer in fwd[:-1] for oc, m in layer.items() for r in bits(m)})
    top_ = depth_bound if depth_bound is not None else engine.o.max_tree_depth
    if max_clauses is not None and (len(states) > engine.o.improve_states or len(states) * 2 ** tree_levels(min(top_, 5)) > max_clauses // 50):
        raise BudgetExhausted("the exact depth search", "states",
                              f"{len(states)} states are too many for the exact depth search")
    clauses, ids, fwd = encode_stationary(arena, clock, fwd=fwd)
    index = {s: i for i, s in enumerate(states)}
    inputs = [arena.inputs(r, oc) for r, oc in states]
    engine.counters["universe_states"] = len(states)
    top = depth_bound if depth_bound is not None else engine.o.max_tree_depth
    cap = min(5, engine.o.condition_depth + 1) if cond_depth is None else cond_depth
    if max_clauses is not None and len(states) * 2 ** tree_levels(min(top, 5)) > max_clauses // 50:
        raise BudgetExhausted("the exact depth search", "states",
                              f"{len(states)} states are too many for the exact depth search")
    n_moves = len(arena.robot.moves)
    proved = True
    last = 0
    enums: dict[int, Enumeration] = {}
    started = time.perf_counter()
    for d in program_depths(top):
        if total_seconds is not None and time.perf_counter() - started > total_seconds:
            raise BudgetExhausted("the exact depth search", "time", f"exact depth search beyond {total_seconds} s")
        last = d
        need = max(2, min(d - 1, cap))  # the root's conditions have depth <= d - 1
        if need not in enums:
            enums[need] = engine._conditions(inputs, arena.variables(), problem, need, clock)
        enum = enums[need]
        by_level = conditions_by_level(enum.conditions, d, len(states))
        est = len(clauses) + sum(len(by_level[(n + 1).bit_length() - 1]) for n in range(2 ** tree_levels(d) - 1)) * len(states)
        engine.counters["exact_search_clauses"] = est
        if max_clauses is not None and est > max_clauses:
            raise BudgetExhausted("the exact depth search", "clauses", f"depth-{d} search of about {est} clauses")
        enc = TreeEncoding(tree_levels(d), by_level, len(states), n_moves, len(ids), list(clauses))

        def out_lit(s: int, k: int, states=states):
            r, oc = states[s]
            v = ids.get(("m", r, oc, 0, k))
            return False if v is None else v

        enc.build(out_lit, clock)
        try:
            model = solve_clauses(enc.clauses, clock, max_conflicts=max_conflicts, max_seconds=max_seconds)
        except ConflictLimit:
            if not skip_hard:
                raise
            proved = False  # this depth is left undecided; try the next one
            continue
        if model is not None:
            return enc.program(model), proved, d
        if d >= 4 and enum.complete_to < d - 1:
            proved = False
    return None, proved, last


def _clock_label(problem: GridProblem, cone: Cone):
    """The time label that accounts for dropped obstacles that cannot stay put.

    Returns None when every dropped obstacle can be kept on its start cell; otherwise
    ``t -> min(t, K)`` where by time K the adversary can have parked all of them.
    """
    from plansynth.grid.native.bitgrid import AgentGeometry

    k_all = 0
    for i in range(len(problem.obstacles)):
        if i in cone.relevant or cone.parkable[i]:
            continue
        g = AgentGeometry.obstacle(problem, i)
        park_cells = 0
        for c in bits(g.full):
            m = 1 << c
            if any(g.image(m, k) == m for k in range(len(g.moves))):
                park_cells |= m
        k_i = next((t for t, pos in enumerate(cone.positions[i]) if pos & park_cells), cone.steps)
        k_all = max(k_all, k_i)
    if k_all == 0:
        return None
    return lambda t, K=k_all: min(t, K)


def program_wins(problem: GridProblem, steps: int, program: Term, clock: Clock | None = None) -> bool:
    """Exact check of a program on the game (the engine's own; the solve loop also runs
    the independent verifier). Obstacles the program reads are tracked jointly, the other
    relevant ones are folded into per-step danger, irrelevant ones never collide."""
    from plansynth.grid.programs import variables_of

    cone = influence_cone(problem, steps)
    names = variables_of(program)
    read = tuple(i for i in cone.relevant if f"o{i}x" in names or f"o{i}y" in names)
    for i in range(len(problem.obstacles)):
        if i not in cone.relevant and (f"o{i}x" in names or f"o{i}y" in names):
            read += (i,)  # read but harmless: still tracked, its cells are inputs
    read = tuple(sorted(read))
    full = Arena.build(problem, steps, _with_relevant(cone, read), read, clock, explore=False)
    variables = problem.variables
    f = compile_program(program, variables)
    n_moves = len(problem.robot.moves)
    goal = full.sem.index(problem.robot.goal)
    start = full.sem.index(problem.robot.start)
    oc0 = tuple(full.sem.index(problem.obstacles[i].start) for i in read)
    frontier = {(start, oc0)}
    base = [0] * len(variables)
    pos = {i: 2 + 2 * i for i in range(len(problem.obstacles))}
    for t in range(steps):
        nxt = set()
        for r, oc in frontier:
            env = list(base)
            env[0], env[1] = full.sem.cell(r)
            for j, i in enumerate(read):
                env[pos[i]], env[pos[i] + 1] = full.sem.cell(oc[j])
            for i in range(len(problem.obstacles)):
                if i not in read:
                    env[pos[i]], env[pos[i] + 1] = problem.obstacles[i].start  # unread: value irrelevant
            k = f(*env)
            if not isinstance(k, int) or not 0 <= k < n_moves:
                return False
            if not full.safe_sources(t, oc)[k] >> r & 1:
                return False
            e = full.robot_end(r, k)
            for oc2 in full.successors(oc):
                nxt.add((e, oc2))
        frontier = nxt
        check_clock(clock, "checking the program", f" at step {t}")
    return all(r == goal for r, _ in frontier)


def _with_relevant(cone: Cone, read: tuple[int, ...]) -> Cone:
    from dataclasses import replace

    return replace(cone, relevant=tuple(sorted(set(cone.relevant) | set(read))))

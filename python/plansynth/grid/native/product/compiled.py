"""The product game's safety objective in the compiled core (``crates/plansynth-core/
src/product/``): the configurations, the greatest fixpoint with its ranks, the
learner's rounds, the program check and the obstacles' rank strategy, behind the same
questions the pure-Python reference (:mod:`.space`, :mod:`.fixpoints`, :mod:`.program`)
answers. A property test compares the two on random problems.

The core holds the game; Python sees configuration ids, robot cell indices and, for a
program, its flat ops (:func:`~plansynth.grid.native.check.program_ops`). Every call
takes the time and memory that are left and raises
:class:`~plansynth.budget.BudgetExhausted` past them.
"""

from __future__ import annotations

from plansynth.budget import Clock
from plansynth.grid.native.bitgrid import AgentGeometry, cell_mask, wall_mask
from plansynth.grid.native.check import ops_program, program_ops
from plansynth.grid.objective import CollisionRule, Schedule
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import App, Const, Term, Var

__all__ = ["available", "CompiledSafety", "LEARN_STEPS"]

#: The steps of one round of the core's learner, whose seconds it reports.
LEARN_STEPS = ("labels", "conditions", "tree", "closure")


def available() -> bool:
    from plansynth.grid.native import fast

    return fast.available() and hasattr(fast._core, "ProductGame")


def _budget(clock: Clock | None, memory_mb: int | None) -> dict:
    left = None if clock is None else clock.remaining()
    return {
        "seconds": None if left is None or left == float("inf") else max(0.0, left),
        "max_bytes": None if memory_mb is None else int(memory_mb) << 20,
    }


class CompiledSafety:
    """A safety game explored and solved in the core."""

    def __init__(self, problem: GridProblem, clock: Clock | None, memory_mb: int | None) -> None:
        from plansynth.grid.native import fast

        self.problem = problem
        self.clock, self.memory_mb = clock, memory_mb
        w = problem.width
        n = w * problem.height
        nbytes = (n + 7) // 8

        def b(m: int) -> bytes:
            return m.to_bytes(nbytes, "little")

        robot = AgentGeometry.robot(problem)
        self.geometry = robot
        walls = wall_mask(problem)
        rows = [
            (b(robot.valid[k]), b(robot.free[k]), m.to[1] * w + m.to[0], [o[1] * w + o[0] for o in m.offsets()])
            for k, m in enumerate(problem.robot.moves)
        ]
        obstacles = []
        for o in problem.obstacles:
            blocked = walls
            for c in o.keep_out:
                blocked |= cell_mask(problem, c)
            moves = [(m.to, list(m.offsets())) for m in o.moves]
            obstacles.append(
                (
                    o.size[0],
                    o.size[1],
                    moves,
                    o.period,
                    o.schedule is Schedule.FIXED,
                    o.initial_phase,
                    o.glitches,
                    b(blocked),
                    o.start[1] * w + o.start[0],
                )
            )
        start = problem.robot.start[1] * w + problem.robot.start[0]
        standing = robot.full & ~walls
        self.core = fast._core.ProductGame(
            w,
            problem.height,
            rows,
            obstacles,
            problem.collision is CollisionRule.POSITION,
            start,
            b(standing),
            **_budget(clock, memory_mb),
        )
        self.start = (0, start)
        self.won: bool | None = None

    @property
    def n_configs(self) -> int:
        return self.core.n_configs()

    def solve(self) -> bool:
        self.won = self.core.solve_safety(**_budget(self.clock, self.memory_mb))
        return self.won

    def rounds(self) -> int:
        return self.core.rounds()

    def winning(self, oc: int) -> int:
        return int.from_bytes(self.core.winning(oc), "little")

    def config_key(self, oc: int) -> tuple:
        """Configuration ``oc`` as the reference's key: per obstacle ((x, y), wait
        counter, glitches left)."""
        w = self.problem.width
        return tuple(((c % w, c // w), p, g) for c, p, g in self.core.config(oc))

    # -- programs ----------------------------------------------------------------------
    def closure(self, program: Term, grow: bool = False) -> tuple[int, list[tuple[int, int]], int]:
        ops = program_ops(program, self.problem.variables)
        return self.core.closure(ops, len(self.problem.variables), grow, **_budget(self.clock, self.memory_mb))

    def learn_round(
        self, cond_depth: int, max_nodes: int, enum_states: int, tree_states: int | None = None
    ) -> tuple[bool, int, int, Term, dict[str, float]]:
        """One round of the core's learner: (closed, sample size, states reached, the
        program, seconds of its steps by name). ``tree_states``: on a larger sample the
        tree is grown on a part of about this many states and refined on the whole."""
        closed, sample, reached, terms, conds, nodes, seconds = self.core.learn_round(
            cond_depth,
            self.problem.max_constant,
            max_nodes,
            enum_states,
            **_budget(self.clock, self.memory_mb),
            tree_states=tree_states,
        )
        steps = dict(zip(LEARN_STEPS, (round(s, 4) for s in seconds), strict=True))
        return closed, sample, reached, _tree(terms, conds, nodes, self.problem.variables), steps

    def reached_sets(self) -> dict[tuple, int]:
        """The last closure's states as the verifier's invariant: configuration key ->
        robot-cell mask."""
        return {self.config_key(oc): int.from_bytes(m, "little") for oc, m in self.core.reached_sets()}

    def certify(self) -> tuple[bool, int, str]:
        return self.core.certify_safety(**_budget(self.clock, self.memory_mb))


class CompiledCheck:
    """:class:`~.program.ProductCheck`'s interface (``check``, ``check_ops``,
    ``variables``, ``n_moves``) on the compiled game, for the simplifier."""

    def __init__(self, game: CompiledSafety) -> None:
        self.game = game
        self.variables = game.problem.variables
        self.n_moves = len(game.problem.robot.moves)
        self.checks = 0

    def check(self, program: Term):
        self.checks += 1
        _, bad, _ = self.game.closure(program)
        return bad[0] if bad else None

    def check_ops(self, ops):
        return self.check(ops_program(ops, self.variables))


def _tree(terms, conds, nodes, variables) -> Term:
    """The learner's tree as a term (pre-order nodes over conditions over terms)."""
    built_terms: list[Term] = []
    for kind, a, b_, _ in terms:
        if kind == 0:
            built_terms.append(Const(a))
        elif kind == 1:
            built_terms.append(Var(variables[a]))
        else:
            built_terms.append(App("+" if kind == 2 else "-", (built_terms[a], built_terms[b_])))
    built: list[Term] = []
    for op, a, b_, _ in conds:
        if op == 0:
            built.append(App("<=", (built_terms[a], built_terms[b_])))
        elif op == 1:
            built.append(App("=", (built_terms[a], built_terms[b_])))
        elif op == 2:
            built.append(App("not", (built[a],)))
        else:
            built.append(App("and" if op == 3 else "or", (built[a], built[b_])))
    it = iter(nodes)

    def grow() -> Term:
        kind, x = next(it)
        if kind == 0:
            return Const(x)
        then, other = grow(), grow()
        return then if then == other else App("ite", (built[x], then, other))

    return grow()

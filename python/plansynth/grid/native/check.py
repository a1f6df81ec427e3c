"""The program check on the game graph, and simplification against it.

After backward induction (:meth:`Arena.solve_game`) every state of the
*winning-forward graph* (pairs (t, joint state) reached from the start with moves that
win the time-dependent game) is winning. A program therefore wins the bounded game
(Chasins & Newcomb, SYNT 2016, Section 3.1: the goal at exactly l steps, no collision,
whatever the obstacles do) iff, in every pair it reaches from the start, it plays one
of that pair's winning moves. :class:`GameGraph` is that graph made explicit, with a
pure-Python check (the reference) and the compiled one of ``crates/plansynth-core``
(``game.rs``) behind the same method; a property test compares them.

:func:`simplify` is the answer-first engine's cheap improvement: replace a subtree by
a move or by one of its branches while the checker still accepts the program.

>>> from plansynth.budget import Budget
>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.native.arena import Arena
>>> from plansynth.grid.native.cone import influence_cone
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [3, 1],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}})
>>> a = Arena.build(p, 2, influence_cone(p, 2), ())
>>> a.solve_game()
True
>>> g = GameGraph.from_arena(a)
>>> g.check(parse_program("1")) is None, g.check(parse_program("0"))
(True, 0)
>>> print(simplify(parse_program("(ite (<= rx 0) 1 1)"), g))
1
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.cone import influence_cone, with_relevant
from plansynth.grid.native.limits import check_clock
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import App, Const, Term, Var, compile_program, variables_of

_OPS = {"+": 2, "-": 3, "<=": 4, "=": 5, "not": 6, "and": 7, "or": 8, "ite": 9}


def program_ops(program: Term, variables: tuple[str, ...]) -> list[tuple[int, int, int, int]]:
    """The program as flat nodes ``(op, a, b, c)``, children first, root last (the
    compiled checker's input): op 0 constant a, 1 variable a, 2 ``+``, 3 ``-``, 4 ``<=``,
    5 ``=``, 6 ``not``, 7 ``and``, 8 ``or``, 9 ``ite`` over node indices."""
    index = {v: i for i, v in enumerate(variables)}
    out: list[tuple[int, int, int, int]] = []
    memo: dict[int, int] = {}  # by identity: hashing a deep frozen term is costly

    def go(t: Term) -> int:
        got = memo.get(id(t))
        if got is not None:
            return got
        if isinstance(t, Const):
            row = (0, t.value, 0, 0)
        elif isinstance(t, Var):
            row = (1, index[t.name], 0, 0)
        else:
            kids = [go(a) for a in t.args] + [0, 0]
            row = (_OPS[t.op], kids[0], kids[1], kids[2])
        out.append(row)
        memo[id(t)] = len(out) - 1
        return len(out) - 1

    go(program)
    return out


@dataclass
class GameGraph:
    """The time-expanded winning-forward graph; pair 0 is the start.

    ``state_of[p]`` indexes ``inputs`` (the controller's inputs of the joint state),
    ``win[p]`` is the bitmask of winning moves, and the successors of pair p under move
    k are ``succ[off[p * n_moves + k]:off[p * n_moves + k + 1]]`` (one per obstacle reply;
    none in the last step, where a winning move ends on the goal).
    """

    n_moves: int
    variables: tuple[str, ...]
    state_of: list[int]
    win: list[int]
    off: list[int]
    succ: list[int]
    inputs: list[tuple[int, ...]]
    use_rust: bool | None = None
    _compiled: object = field(default=None, repr=False)
    _sizes: tuple[int, int] | None = field(default=None, repr=False)
    checks: int = 0

    @classmethod
    def from_arena(cls, arena: Arena, clock: Clock | None = None, use_rust: bool | None = None) -> GameGraph:
        """Explore the pairs reachable from the start with winning moves (needs
        :meth:`Arena.solve_game` first): in the compiled core when available
        (``game.rs``, ``build_game_graph``), else :meth:`from_arena_reference`; both
        number pairs and states the same way."""
        if use_rust is not False:
            from plansynth.grid.native import fast

            if fast.available() and hasattr(fast._core, "build_game_graph"):
                return cls._from_arena_compiled(arena, clock, fast._core)
        return cls.from_arena_reference(arena, clock, use_rust)

    @classmethod
    def _from_arena_compiled(cls, arena: Arena, clock: Clock | None, core) -> GameGraph:
        from plansynth.grid.native.stationary import winning_forward

        n_moves = len(arena.robot.moves)
        fwd = winning_forward(arena, clock)
        config_id: dict[tuple[int, ...], int] = {}
        configs: list[list[int]] = []
        successors: list[list[int]] = []

        def cid(oc: tuple[int, ...]) -> int:
            i = config_id.get(oc)
            if i is None:
                i = config_id[oc] = len(configs)
                configs.append(list(oc))
                successors.append([])
            return i

        cid(next(iter(fwd[0])))
        n_cells = arena.problem.width * arena.problem.height
        nbytes = (n_cells + 7) // 8
        cells = 0
        layers = []
        expanded: set[int] = set()
        for t in range(arena.steps):
            for oc, rmask in fwd[t].items():
                c = cid(oc)
                cells |= rmask
                wm = arena.winning_moves(t, oc)
                layers.append((t, c, [m.to_bytes(nbytes, "little") for m in wm]))
                if c not in expanded and t + 1 < arena.steps:
                    expanded.add(c)
                    successors[c] = [cid(oc2) for oc2 in arena.successors(oc)]
            check_clock(clock, "building the game graph for program checks", f" at step {t}")
        robot_end = [0] * (n_cells * n_moves)
        for r in range(n_cells):
            for k in range(n_moves):
                robot_end[r * n_moves + k] = arena.robot_end(r, k) if cells >> r & 1 else r
        start = arena.sem.index(arena.problem.robot.start)
        compiled = core.build_game_graph(
            n_moves, arena.steps, arena.problem.width, start, configs, successors, robot_end, layers
        )
        g = cls(n_moves, arena.variables(), [], [], [], [], [], None)
        g._compiled = compiled  # the arrays stay in the core until asked for (materialize)
        g._sizes = compiled.sizes()
        return g

    def materialize(self) -> GameGraph:
        """Fetch the arrays of a graph built in the compiled core (for the reference
        check and for comparing the two builds)."""
        if self._sizes is not None and self._compiled is not None:
            state_of, win, off, succ, inputs = self._compiled.arrays()
            self.state_of, self.win, self.off, self.succ = state_of, win, off, succ
            self.inputs = [tuple(x) for x in inputs]
            self._sizes = None
        return self

    @classmethod
    def from_arena_reference(cls, arena: Arena, clock: Clock | None = None, use_rust: bool | None = None) -> GameGraph:
        """:meth:`from_arena` in pure Python (the reference of ``build_game_graph``)."""
        n_moves = len(arena.robot.moves)
        steps = arena.steps
        oc0 = next(iter(arena.layers[0]))
        r0 = arena.sem.index(arena.problem.robot.start)
        pair_id: dict[tuple[int, int, tuple[int, ...]], int] = {(0, r0, oc0): 0}
        order: list[tuple[int, int, tuple[int, ...]]] = [(0, r0, oc0)]
        state_id: dict[tuple[int, tuple[int, ...]], int] = {}
        state_of: list[int] = []
        inputs: list[tuple[int, ...]] = []
        win: list[int] = []
        off: list[int] = [0]
        succ: list[int] = []
        wm_cache: dict[tuple[int, tuple[int, ...]], tuple[int, ...]] = {}
        ends: dict[tuple[int, int, tuple[int, ...]], list[int]] = {}
        head = 0
        while head < len(order):
            t, r, oc = order[head]
            head += 1
            s = state_id.get((r, oc))
            if s is None:
                s = state_id[(r, oc)] = len(inputs)
                inputs.append(arena.inputs(r, oc))
            state_of.append(s)
            wm = wm_cache.get((t, oc))
            if wm is None:
                wm = wm_cache[(t, oc)] = arena.winning_moves(t, oc)
            w = 0
            for k in range(n_moves):
                if wm[k] >> r & 1:
                    w |= 1 << k
                    if t + 1 < steps:
                        e = arena.robot_end(r, k)
                        # every (r, k) of this configuration ending in e has the same replies
                        ids = ends.get((t, e, oc))
                        if ids is None:
                            ids = []
                            for oc2 in arena.successors(oc):
                                key = (t + 1, e, oc2)
                                q = pair_id.get(key)
                                if q is None:
                                    q = pair_id[key] = len(order)
                                    order.append(key)
                                ids.append(q)
                            ends[(t, e, oc)] = ids
                        succ.extend(ids)
                off.append(len(succ))
            win.append(w)
            if head % 4096 == 0:
                check_clock(clock, "building the game graph for program checks")
        return cls(n_moves, arena.variables(), state_of, win, off, succ, inputs, use_rust)

    @property
    def n_pairs(self) -> int:
        return self._sizes[0] if self._sizes is not None else len(self.state_of)

    @property
    def n_states(self) -> int:
        return self._sizes[1] if self._sizes is not None else len(self.inputs)

    def check(self, program: Term) -> int | None:
        """None when ``program`` wins; else the first pair (breadth-first) where it
        plays a move that does not win. The compiled core when available."""
        return self.check_ops(program_ops(program, self.variables))

    def check_ops(self, ops: list[tuple[int, int, int, int]]) -> int | None:
        """:meth:`check` of a program given as :func:`program_ops` rows."""
        self.checks += 1
        core = self._core()
        if core is not None:
            return core.check(ops)
        return self.check_reference(ops_program(ops, self.variables))

    def check_reference(self, program: Term) -> int | None:
        """:meth:`check` in pure Python (the reference of ``game.rs``)."""
        self.materialize()
        f = compile_program(program, self.variables)
        cache: dict[int, object] = {}
        seen = {0}
        queue = [0]
        head = 0
        n = self.n_moves
        while head < len(queue):
            p = queue[head]
            head += 1
            s = self.state_of[p]
            k = cache.get(s)
            if k is None:
                k = cache[s] = f(*self.inputs[s])
            if not isinstance(k, int) or isinstance(k, bool) or not 0 <= k < n or not self.win[p] >> k & 1:
                return p
            i = p * n + k
            for q in self.succ[self.off[i] : self.off[i + 1]]:
                if q not in seen:
                    seen.add(q)
                    queue.append(q)
        return None

    def _core(self):
        if self.use_rust is False:
            return None
        if self._compiled is None:
            from plansynth.grid.native import fast

            if not fast.available() or not hasattr(fast._core, "GameGraph"):
                self.use_rust = False
                return None
            self._compiled = fast._core.GameGraph(
                self.n_moves, self.state_of, self.win, self.off, self.succ, [list(x) for x in self.inputs]
            )
        return self._compiled


class ArenaCheck:
    """The program check of :class:`GameGraph`, run on the compiled game itself
    (``arena/program.rs``, ``Arena::check_program``) without building the graph: the program is
    followed from the start breadth-first, and each pair it reaches must play a winning
    move there. On large games the graph has millions of pairs times moves times
    obstacle replies, while a program reaches only the pairs of its own moves.
    :class:`GameGraph` (and its :meth:`GameGraph.check_reference`) is the reference;
    a property test compares the two.
    """

    def __init__(self, arena: Arena, clock: Clock | None = None) -> None:
        from plansynth.grid.native.stationary import core_forward

        self.arena, self.clock = arena, clock
        self.core = arena._core
        self.n_moves = len(arena.robot.moves)
        self.variables = arena.variables()
        core_forward(arena, clock)  # the pair and state counts below
        self.n_pairs, self.n_states = self.core.forward_sizes()
        self.checks = 0

    def check(self, program: Term):
        """None when ``program`` wins; else the first pair ``(t, robot cell, obstacle
        cells)`` (breadth-first) where it plays a move that does not win."""
        return self.check_ops(program_ops(program, self.variables))

    def check_ops(self, ops: list[tuple[int, int, int, int]]):
        self.checks += 1
        left = None if self.clock is None else self.clock.remaining()
        if left is not None and left <= 0:
            raise BudgetExhausted("checking programs on the game", "time", "checking programs on the game: out of time")
        # the compiled check raises BudgetExhausted past its seconds
        got = self.core.check(ops, self.arena.problem.width, None if left is None or left == float("inf") else left)
        return None if got is None else (got[0], got[1], tuple(got[2]))


def program_checker(arena: Arena, clock: Clock | None = None, use_rust: bool | None = None):
    """The program check for ``arena`` (solved and won): :class:`ArenaCheck` on a
    compiled game, else :meth:`GameGraph.from_arena`."""
    if arena._core is not None and use_rust is not False:
        return ArenaCheck(arena, clock)
    return GameGraph.from_arena(arena, clock, use_rust)


def ops_program(ops: list[tuple[int, int, int, int]], variables: tuple[str, ...]) -> Term:
    """The inverse of :func:`program_ops`: the term of the root (the last node)."""
    names = {0: None, 1: None, 2: "+", 3: "-", 4: "<=", 5: "=", 6: "not", 7: "and", 8: "or", 9: "ite"}
    arity = {2: 2, 3: 2, 4: 2, 5: 2, 6: 1, 7: 2, 8: 2, 9: 3}
    built: list[Term] = []
    for op, a, b, c in ops:
        if op == 0:
            built.append(Const(a))
        elif op == 1:
            built.append(Var(variables[a]))
        else:
            built.append(App(names[op], tuple(built[x] for x in (a, b, c)[: arity[op]])))
    return built[-1]


def simplify(program: Term, graph: GameGraph | ArenaCheck, deadline: float | None = None) -> Term:
    """Shrink ``program`` top-down while the checker accepts it: each ``ite`` node is
    replaced by one of its branches or by a move when the whole program still wins.
    Stops at ``deadline`` (a ``time.perf_counter()`` value), keeping the best so far.

    Works on the flat nodes of :func:`program_ops` (children first): replacing node i
    by its child j copies row j into row i, and a move is a constant row, so each
    candidate costs one list copy and one check.
    """
    ops = program_ops(program, graph.variables)
    moves = range(graph.n_moves)
    todo = [len(ops) - 1]
    while todo:
        i = todo.pop(0)
        if ops[i][0] != 9:
            continue
        if deadline is not None and time.perf_counter() > deadline:
            break
        _, cond, then, other = ops[i]
        cands = [ops[then], ops[other]] + [(0, k, 0, 0) for k in moves if (0, k, 0, 0) not in (ops[then], ops[other])]
        for row in cands:
            trial = list(ops)
            trial[i] = row
            if graph.check_ops(trial) is None:
                ops = trial
                todo.insert(0, i)  # the replacement may simplify further
                break
        else:
            todo.extend([then, other])
    return ops_program(_compact(ops), graph.variables)


def _compact(ops: list[tuple[int, int, int, int]]) -> list[tuple[int, int, int, int]]:
    """Drop the nodes the root no longer reaches (renumbered, children first)."""
    keep: dict[int, int] = {}
    out: list[tuple[int, int, int, int]] = []
    arity = {0: 0, 1: 0, 2: 2, 3: 2, 4: 2, 5: 2, 6: 1, 7: 2, 8: 2, 9: 3}

    def go(i: int) -> int:
        if i in keep:
            return keep[i]
        op, a, b, c = ops[i]
        kids = [go(x) for x in (a, b, c)[: arity[op]]] + [0, 0, 0]
        row = (
            (op, a, 0, 0)
            if arity[op] == 0
            else (op, kids[0], kids[1] if arity[op] > 1 else 0, kids[2] if arity[op] > 2 else 0)
        )
        out.append(row)
        keep[i] = len(out) - 1
        return keep[i]

    go(len(ops) - 1)
    return out


__all__ = ["ArenaCheck", "GameGraph", "program_checker", "program_ops", "ops_program", "simplify"]


def program_wins(problem: GridProblem, steps: int, program: Term, clock: Clock | None = None) -> bool:
    """Exact check of a program on the game (the engine's own; the solve loop also runs
    the independent verifier). Obstacles the program reads are tracked jointly, the other
    relevant ones are folded into per-step danger, irrelevant ones never collide."""
    cone = influence_cone(problem, steps)
    names = variables_of(program)
    read = tuple(i for i in cone.relevant if f"o{i}x" in names or f"o{i}y" in names)
    for i in range(len(problem.obstacles)):
        if i not in cone.relevant and (f"o{i}x" in names or f"o{i}y" in names):
            read += (i,)  # read but harmless: still tracked, its cells are inputs
    read = tuple(sorted(read))
    full = Arena.build(problem, steps, with_relevant(cone, read), read, clock, explore=False)
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

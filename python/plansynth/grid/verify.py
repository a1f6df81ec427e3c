"""The independent verifier: does a controller win a grid problem at exactly l steps?

A controller wins for path length l if, for every behaviour of the obstacles, the robot
never collides in steps 0..l-1 and stands on the goal after step l-1 (spec:
grid-problem.md, Semantics; Chasins & Newcomb, SYNT 2016, Section 3.1). This module
decides that exactly, using only :mod:`plansynth.grid.semantics` (the single definition
of a step) and :mod:`plansynth.grid.programs` (evaluation). Every program a solver
reports is checked here before it is called realizable.

Enumerating the obstacles' joint choices is hopeless on the paper's families (2^50 per
step for obstacles-50), so the verifier uses three reductions that preserve exactness.
There is no alternation to preserve: the program is fixed, so the question is whether
*some* obstacle behaviour makes the robot lose.

1. **Only read obstacles steer the robot.** The robot's next move is a function of the
   inputs the program reads (:func:`~plansynth.grid.programs.variables_of`). The robot
   and the obstacles the program reads are explored jointly, depth first, with every
   abstract state already shown safe remembered.
2. **Unread obstacles are independent of everything.** An obstacle the program never
   reads cannot influence the robot, nor can the other obstacles influence it. So it
   can collide at step t iff some cell it can occupy at time t (its t-step reachable
   set) has a move whose swept cells meet the robot's swept cells at step t. Those sets
   are computed once per obstacle, and their swept cells are merged into one "danger"
   bitmask per step.
3. **Read obstacles are tracked as sets, split only where the program looks.** Given
   the robot's moves so far, the read obstacles' possible cells form a product of one
   set per obstacle (they move independently, and the image of a product under their
   moves is a product). The program's choice is evaluated on the sets with interval
   arithmetic; where a comparison is undecided, the sets are split on it until the
   choice is constant on each part. On a part, a read obstacle can collide iff one of
   its cells has a move meeting the robot's swept cells, as in 2. A program that
   compares against a threshold (``(<= o0y 3)``) splits a set in two; only relational
   comparisons between obstacles (``(<= o0y o1y)``) approach explicit enumeration.

When the controller loses, the verdict carries a concrete :class:`Counterexample`: the
obstacles' joint moves, the states visited and the program's choices, which replay
through :func:`~plansynth.grid.semantics.step` to the loss it describes.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [4, 1],
...     "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}]})
>>> verify(p, parse_program("1"), 3).wins
False
>>> print(verify(p, parse_program("1"), 3).counterexample.reason)
collision at step 1 in cell (2, 0) with obstacle 0
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.programs import (
    App,
    Const,
    ProgramSyntaxError,
    Term,
    Var,
    check_program,
    evaluate,
    variables_of,
)
from plansynth.grid.semantics import CompiledSemantics, State, initial_state, obstacle_move, robot_move, step


@dataclass(frozen=True)
class Counterexample:
    """A run on which the controller loses.

    ``states[t]`` is the state at the start of step t (``states[0]`` the initial one,
    the last one the state after the losing step); ``robot_moves[t]`` and
    ``obstacle_moves[t]`` are the moves taken at step t. ``reason`` says why it loses.
    """

    obstacle_moves: tuple[tuple[int, ...], ...]
    states: tuple[State, ...]
    robot_moves: tuple[int, ...]
    reason: str


@dataclass(frozen=True)
class Verdict:
    """The verifier's answer for one program and one path length.

    ``wins`` is exact (there is no "unknown": the verifier is complete). When it is
    False, ``counterexample`` shows a losing run. ``states_explored`` counts the
    (t, robot, read obstacles) nodes expanded.
    """

    wins: bool
    steps: int
    counterexample: Counterexample | None
    states_explored: int
    seconds: float


def read_obstacles(program: Term, n_obstacles: int) -> tuple[int, ...]:
    """Indices of the obstacles whose coordinates ``program`` reads, in order.

    >>> from plansynth.grid.programs import parse_program
    >>> read_obstacles(parse_program("(ite (<= o2y rx) 0 1)"), 3)
    (2,)
    """
    names = variables_of(program)
    return tuple(i for i in range(n_obstacles) if f"o{i}x" in names or f"o{i}y" in names)


def check_controller(problem: GridProblem, program: Term) -> None:
    """Raise :class:`ProgramSyntaxError` unless ``program`` is a controller of ``problem``'s
    grammar: a Start term over its inputs whose move numbers name robot moves."""
    check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)


def verify(problem: GridProblem, program: Term, steps: int) -> Verdict:
    """Decide exactly whether ``program`` wins ``problem`` at path length ``steps``.

    Raises :class:`~plansynth.grid.programs.ProgramSyntaxError` when the program is not
    a controller of the problem's grammar (for example a move number with no move).
    """
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    check_controller(problem, program)
    t0 = time.perf_counter()
    search = _Search(problem, program, steps)
    loss = search.run()
    cex = None if loss is None else search.counterexample(loss)
    return Verdict(loss is None, steps, cex, search.explored, time.perf_counter() - t0)


# -- the search ------------------------------------------------------------------------

#: A set of cells (indices ``y * width + x``) one read obstacle may occupy.
Cells = frozenset[int]
#: An abstract state below time ``steps``: (robot index, one cell set per read obstacle).
Box = tuple[int, tuple[Cells, ...]]


@dataclass(frozen=True)
class _Loss:
    """A losing path of abstract states.

    ``boxes[t]`` is the abstract state in which the robot took ``robot_moves[t]`` (after
    splitting, so the program's choice is constant on it); for ``kind == "goal"`` there
    is one more box, the state after the last step. ``kind`` is "wall", "unread",
    "read" (read obstacle ``obstacle`` can collide at the last step) or "goal".
    """

    kind: str
    robot_moves: tuple[int, ...]
    boxes: tuple[Box, ...]
    obstacle: int = -1


_UNDECIDED = None


class _Search:
    """Depth-first exploration of (t, robot cell, read obstacles' cell sets).

    Given the robot's history, the read obstacles' possible positions form a product
    set: the obstacles move independently, and the image of a product set under their
    moves is again one. The only thing that breaks products is the program's choice,
    which depends on the read coordinates; so each set is evaluated with intervals and
    split on an undecided comparison until the choice is constant on every part
    (reduction 3 of the module docstring; all-singleton sets are plain enumeration).
    On each part, a read obstacle can collide iff one of its cells has a move sweeping
    the robot's swept cells, exactly as for unread obstacles.
    """

    def __init__(self, problem: GridProblem, program: Term, steps: int) -> None:
        self.problem = problem
        self.program = program
        self.steps = steps
        self.sem = CompiledSemantics(problem)
        self.width = problem.width
        self.goal = self.sem.index(problem.robot.goal)
        self.read = read_obstacles(program, len(problem.obstacles))
        self.unread = tuple(i for i in range(len(problem.obstacles)) if i not in self.read)
        self.slot = {i: j for j, i in enumerate(self.read)}
        self.explored = 0
        self.reach, self.danger = self._unread_reach()
        # Per read obstacle: cell set -> (successor set, every cell it can sweep).
        self._image: list[dict[Cells, tuple[Cells, int]]] = [{} for _ in self.read]
        self._bounds: dict[Cells, tuple[int, int, int, int]] = {}
        # (robot, sets) -> parts on which the program's choice is constant, with it.
        self._parts: dict[tuple[int, tuple[Cells, ...]], tuple[tuple[tuple[Cells, ...], int], ...]] = {}
        self.safe: set[tuple[int, int, tuple[Cells, ...]]] = set()

    # -- unread obstacles ------------------------------------------------------------

    def _unread_reach(self) -> tuple[list[list[Cells]], list[int]]:
        """Per unread obstacle, the cells it can occupy at each time 0..steps-1, and per
        step the union of every cell some unread obstacle can sweep then."""
        danger = [0] * self.steps
        reach: list[list[Cells]] = []
        for i in self.unread:
            succ = self.sem.obstacle_successors[i]
            # A set of cells determines its successor set and its swept cells, and the
            # sequence of sets is often periodic (an up/down obstacle alternates), so
            # each distinct set is expanded once.
            expanded: dict[Cells, tuple[Cells, int]] = {}
            cur = frozenset((self.sem.index(self.problem.obstacles[i].start),))
            sets = []
            for t in range(self.steps):
                sets.append(cur)
                if cur not in expanded:
                    expanded[cur] = _image(succ, cur)
                cur, mask = expanded[cur]
                danger[t] |= mask
            reach.append(sets)
        return reach, danger

    # -- read obstacles: images, bounds, and the program's choice on a product set ----

    def image(self, j: int, cells: Cells) -> tuple[Cells, int]:
        """Successor set and swept-cells mask of read obstacle number ``j`` (slot) on ``cells``."""
        cache = self._image[j]
        if cells not in cache:
            cache[cells] = _image(self.sem.obstacle_successors[self.read[j]], cells)
        return cache[cells]

    def bounds(self, cells: Cells) -> tuple[int, int, int, int]:
        """(min x, max x, min y, max y) over ``cells``."""
        b = self._bounds.get(cells)
        if b is None:
            w = self.width
            xs = [c % w for c in cells]
            ys = [c // w for c in cells]
            b = self._bounds[cells] = (min(xs), max(xs), min(ys), max(ys))
        return b

    def intervals(self, r: int, sets: tuple[Cells, ...]) -> dict[str, tuple[int, int]]:
        w = self.width
        env = {"rx": (r % w, r % w), "ry": (r // w, r // w)}
        for j, i in enumerate(self.read):
            x0, x1, y0, y1 = self.bounds(sets[j])
            env[f"o{i}x"] = (x0, x1)
            env[f"o{i}y"] = (y0, y1)
        return env

    def parts(self, r: int, sets: tuple[Cells, ...]) -> tuple[tuple[tuple[Cells, ...], int], ...]:
        """Split ``sets`` into parts on which the program's move is constant: (part, move)."""
        key = (r, sets)
        cached = self._parts.get(key)
        if cached is not None:
            return cached
        out: list[tuple[tuple[Cells, ...], int]] = []
        stack: list[tuple[tuple[Cells, ...], dict[int, bool]]] = [(sets, {})]
        while stack:
            part, known = stack.pop()
            env = self.intervals(r, part)
            found = _choose(self.program, env, known)
            if isinstance(found, int):
                out.append((part, found))
            else:
                stack.extend(self._split(found, r, part, env, known))
        result = tuple(out)
        self._parts[key] = result
        return result

    def _split(
        self, atom: App, r: int, part: tuple[Cells, ...], env: dict[str, tuple[int, int]], known: dict[int, bool]
    ) -> list[tuple[tuple[Cells, ...], dict[int, bool]]]:
        """Split ``part`` so that ``atom`` (undecided on its intervals) is decided on each piece."""
        names = variables_of(atom)
        # Read obstacles whose coordinates in the atom are not yet single values.
        loose = []
        for j, i in enumerate(self.read):
            coords = [c for c in "xy" if f"o{i}{c}" in names]
            if any(env[f"o{i}{c}"][0] != env[f"o{i}{c}"][1] for c in coords):
                loose.append((j, i, coords))
        if len(loose) == 1:
            # The atom reads one undetermined obstacle: evaluate it on each of its cells.
            j, i, _ = loose[0]
            w = self.width
            point = {v: lo for v, (lo, hi) in env.items() if lo == hi}
            by_value: dict[bool, set[int]] = {True: set(), False: set()}
            for c in part[j]:
                point[f"o{i}x"], point[f"o{i}y"] = c % w, c // w
                by_value[bool(evaluate(atom, point))].add(c)
            return [
                (part[:j] + (frozenset(cells),) + part[j + 1 :], {**known, id(atom): value})
                for value, cells in by_value.items()
                if cells
            ]
        # Several undetermined obstacles: fix the read coordinates of the one with the
        # fewest distinct values; the atom then reads one fewer undetermined obstacle.
        w = self.width

        def key_of(c: int, coords: list[str]) -> tuple[int, ...]:
            return tuple(c % w if k == "x" else c // w for k in coords)

        j, i, coords = min(loose, key=lambda l: len({key_of(c, l[2]) for c in part[l[0]]}))
        groups: dict[tuple[int, ...], set[int]] = {}
        for c in part[j]:
            groups.setdefault(key_of(c, coords), set()).add(c)
        return [(part[:j] + (frozenset(g),) + part[j + 1 :], known) for g in groups.values()]

    # -- exploration -----------------------------------------------------------------

    def run(self) -> _Loss | None:
        r0 = self.sem.index(self.problem.robot.start)
        s0 = tuple(frozenset((self.sem.index(self.problem.obstacles[i].start),)) for i in self.read)
        limit = sys.getrecursionlimit()
        if limit < self.steps + 200:
            sys.setrecursionlimit(self.steps + 200)
        try:
            return self._explore(0, r0, s0)
        finally:
            sys.setrecursionlimit(limit)

    def _explore(self, t: int, r: int, sets: tuple[Cells, ...]) -> _Loss | None:
        """None if the controller wins from every state in (t, r, sets); else a losing path."""
        if t == self.steps:
            return None if r == self.goal else _Loss("goal", (), ((r, sets),))
        key = (t, r, sets)
        if key in self.safe:
            return None
        for part, k in self.parts(r, sets):
            self.explored += 1
            here = ((r, part),)
            r_end, r_mask = self.sem.robot[r][k]
            if r_mask & self.sem.walls:
                return _Loss("wall", (k,), here)
            if r_mask & self.danger[t]:
                return _Loss("unread", (k,), here)
            nxt = []
            for j, cells in enumerate(part):
                succ, swept = self.image(j, cells)
                if swept & r_mask:
                    return _Loss("read", (k,), here, j)
                nxt.append(succ)
            sub = self._explore(t + 1, r_end, tuple(nxt))
            if sub is not None:
                return _Loss(sub.kind, (k, *sub.robot_moves), here + sub.boxes, sub.obstacle)
        self.safe.add(key)
        return None

    # -- counterexamples -------------------------------------------------------------

    def counterexample(self, loss: _Loss) -> Counterexample:
        """Turn a losing path of abstract states into a run of all obstacles and replay it."""
        p = self.problem
        n = len(loss.robot_moves)  # steps taken (the last one loses unless kind == "goal")
        joint: list[list[int]] = [[0] * len(p.obstacles) for _ in range(n)]
        last = n - 1
        r_mask = self.sem.robot[loss.boxes[last][0]][loss.robot_moves[last]][1]
        for j, i in enumerate(self.read):
            table = self.sem.obstacle[i]
            if loss.kind == "goal":
                # Any cell of the final set, reached through the sets before it.
                cell, tail = min(loss.boxes[n][1][j]), []
            else:
                final = loss.boxes[last][1][j]
                cell, k = min(final), 0
                if loss.kind == "read" and j == loss.obstacle:
                    cell, k = next((c, k) for c in sorted(final) for k, (_, m) in enumerate(table[c]) if m & r_mask)
                tail = [k]
            n_back = n if loss.kind == "goal" else last
            moves = _walk_back(table, [b[1][j] for b in loss.boxes[:n_back]], cell)
            for s, k in enumerate(moves + tail):
                joint[s][i] = k
        if loss.kind == "unread":
            # Steer one unread obstacle into the robot's swept cells at the last step.
            for u, i in enumerate(self.unread):
                hit = self._unread_hit(u, i, last, r_mask)
                if hit is not None:
                    for s, k in enumerate(hit):
                        joint[s][i] = k
                    break
            else:  # pragma: no cover - the danger mask promised a hit
                raise AssertionError("verifier bug: no unread obstacle realises the danger mask")
        robot_moves = tuple(loss.robot_moves)
        obstacle_moves = tuple(tuple(j) for j in joint)
        states, reason = _replay(p, robot_moves, obstacle_moves, self.steps)
        if reason is None:  # pragma: no cover - would mean the search and step() disagree
            raise AssertionError("verifier bug: the counterexample does not lose when replayed")
        return Counterexample(obstacle_moves, states, robot_moves, reason)

    def _unread_hit(self, u: int, i: int, t: int, r_mask: int) -> list[int] | None:
        """Moves of unread obstacle ``i`` for steps 0..t that sweep ``r_mask`` at step t."""
        table = self.sem.obstacle[i]
        sets = self.reach[u]
        for c in sorted(sets[t]):
            for k, (_, mask) in enumerate(table[c]):
                if mask & r_mask:
                    return _walk_back(table, sets[:t], c) + [k]
        return None


def _image(succ: Sequence[Sequence[tuple[int, int]]], cells: Cells) -> tuple[Cells, int]:
    """The cells reachable in one move from ``cells`` and every cell swept on the way."""
    nxt: set[int] = set()
    mask = 0
    for c in cells:
        for end, swept in succ[c]:
            nxt.add(end)
            mask |= swept
    return frozenset(nxt), mask


def _walk_back(table: Sequence[Sequence[tuple[int, int]]], sets: Sequence[Cells], cell: int) -> list[int]:
    """Moves m_0..m_{T-1} of one obstacle with cell_s in ``sets[s]`` ending in ``cell`` at T.

    Each ``sets[s + 1]`` must lie in the image of ``sets[s]`` (true of the search's sets).
    """
    moves: list[int] = []
    cur = cell
    for s in range(len(sets) - 1, -1, -1):
        prev, k = next((q, k) for q in sorted(sets[s]) for k, (e, _) in enumerate(table[q]) if e == cur)
        moves.append(k)
        cur = prev
    return moves[::-1]


def _choose(program: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> int | App:
    """The program's move if it is the same for every input in the intervals ``env``,
    else an undecided comparison to split on. ``known`` fixes atoms decided by splits."""
    t = program
    while isinstance(t, App):  # (ite B S S)
        cond = t.args[0]
        v = _truth(cond, env, known)
        if v is _UNDECIDED:
            return _undecided_atom(cond, env, known)
        t = t.args[1] if v else t.args[2]
    assert isinstance(t, Const)
    return t.value


def _truth(b: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> bool | None:
    """Kleene three-valued truth of a condition over intervals."""
    assert isinstance(b, App)
    op = b.op
    if op == "not":
        v = _truth(b.args[0], env, known)
        return None if v is None else not v
    if op == "and":
        a = _truth(b.args[0], env, known)
        if a is False:
            return False
        c = _truth(b.args[1], env, known)
        if c is False:
            return False
        return True if (a and c) else None
    if op == "or":
        a = _truth(b.args[0], env, known)
        if a is True:
            return True
        c = _truth(b.args[1], env, known)
        if c is True:
            return True
        return False if (a is False and c is False) else None
    if id(b) in known:
        return known[id(b)]
    lo1, hi1 = _interval(b.args[0], env)
    lo2, hi2 = _interval(b.args[1], env)
    if op == "<=":
        if hi1 <= lo2:
            return True
        if lo1 > hi2:
            return False
        return None
    # "="
    if lo1 == hi1 == lo2 == hi2:
        return True
    if hi1 < lo2 or hi2 < lo1:
        return False
    return None


def _undecided_atom(b: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> App:
    """A comparison inside the undecided condition ``b`` that is itself undecided."""
    assert isinstance(b, App)
    if b.op in ("not", "and", "or"):
        for a in b.args:
            if _truth(a, env, known) is _UNDECIDED:
                return _undecided_atom(a, env, known)
        raise AssertionError("an undecided condition has an undecided part")  # pragma: no cover
    return b


def _interval(t: Term, env: dict[str, tuple[int, int]]) -> tuple[int, int]:
    if isinstance(t, Const):
        return t.value, t.value
    if isinstance(t, Var):
        return env[t.name]
    a0, a1 = _interval(t.args[0], env)
    b0, b1 = _interval(t.args[1], env)
    if t.op == "+":
        return a0 + b0, a1 + b1
    return a0 - b1, a1 - b0  # "-"


def _replay(
    problem: GridProblem,
    robot_moves: Sequence[int],
    obstacle_moves: Sequence[Sequence[int]],
    steps: int,
) -> tuple[tuple[State, ...], str | None]:
    """Run the moves through :func:`step`; the states and why the run loses (None: it wins)."""
    state = initial_state(problem)
    states = [state]
    for t, (k, joint) in enumerate(zip(robot_moves, obstacle_moves, strict=True)):
        nxt, collided = step(problem, state, k, joint)
        states.append(nxt)
        if collided:
            return tuple(states), collision_reason(problem, state, k, joint, t)
        state = nxt
    if len(robot_moves) == steps and state.robot != problem.robot.goal:
        return tuple(states), (
            f"not on the goal {_fmt(problem.robot.goal)} after step {steps - 1}: "
            f"the robot is at {_fmt(state.robot)}"
        )
    return tuple(states), None


def collision_reason(problem: GridProblem, state: State, k: int, joint: Sequence[int], t: int) -> str:
    """Why the robot collides at step ``t`` from ``state`` (a wall, or the first obstacle)."""
    _, swept = robot_move(problem, state.robot, k)
    for c in swept:
        if c in problem.walls:
            return f"collision at step {t} with the wall at {_fmt(c)}"
    for i, (p, j) in enumerate(zip(state.obstacles, joint)):
        _, o_swept = obstacle_move(problem, i, p, j)
        common = [c for c in swept if c in o_swept]
        if common:
            return f"collision at step {t} in cell {_fmt(common[0])} with obstacle {i}"
    raise ValueError(f"no collision at step {t}")


def _fmt(c: Cell) -> str:
    return f"({c[0]}, {c[1]})"


__all__ = [
    "Counterexample",
    "ProgramSyntaxError",
    "Verdict",
    "check_controller",
    "collision_reason",
    "read_obstacles",
    "verify",
]

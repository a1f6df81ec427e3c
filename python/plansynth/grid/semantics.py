"""One step of the grid game, exactly as ``shared/spec/grid-problem.md`` defines it.

This is the single definition of swept cells, clamping, walls and collisions. The
verifier, the simulator, the renderer and the native engine all use it; the SyGuS
compiler encodes the same rules as formulas and is cross-checked against it.

plansynth's extensions (docs/reference/grid-format.md) are defined here too: an
obstacle's block (``size``), the cells it keeps out of, its wait counter and glitches
(``period``, :class:`~plansynth.grid.objective.Schedule`), collisions of positions
(:class:`~plansynth.grid.objective.CollisionRule`), and the two counters of the
objectives (:mod:`plansynth.grid.objective`): the mode m of a recurrence objective and
the fairness counter f. A :class:`State` carries the wait counters and the glitches
left only when the problem has such obstacles (:attr:`GridProblem.stateful`), so the
states of a paper problem are what they always were.

The spec deliberately differs from the paper's published encoding (Chasins & Newcomb,
SYNT 2016, Section 3.2): cells are (x, y) pairs, so a move off the right edge does not
alias to the next row, and a clamped move sweeps only the cell it stays on.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 3],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right", "left"]},
...     "obstacles": [{"start": [1, 1], "moves": ["stay", "down"]}]})
>>> robot_move(p, (0, 0), 2)          # left is off the grid: clamped, sweeps only (0, 0)
((0, 0), ((0, 0),))
>>> step(p, State((0, 0), ((1, 1),)), 1, (1,))   # robot and obstacle both enter (1, 0)
StepOutcome(state=State(robot=(1, 0), obstacles=((1, 0),)), collided=True)
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from functools import cache, cached_property
from typing import NamedTuple

from plansynth.grid.objective import CollisionRule, ObjectiveKind, Schedule
from plansynth.grid.problem import Cell, GridProblem, Move


class State(NamedTuple):
    """The state of the game at the start of a step: the robot's and every obstacle's
    cell (its block's lowest corner); for a problem with periodic or glitching
    obstacles, every obstacle's wait counter and glitches left; the mode m of a
    recurrence objective and the fairness counter f (0 when the problem has none)."""

    robot: Cell
    obstacles: tuple[Cell, ...]
    phases: tuple[int, ...] = ()
    glitches: tuple[int, ...] = ()
    mode: int = 0
    fair: int = 0

    def __repr__(self) -> str:  # a paper problem's state reads as it always did
        extra = "".join(
            f", {k}={v!r}"
            for k, v in (("phases", self.phases), ("glitches", self.glitches), ("mode", self.mode), ("fair", self.fair))
            if v
        )
        return f"State(robot={self.robot!r}, obstacles={self.obstacles!r}{extra})"

    def inputs(self) -> tuple[int, ...]:
        """The cells in the spec's order ``rx ry o0x o0y ...`` (a paper problem's
        controller inputs; :func:`controller_inputs` gives every problem's)."""
        out = list(self.robot)
        for o in self.obstacles:
            out.extend(o)
        return tuple(out)


class StepOutcome(NamedTuple):
    state: State
    collided: bool


def initial_state(problem: GridProblem) -> State:
    cells = tuple(o.start for o in problem.obstacles)
    if not problem.stateful:
        return State(problem.robot.start, cells)
    return State(
        problem.robot.start,
        cells,
        tuple(o.initial_phase for o in problem.obstacles),
        tuple(o.glitches for o in problem.obstacles),
    )


def controller_inputs(problem: GridProblem, state: State) -> tuple[int, ...]:
    """The controller's inputs of ``state`` over ``problem.variables``.

    >>> from plansynth.grid.problem import grid_problem_from_dict
    >>> p = grid_problem_from_dict({"grid": [4, 4], "objective": "safety",
    ...     "robot": {"start": [0, 0], "moves": ["stay"]},
    ...     "obstacles": [{"start": [2, 2], "size": [2, 2], "moves": ["stay", "left"], "period": 2, "glitches": 1}]})
    >>> p.variables, controller_inputs(p, initial_state(p))
    (('rx', 'ry', 'o0x', 'o0y', 'o0p', 'o0g'), (0, 0, 2, 2, 1, 1))
    """
    out = list(state.robot)
    for i, o in enumerate(problem.obstacles):
        out.extend(state.obstacles[i])
        if o.periodic:
            out.append(state.phases[i])
        if o.glitching:
            out.append(state.glitches[i])
    if problem.mode_count > 1:
        out.append(state.mode)
    if problem.fair_count > 1:
        out.append(state.fair)
    return tuple(out)


def _sweep(problem: GridProblem, p: Cell, move: Move, size: Cell = (1, 1)) -> tuple[Cell, tuple[Cell, ...]] | None:
    """End cell and swept cells of ``move`` from ``p`` for an agent covering a ``size``
    block; None when a swept cell is off the grid."""
    w, h = size
    cells = tuple(
        dict.fromkeys((p[0] + dx + a, p[1] + dy + b) for dx, dy in move.offsets() for b in range(h) for a in range(w))
    )
    if not all(problem.in_grid(c) for c in cells):
        return None
    return (p[0] + move.to[0], p[1] + move.to[1]), cells


def robot_move(problem: GridProblem, p: Cell, k: int) -> tuple[Cell, tuple[Cell, ...]]:
    """The robot's move number ``k`` from ``p``: (end cell, swept cells).

    A move that would sweep a cell outside the grid leaves the robot at ``p``, sweeping
    only ``p``. Walls do not clamp the robot: sweeping a wall is a collision.
    """
    swept = _sweep(problem, p, problem.robot.moves[k])
    return swept if swept is not None else (p, (p,))


def robot_end(problem: GridProblem, p: Cell, k: int) -> Cell:
    """The end cell of the robot's move ``k`` from ``p``: ``robot_move(problem, p, k)[0]``
    without listing the swept cells (the verifier asks it of every cell near the goal).

    >>> from plansynth.grid.problem import grid_problem_from_dict
    >>> p = grid_problem_from_dict({"grid": [3, 1], "robot": {"start": [0, 0], "goal": [2, 0],
    ...     "moves": ["stay", "right", {"name": "jump", "to": [2, 0], "via": [[1, 0]]}]}})
    >>> robot_end(p, (0, 0), 2), robot_end(p, (1, 0), 2)   # the jump from (1, 0) is clamped
    ((2, 0), (1, 0))
    """
    move = problem.robot.moves[k]
    lo_x, hi_x, lo_y, hi_y = _extent(move)
    x, y = p
    if 0 <= x + lo_x and x + hi_x < problem.width and 0 <= y + lo_y and y + hi_y < problem.height:
        return (x + move.to[0], y + move.to[1])
    return p


@cache
def _extent(move: Move) -> tuple[int, int, int, int]:
    """The bounding box of a move's offsets: all of them are in the grid iff it is."""
    offsets = move.offsets()
    xs = [dx for dx, _ in offsets]
    ys = [dy for _, dy in offsets]
    return min(xs), max(xs), min(ys), max(ys)


def obstacle_move(problem: GridProblem, i: int, p: Cell, k: int) -> tuple[Cell, tuple[Cell, ...]]:
    """Obstacle ``i``'s move number ``k`` from ``p``: (end cell, swept cells).

    The cells swept are the obstacle's blocks at ``p``, at ``p + to`` and at ``p + v``
    for each ``via`` offset v. A move that would sweep a cell outside the grid, a wall
    or a cell the obstacle keeps out of leaves it at ``p``, sweeping only its block
    there.
    """
    o = problem.obstacles[i]
    swept = _sweep(problem, p, o.moves[k], o.size)
    if swept is None or any(c in problem.walls or c in o.keep_out for c in swept[1]):
        return p, o.block(p) if o.size != (1, 1) else (p,)
    return swept


def may_change_cell(problem: GridProblem, state: State, i: int) -> bool:
    """Whether obstacle ``i`` may end a step on another cell: its wait counter is 0, or
    it has a glitch left (:class:`~plansynth.grid.objective.Schedule`)."""
    if not problem.stateful:
        return True
    return state.phases[i] == 0 or state.glitches[i] > 0


def legal_moves(problem: GridProblem, state: State, i: int) -> tuple[int, ...]:
    """Obstacle ``i``'s moves allowed in ``state``: every move that leaves it on its
    cell, and the others when :func:`may_change_cell`."""
    n = len(problem.obstacles[i].moves)
    if may_change_cell(problem, state, i):
        return tuple(range(n))
    p = state.obstacles[i]
    return tuple(k for k in range(n) if obstacle_move(problem, i, p, k)[0] == p)


def counters_after(problem: GridProblem, i: int, phase: int, glitches: int, changed: bool) -> tuple[int, int]:
    """Obstacle ``i``'s wait counter and glitches left after a step in which it
    ``changed`` its cell (or not), from ``phase`` and ``glitches``
    (:class:`~plansynth.grid.objective.Schedule`). A change while the counter is above
    0 is a glitch: the caller checks that one was left."""
    o = problem.obstacles[i]
    k = o.period
    if changed and phase > 0:
        glitches -= 1
    if o.schedule is Schedule.REST:
        return (k - 1 if changed else max(phase - 1, 0)), glitches
    return (k - 1 if phase == 0 else phase - 1), glitches


def step(problem: GridProblem, state: State, k: int, obstacle_moves: Sequence[int]) -> StepOutcome:
    """All agents move at once: the robot by move ``k``, obstacle i by ``obstacle_moves[i]``.

    The robot collides if a cell it sweeps is a wall or (``collision: sweep``) is swept
    by some obstacle in the same step, or (``collision: position``) if its cell after
    the step lies in some obstacle's block after the step. The obstacles' counters, the
    mode and the fairness counter are updated as :mod:`plansynth.grid.objective` says.
    Raises ``ValueError`` for an obstacle move that :func:`legal_moves` does not allow.
    """
    r_end, r_swept = robot_move(problem, state.robot, k)
    collided = any(c in problem.walls for c in r_swept)
    position = problem.collision is CollisionRule.POSITION
    ends: list[Cell] = []
    phases: list[int] = []
    glitches: list[int] = []
    changed: list[bool] = []
    for i, (p, j) in enumerate(zip(state.obstacles, obstacle_moves, strict=True)):
        o_end, o_swept = obstacle_move(problem, i, p, j)
        moved = o_end != p
        if moved and not may_change_cell(problem, state, i):
            raise ValueError(f"obstacle {i} may not change its cell in this step (it waits, no glitch left)")
        ends.append(o_end)
        changed.append(moved)
        if problem.stateful:
            ph, gl = counters_after(problem, i, state.phases[i], state.glitches[i], moved)
            phases.append(ph)
            glitches.append(gl)
        if collided:
            continue
        collided = r_end in problem.obstacles[i].block(o_end) if position else not set(o_swept).isdisjoint(r_swept)
    mode, fair = state.mode, state.fair
    if problem.objective is ObjectiveKind.RECURRENCE and r_end == problem.robot.goals[mode]:
        mode = (mode + 1) % problem.mode_count
    if problem.fair_count > 1 and changed[fair]:
        fair = (fair + 1) % problem.fair_count
    return StepOutcome(State(r_end, tuple(ends), tuple(phases), tuple(glitches), mode, fair), collided)


def obstacle_choices(problem: GridProblem) -> Iterator[tuple[int, ...]]:
    """Every joint obstacle move (the adversary's choices in one step of a problem
    without wait counters; :func:`joint_choices` gives those of any state)."""
    return itertools.product(*(range(len(o.moves)) for o in problem.obstacles))


def joint_choices(problem: GridProblem, state: State) -> Iterator[tuple[int, ...]]:
    """Every joint obstacle move allowed in ``state``."""
    return itertools.product(*(legal_moves(problem, state, i) for i in range(len(problem.obstacles))))


@dataclass(frozen=True)
class CompiledSemantics:
    """The same rules as tables over cell indices ``y * width + x`` and bitmasks.

    For the hot loops of the verifier and the native engine: ``robot[c][k]`` and
    ``obstacle[i][c][k]`` are (end cell index, swept-cells bitmask); ``walls`` is a
    bitmask. Equivalence with :func:`step` is property-tested.
    """

    problem: GridProblem

    def index(self, c: Cell) -> int:
        return c[1] * self.problem.width + c[0]

    def cell(self, i: int) -> Cell:
        return (i % self.problem.width, i // self.problem.width)

    @cached_property
    def walls(self) -> int:
        m = 0
        for w in self.problem.walls:
            m |= 1 << self.index(w)
        return m

    def _table(self, move_of) -> tuple[tuple[tuple[int, int], ...], ...]:
        p = self.problem
        rows = []
        for ci in range(p.width * p.height):
            c = self.cell(ci)
            row = []
            for end, swept in move_of(c):
                mask = 0
                for s in swept:
                    mask |= 1 << self.index(s)
                row.append((self.index(end), mask))
            rows.append(tuple(row))
        return tuple(rows)

    @cached_property
    def robot(self) -> tuple[tuple[tuple[int, int], ...], ...]:
        p = self.problem
        return self._table(lambda c: [robot_move(p, c, k) for k in range(len(p.robot.moves))])

    @cached_property
    def obstacle(self) -> tuple[tuple[tuple[tuple[int, int], ...], ...], ...]:
        p = self.problem
        return tuple(
            self._table(lambda c, i=i: [obstacle_move(p, i, c, k) for k in range(len(o.moves))])
            for i, o in enumerate(p.obstacles)
        )

    @cached_property
    def obstacle_successors(self) -> tuple[tuple[tuple[tuple[int, int], ...], ...], ...]:
        """``obstacle_successors[i][c]``: the distinct (end, swept mask) pairs of obstacle i at c."""
        return tuple(tuple(tuple(dict.fromkeys(row)) for row in table) for table in self.obstacle)

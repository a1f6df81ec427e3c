"""One step of the grid game, exactly as ``shared/spec/grid-problem.md`` defines it.

This is the single definition of swept cells, clamping, walls and collisions. The
verifier, the simulator, the renderer and the native engine all use it; the SyGuS
compiler encodes the same rules as formulas and is cross-checked against it.

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

from plansynth.grid.problem import Cell, GridProblem, Move


class State(NamedTuple):
    """What the controller sees at the start of a step: the robot's and every obstacle's cell."""

    robot: Cell
    obstacles: tuple[Cell, ...]

    def inputs(self) -> tuple[int, ...]:
        """The controller's inputs in the spec's order ``rx ry o0x o0y ...``."""
        out = list(self.robot)
        for o in self.obstacles:
            out.extend(o)
        return tuple(out)


class StepOutcome(NamedTuple):
    state: State
    collided: bool


def initial_state(problem: GridProblem) -> State:
    return State(problem.robot.start, tuple(o.start for o in problem.obstacles))


def _sweep(problem: GridProblem, p: Cell, move: Move) -> tuple[Cell, tuple[Cell, ...]] | None:
    """End cell and swept cells of ``move`` from ``p``; None when a swept cell is off the grid."""
    cells = tuple((p[0] + dx, p[1] + dy) for dx, dy in move.offsets())
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

    A move that would sweep a cell outside the grid or a wall leaves the obstacle at
    ``p``, sweeping only ``p``.
    """
    swept = _sweep(problem, p, problem.obstacles[i].moves[k])
    if swept is None or any(c in problem.walls for c in swept[1]):
        return p, (p,)
    return swept


def step(problem: GridProblem, state: State, k: int, obstacle_moves: Sequence[int]) -> StepOutcome:
    """All agents move at once: the robot by move ``k``, obstacle i by ``obstacle_moves[i]``.

    The robot collides if a cell it sweeps is a wall or is swept by some obstacle in the
    same step.
    """
    r_end, r_swept = robot_move(problem, state.robot, k)
    collided = any(c in problem.walls for c in r_swept)
    ends = []
    for i, (p, j) in enumerate(zip(state.obstacles, obstacle_moves, strict=True)):
        o_end, o_swept = obstacle_move(problem, i, p, j)
        ends.append(o_end)
        if not collided and not set(o_swept).isdisjoint(r_swept):
            collided = True
    return StepOutcome(State(r_end, tuple(ends)), collided)


def obstacle_choices(problem: GridProblem) -> Iterator[tuple[int, ...]]:
    """Every joint obstacle move (the adversary's choices in one step)."""
    return itertools.product(*(range(len(o.moves)) for o in problem.obstacles))


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

"""Ehlers' "Robot-on-a-grid Moving Obstacle Evasion" family as an explicit safety game.

Source: R. Ehlers, *Robot-on-a-grid Moving Obstacle Evasion Benchmarks*, the description
``moving_obstacle_evasion.pdf`` beside the circuits ``aiger/moving_obstacle/
moving_obstacle_<m>x<m>_<c>glitches.aag`` of SYNTCOMP's benchmark repository
(``SYNTCOMP/benchmarks``, CC BY 4.0). The description states the specification in words
(Sect. I.A signals, I.B assumptions and guarantees, II error resilience); where it leaves
a detail open (the move encoding, the border, the first step, when a guarantee is read)
the rule below is what the benchmark's own circuits do, established by simulating them
(:mod:`plansynth.grid.syntcomp.aiger`) and pinned by ``tests/grid/syntcomp``, which
checks every rule below against the circuits (exhaustively on 8x8, at random on 16x16).

The rules (the grid is ``m x m``: Ehlers' ``mx = my = m`` in every published instance)
======================================================================================

* **Cells.** ``(x, y)`` with ``0 <= x, y < m`` (bits ``robx``/``roby`` of the circuits).
  The obstacle is the 2 x 2 block ``{ox, ox+1} x {oy, oy+1}`` given by its upper-left
  cell ``(ox, oy)``, ``0 <= ox, oy <= m - 2`` (assumptions 6, 7: ``ox`` is never
  ``>= mx - 1``).
* **Start.** Robot at ``(0, 0)``, obstacle at ``(m - 2, m - 2)`` ("the workspace corner
  that is most distant from the robot", assumptions 3 and 9), glitch counter 0.
* **The robot** picks, every step, ``dx`` and ``dy`` in ``{-1, 0, +1}`` independently
  (the circuits' ``controllable_movx``/``movy``: value ``v`` in 0..2 means ``v - 1``; the
  value 3 is an invalid move and a lost game, guarantees 3, 4). So it has 9 moves, staying
  included (Sect. I: "±1 cell in the x direction, and/or by ±1 cell in the y direction";
  "does not want to change its x position" is a move). **Border:** a move that would leave
  the grid leaves that coordinate unchanged ("collisions with the boundaries do not need
  to be avoided ... its boundaries cannot be crossed"; in the circuits the environment
  must then report the unchanged coordinate). The grid is not a torus.
* **The obstacle** (the environment) moves by at most one cell in x and in y each step
  (9 moves, staying and diagonals included; assumption 1) and stays inside the grid.
  **When:** it may change position only if it did not change position in the step
  before (assumption 8 with guarantee 2: the controller's output ``obsmove`` must be
  false exactly after a change of the obstacle's position, and the obstacle may change
  only while ``obsmove`` was true). It may also wait: "at most every second step", with
  no fixed phase. At the start ``obsmove`` must be false (the circuits flag a true
  ``obsmove`` in the first step; the description does not say), so the obstacle must
  wait in the first step unless it spends a glitch: the robot moves first.
* **Glitches** (Sect. II): a counter ``g`` set by the environment, ``0 <= g <= c``, that
  never decreases; a move of the obstacle right after a move (``obsmove`` false) is a
  glitch and must strictly increase the counter. The environment may also raise the
  counter without a glitch (never to its advantage). So at most ``c`` times the obstacle
  moves in two consecutive steps.
* **Collision** (guarantee 1): the robot's cell lies in the obstacle's 2 x 2 block, at
  one time step: ``ox <= x <= ox + 1`` and ``oy <= y <= oy + 1``. Only positions count:
  there are no swaps or crossings to rule out, since the robot's offset from the block's
  corner changes by at most 2 per coordinate and step, so it cannot pass from one side of
  the 2-cell-wide block to the other without landing in it. (The circuits read this
  guarantee one step late, from the latched positions, and the environment always has a
  legal next step, so a collision loses exactly as if read at once.)
* **Who sees what.** Each step the environment moves first (the obstacle's new cell, the
  robot's resulting cell, the counter); the robot then chooses its move having seen them
  (SYNTCOMP's AIGER games: the controllable inputs are chosen after the uncontrollable
  ones). The robot must avoid collisions forever (strong implication, Sect. I.B: once
  the environment breaks an assumption, the robot has won; an assumption and a guarantee
  broken in the same step is a robot win too).

The game here
=============

A :class:`State` is the robot's decision point: ``(robot, obstacle, obstacle_waits,
glitches)``, where ``obstacle_waits`` says that the obstacle may not move in the coming
step without a glitch (it changed position in the step that led here, or this is the
start) and ``glitches`` is the counter (``c - glitches`` glitches are left). The
controller's ``obsmove`` output is forced (``obsmove = not obstacle_waits``), so it is
not a choice of the robot here. The robot's moves are
:data:`MOVES`; :meth:`MovingObstacle.successors` gives every legal reply of the
environment. The robot wins from a state iff it can keep away from collisions forever:
:mod:`plansynth.grid.syntcomp.safety` solves it.

Published answers (Ehlers' Table I; SLUGS, realizability only): for ``m`` = 8, 16, 24,
32, 48, 64, 96 the game is realizable with ``c`` = 0, 3, 7, 11, 19, 27, 43 glitches and
unrealizable with one more: :data:`PUBLISHED`.

>>> game = MovingObstacle(8, 0)
>>> game.initial
State(robot=(0, 0), obstacle=(6, 6), obstacle_waits=True, glitches=0)
>>> game.is_collision(State((3, 4), (2, 3), False, 0)), game.is_collision(State((4, 4), (2, 3), False, 0))
(True, False)
>>> [s.obstacle for s in game.successors(game.initial, (1, 1))]     # it waits in the first step
[(6, 6)]
>>> sorted({s.obstacle for s in game.successors(State((0, 0), (6, 6), False, 0), (1, 1))})
[(5, 5), (5, 6), (6, 5), (6, 6)]
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import NamedTuple

from plansynth.errors import InvalidProblem

__all__ = [
    "MOVES",
    "PUBLISHED",
    "MovingObstacle",
    "State",
    "Cell",
    "Move",
    "circuit_name",
    "grid_document",
    "KING_MOVES",
]

Cell = tuple[int, int]
Move = tuple[int, int]

#: The robot's moves ``(dx, dy)``, staying first; also the obstacle's displacements.
MOVES: tuple[Move, ...] = tuple((dx, dy) for dx in (0, -1, 1) for dy in (0, -1, 1))

#: Ehlers' Table I: ``(m, c) -> (realizable, SLUGS seconds on an AMD E-450 1.6 GHz)``;
#: ``None`` where SLUGS did not decide in 4 h (128 x 128).
PUBLISHED: dict[tuple[int, int], tuple[bool | None, float | None]] = {
    (8, 0): (True, 0.3),
    (8, 1): (False, 0.4),
    (16, 3): (True, 1.7),
    (16, 4): (False, 4.5),
    (24, 7): (True, 27.6),
    (24, 8): (False, 20.0),
    (32, 11): (True, 53.0),
    (32, 12): (False, 53.0),
    (48, 19): (True, 359.0),
    (48, 20): (False, 294.0),
    (64, 27): (True, 2172.0),
    (64, 28): (False, 3280.0),
    (96, 43): (True, 3764.0),
    (96, 44): (False, 5744.829),
    (128, 59): (None, None),
    (128, 60): (None, None),
}


#: The nine moves of the robot and of the obstacle as the grid format's built-in names,
#: staying first (the format's diagonals sweep their start and end cells only).
KING_MOVES: tuple[str, ...] = ("stay", "up", "down", "left", "right", "up-right", "up-left", "down-right", "down-left")


def grid_document(m: int, c: int) -> dict:
    """The instance ``m x m`` with ``c`` glitches as a plansynth problem document
    (docs/reference/grid-format.md), the rules of the module docstring written in the
    format: objective ``safety``; ``collision: position`` (guarantee 1 reads positions
    only); the robot at (0, 0) with the nine king moves; one 2 x 2 obstacle at
    (m - 2, m - 2) with the same moves, ``period: 2`` on the ``rest`` schedule with the
    default phase 1 (it may change cell at most every second step, with no fixed phase,
    and must wait in the first step: the robot moves first) and ``glitches: c``.

    At the border the format voids a move whose end cell is off the grid (the robot
    stays), where the circuits move the other coordinate; both leave the robot the same
    set of next cells (staying is a move), so the games are the same. The circuits'
    environment may also raise the glitch counter without a glitch, which never helps
    it; ``tests/grid/syntcomp/test_moving_obstacle_format.py`` checks both claims.

    >>> d = grid_document(8, 1)
    >>> d["objective"], d["collision"], d["obstacles"][0]["size"], d["obstacles"][0]["glitches"]
    ('safety', 'position', [2, 2], 1)
    """
    obstacle: dict = {"start": [m - 2, m - 2], "size": [2, 2], "moves": list(KING_MOVES), "period": 2}
    if c:
        obstacle["glitches"] = c
    return {
        "name": f"moving-obstacle-{m}x{m}-{c}",
        "grid": [m, m],
        "objective": "safety",
        "collision": "position",
        "robot": {"start": [0, 0], "moves": list(KING_MOVES)},
        "obstacles": [obstacle],
    }


def circuit_name(m: int, c: int) -> str:
    """The benchmark file's name for ``(m, c)``.

    >>> circuit_name(16, 3)
    'moving_obstacle_16x16_3glitches.aag'
    """
    return f"moving_obstacle_{m}x{m}_{c}glitches.aag"


class State(NamedTuple):
    """The robot's decision point (see the module's docstring): the robot's cell, the
    obstacle's upper-left cell, whether the obstacle must wait (or glitch) before its
    next move, and the glitch counter."""

    robot: Cell
    obstacle: Cell
    obstacle_waits: bool
    glitches: int


@dataclass(frozen=True)
class MovingObstacle:
    """The instance ``m x m`` with ``c`` glitches (Ehlers' ``mx = my = m``)."""

    size: int
    glitches: int

    def __post_init__(self) -> None:
        if isinstance(self.size, bool) or not isinstance(self.size, int) or self.size < 3:
            raise InvalidProblem(None, "size", f"the grid needs at least 3 x 3 cells, got {self.size!r}")
        if isinstance(self.glitches, bool) or not isinstance(self.glitches, int) or self.glitches < 0:
            raise InvalidProblem(None, "glitches", f"a number of glitches >= 0, got {self.glitches!r}")

    @property
    def initial(self) -> State:
        """Robot at (0, 0), obstacle in the far corner and waiting, no glitch."""
        return State((0, 0), (self.size - 2, self.size - 2), True, 0)

    def states(self) -> Iterator[State]:
        """Every state: ``m^2 (m-1)^2 2 (c+1)`` of them."""
        m = self.size
        for rx in range(m):
            for ry in range(m):
                for ox in range(m - 1):
                    for oy in range(m - 1):
                        for waits in (False, True):
                            for g in range(self.glitches + 1):
                                yield State((rx, ry), (ox, oy), waits, g)

    def is_collision(self, state: State) -> bool:
        """The robot's cell lies in the obstacle's 2 x 2 block."""
        (x, y), (ox, oy) = state.robot, state.obstacle
        return ox <= x <= ox + 1 and oy <= y <= oy + 1

    def move_robot(self, cell: Cell, move: Move) -> Cell:
        """The robot's next cell: each coordinate moves by the move's component unless
        that would leave the grid (then it stays)."""
        return (_clamp(cell[0] + move[0], self.size - 1), _clamp(cell[1] + move[1], self.size - 1))

    def obstacle_moves(self, state: State) -> Iterator[tuple[Cell, int]]:
        """The environment's legal replies ``(new obstacle corner, new counter)``."""
        m, c = self.size, self.glitches
        ox, oy = state.obstacle
        for dx, dy in MOVES:
            nx, ny = ox + dx, oy + dy
            if not (0 <= nx <= m - 2 and 0 <= ny <= m - 2):
                continue
            glitch = (dx, dy) != (0, 0) and state.obstacle_waits
            for g in range(state.glitches + (1 if glitch else 0), c + 1):
                yield (nx, ny), g

    def successors(self, state: State, move: Move) -> Iterator[State]:
        """The states the environment can lead to after the robot's ``move``."""
        robot = self.move_robot(state.robot, move)
        for obstacle, g in self.obstacle_moves(state):
            yield State(robot, obstacle, obstacle != state.obstacle, g)


def _clamp(v: int, top: int) -> int:
    return 0 if v < 0 else top if v > top else v

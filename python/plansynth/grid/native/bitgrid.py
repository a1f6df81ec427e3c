"""Sets of cells as Python integers, and the images of whole sets under one move.

A set of cells is an ``int`` whose bit ``y * width + x`` is set for each cell (the
indexing of :class:`~plansynth.grid.semantics.CompiledSemantics`). Moving every cell of
a set by the same move is a shift of the integer, restricted to the cells where the
move is not clamped; clamped cells stay where they are (spec, Semantics). This turns
the reachability and cone-of-influence computations into a handful of big-integer
operations per step instead of a loop over cells.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 2],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right", "up"]}})
>>> g = AgentGeometry.robot(p)
>>> cells(g.image(1 << 0, 1), 3)        # right from (0, 0)
[(1, 0)]
>>> cells(g.image(0b100, 1), 3)         # right from (2, 0) is clamped
[(2, 0)]
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.grid.problem import Cell, GridProblem, Move


def shift(mask: int, offset: Cell, width: int) -> int:
    """Move every cell of ``mask`` by ``offset`` (no border check: callers mask first)."""
    d = offset[1] * width + offset[0]
    return mask << d if d >= 0 else mask >> -d


def cells(mask: int, width: int) -> list[Cell]:
    """The cells of a mask, in index order."""
    out = []
    i = 0
    while mask:
        if mask & 1:
            out.append((i % width, i // width))
        mask >>= 1
        i += 1
    return out


def bits(mask: int) -> list[int]:
    """Indices of the set bits of ``mask``, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return out


def grid_mask(problem: GridProblem) -> int:
    return (1 << (problem.width * problem.height)) - 1


def cell_mask(problem: GridProblem, c: Cell) -> int:
    return 1 << (c[1] * problem.width + c[0])


def wall_mask(problem: GridProblem) -> int:
    m = 0
    for w in problem.walls:
        m |= cell_mask(problem, w)
    return m


@dataclass(frozen=True)
class AgentGeometry:
    """One agent's moves as set operations.

    ``valid[k]``: cells from which move k is taken as written (not clamped).
    ``free[k]``: for the robot, cells from which move k sweeps no wall (a clamped move
    sweeps only its start cell, never a wall for a robot standing there); for an
    obstacle every cell (walls clamp obstacles instead, already in ``valid``).
    """

    width: int
    full: int
    moves: tuple[Move, ...]
    valid: tuple[int, ...]
    free: tuple[int, ...]

    @staticmethod
    def _valid(problem: GridProblem, move: Move, blocked: int) -> int:
        """Cells whose every swept cell is on the grid and outside ``blocked``."""
        w, h = problem.width, problem.height
        full = grid_mask(problem)
        ok = full
        for dx, dy in move.offsets():
            # sources c with c + (dx, dy) on the grid: columns max(0, -dx)..min(w, w - dx)
            # of rows max(0, -dy)..min(h, h - dy), built as a row pattern times a repunit
            # (one bit per row): two big-integer operations instead of one per row
            x0, x1 = max(0, -dx), min(w, w - dx)
            y0, y1 = max(0, -dy), min(h, h - dy)
            if x0 >= x1 or y0 >= y1:
                ok = 0
                continue
            row = ((1 << (x1 - x0)) - 1) << x0
            rows = y1 - y0
            repunit = ((1 << (w * rows)) - 1) // ((1 << w) - 1)
            ok &= (row * repunit) << (y0 * w)
            if blocked:
                ok &= ~shift(blocked, (-dx, -dy), w) & full
        return ok

    @classmethod
    def robot(cls, problem: GridProblem) -> AgentGeometry:
        full = grid_mask(problem)
        walls = wall_mask(problem)
        valid = tuple(cls._valid(problem, m, 0) for m in problem.robot.moves)
        free = []
        for m, v in zip(problem.robot.moves, valid):
            hits = 0
            for o in m.offsets():
                hits |= shift(walls, (-o[0], -o[1]), problem.width) & v
            free.append(full & ~hits & ~walls)
        return cls(problem.width, full, problem.robot.moves, valid, tuple(free))

    @classmethod
    def obstacle(cls, problem: GridProblem, i: int) -> AgentGeometry:
        full = grid_mask(problem)
        moves = problem.obstacles[i].moves
        valid = tuple(cls._valid(problem, m, wall_mask(problem)) for m in moves)
        return cls(problem.width, full, moves, valid, tuple(full for _ in moves))

    def image(self, mask: int, k: int) -> int:
        """End cells of move ``k`` from every cell of ``mask`` (collision-free sources only)."""
        src = mask & self.free[k]
        v = src & self.valid[k]
        return shift(v, self.moves[k].to, self.width) | (src & ~self.valid[k])

    def post(self, mask: int) -> int:
        """End cells of any move from ``mask``."""
        out = 0
        for k in range(len(self.moves)):
            out |= self.image(mask, k)
        return out

    def sweep(self, mask: int, k: int) -> int:
        """Cells swept by move ``k`` from every cell of ``mask`` (collision-free sources)."""
        src = mask & self.free[k]
        v = src & self.valid[k]
        out = src & ~self.valid[k]
        for o in self.moves[k].offsets():
            out |= shift(v, o, self.width)
        return out

    def sweep_all(self, mask: int) -> int:
        """Cells swept by some move from some cell of ``mask``."""
        out = 0
        for k in range(len(self.moves)):
            out |= self.sweep(mask, k)
        return out

    def pre(self, target: int, k: int) -> int:
        """Cells from which move ``k`` is collision-free (walls) and ends in ``target``."""
        v = shift(target, (-self.moves[k].to[0], -self.moves[k].to[1]), self.width) & self.valid[k]
        return (v | (target & ~self.valid[k])) & self.free[k]

    def hit_sources(self, danger: int, k: int) -> int:
        """Cells from which move ``k`` sweeps some cell of ``danger``."""
        v = 0
        for o in self.moves[k].offsets():
            v |= shift(danger, (-o[0], -o[1]), self.width)
        return ((v & self.valid[k]) | (danger & ~self.valid[k])) & self.full

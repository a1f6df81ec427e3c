"""Move tables and reachable sets in plain Python (dicts, integer bitsets), for small
grids: on them the search takes milliseconds and numpy's import (0.1-0.15 s) would
dominate a ``plansynth grid solve``. The same answers, cell for cell, as
:mod:`.numpy_tables`."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.semantics import robot_end
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.tables import Cells, Distinct, MoveTable, PeriodicReach, Row, StepDanger

__all__ = ["Table", "UnreadReach", "goal_distances", "cells_of"]

Move = Callable[[Cell, int], tuple[Cell, Sequence[Cell]]]


class Table:
    """The moves of one agent: ``table[c]`` is the row of cell ``c`` (``(end, frozenset
    of swept cells)`` per move), computed from the semantics on first use;
    ``masks(c)`` the same row as two integer bitsets (every end cell, every swept
    cell), for :class:`Reach`."""

    def __init__(self, problem: GridProblem, move: Move, moves: Sequence, meter: Meter) -> None:
        self.width = problem.width
        self.move = move
        self.n_moves = len(moves)
        self.meter = meter
        self.rows: dict[int, Row] = {}
        self._masks: dict[int, tuple[int, int]] = {}
        self.successors = Distinct(self)

    def __getitem__(self, c: int) -> Row:
        row = self.rows.get(c)
        if row is None:
            self.meter.tick(self.n_moves * Meter.SEMANTICS_CALL)
            w = self.width
            out = []
            for k in range(self.n_moves):
                end, cells_k = self.move((c % w, c // w), k)
                out.append((end[1] * w + end[0], frozenset(y * w + x for x, y in cells_k)))
            row = self.rows[c] = tuple(out)
        return row

    def masks(self, c: int) -> tuple[int, int]:
        m = self._masks.get(c)
        if m is None:
            ends = swept = 0
            for end, cells_k in self[c]:
                ends |= 1 << end
                for x in cells_k:
                    swept |= 1 << x
            m = self._masks[c] = (ends, swept)
        return m


def cells_of(mask: int) -> list[int]:
    """The cell indices of an integer bitset, ascending.

    >>> cells_of(0b10110)
    [1, 2, 4]
    """
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return out


class Reach(PeriodicReach):
    """One unread obstacle's reachable cells as an integer bitset (see :class:`UnreadReach`)."""

    def __init__(self, table: Table, start: int) -> None:
        super().__init__(1 << start)
        self.table = table

    def successors(self, cells: int, meter: Meter) -> int:
        out = 0
        masks = self.table.masks
        listed = cells_of(cells)
        meter.tick(len(listed) * self.table.n_moves)
        for c in listed:
            out |= masks(c)[0]
        return out

    def sweep(self, cells: int, meter: Meter) -> int:
        listed = cells_of(cells)
        meter.tick(len(listed) * self.table.n_moves)
        masks = self.table.masks
        out = 0
        for c in listed:
            out |= masks(c)[1]
        return out

    def same(self, a: int, b: int) -> bool:
        return a == b


class UnreadReach(StepDanger):
    """Reduction 2 of :mod:`plansynth.grid.verify`, a step at a time (see
    :class:`.numpy_tables.UnreadReach`); ``danger(t)`` is the same packed bitmap (bit
    ``c`` of byte ``c >> 3``)."""

    def __init__(self, problem: GridProblem, tables: Sequence[Table], unread: tuple[int, ...], meter: Meter) -> None:
        super().__init__(problem, meter, len(unread))
        self.tables = tables
        self.obstacles = [Reach(tables[i], self.start(i)) for i in unread]

    def swept(self, t: int) -> bytes:
        total = 0
        for ob in self.obstacles:
            total |= ob.sweeps(t, self.meter)
        return total.to_bytes(len(self.zero), "little")

    def hit(self, i: int, t: int, r_swept: Cells) -> list[int] | None:
        """As :meth:`.numpy_tables.UnreadReach.hit`, choosing the same moves (lowest
        move, then lowest cell, at each step)."""
        table = self.tables[i]
        ob = Reach(table, self.start(i))
        history: list[int] = []
        for step_t in range(t + 1):
            history.append(ob.cur)
            if step_t < t:
                ob.cur = ob.successors(ob.cur, self.meter)
        cur = cells_of(ob.cur)
        for k in range(table.n_moves):
            c = next((c for c in cur if not table[c][k][1].isdisjoint(r_swept)), None)
            if c is not None:
                moves = [k]
                for step_t in range(t - 1, -1, -1):
                    cells = cells_of(history[step_t])
                    self.meter.tick(len(cells))
                    for m in range(table.n_moves):
                        prev = next((p for p in cells if table[p][m][0] == c), None)
                        if prev is not None:
                            c = prev
                            moves.append(m)
                            break
                    else:  # pragma: no cover - each set is the image of the one before
                        raise AssertionError("verifier bug: an unread obstacle's cell has no predecessor")
                return moves[::-1]
        return None


def goal_distances(problem: GridProblem, robot: MoveTable, goal: int, steps: int, meter: Meter) -> list[int]:
    """Fewest robot moves from each cell to the goal (obstacles and walls ignored;
    ``steps + 1`` when more than ``steps``): breadth-first back from the goal."""
    w, h, far = problem.width, problem.height, steps + 1
    meter.check()
    dist = [far] * (w * h)
    dist[goal] = 0
    frontier = [goal]
    for d in range(1, far):
        if not frontier:
            break
        found: set[int] = set()
        for k, m in enumerate(problem.robot.moves):
            dx, dy = m.to
            for e in frontier:
                cx, cy = e % w - dx, e // w - dy
                if 0 <= cx < w and 0 <= cy < h:
                    c = cy * w + cx
                    if dist[c] == far and robot_end(problem, (cx, cy), k) == (e % w, e // w):
                        found.add(c)
        for c in found:
            dist[c] = d
        frontier = sorted(found)
        meter.tick(len(found) // 8 + 1)
    return dist

"""What the search asks of a move table and of the unread obstacles' reachable sets.

Two representations provide it, with the same answers (tests/grid/test_verify.py):
:mod:`.python_tables` (dicts and integer bitsets, for small grids: no numpy import) and
:mod:`.numpy_tables` (lazily filled arrays, for large ones). Each module has a
``Table`` (:class:`MoveTable`), an ``UnreadReach`` (:class:`UnreadDanger`) and a
``goal_distances`` function.
"""

from __future__ import annotations

from typing import Any, Protocol

from plansynth.grid.problem import GridProblem
from plansynth.grid.verify.meter import Meter

__all__ = ["Cells", "Sets", "Row", "MoveTable", "UnreadDanger", "StepDanger", "PeriodicReach", "Distinct"]

#: A set of cells (indices ``y * width + x``) one read obstacle may occupy.
Cells = frozenset[int]
#: One cell set per read obstacle: a product of possible positions.
Sets = tuple[Cells, ...]
#: The moves of one cell: ``(end cell, swept cells)`` per move number.
Row = tuple[tuple[int, Cells], ...]


class MoveTable(Protocol):
    """The moves of one agent over cell indices, computed from
    :mod:`plansynth.grid.semantics` on first use."""

    n_moves: int
    successors: Distinct

    def __getitem__(self, c: int) -> Row: ...


class UnreadDanger(Protocol):
    """Reduction 2 of :mod:`plansynth.grid.verify`: what the obstacles a program does not
    read can sweep at each step."""

    def danger(self, t: int) -> bytes:
        """Packed bitmap (bit ``c`` of byte ``c >> 3``) of every cell some unread
        obstacle can sweep at step ``t``."""
        ...

    def hit(self, i: int, t: int, r_swept: Cells) -> list[int] | None:
        """Moves of unread obstacle ``i`` for steps 0..t whose last one sweeps a cell of
        ``r_swept`` (None if it cannot)."""
        ...


class Distinct:
    """``successors[c]``: the distinct (end, swept cells) pairs of a table's row."""

    def __init__(self, rows: MoveTable) -> None:
        self.of = rows
        self.cache: dict[int, Row] = {}

    def __getitem__(self, ci: int) -> Row:
        row = self.cache.get(ci)
        if row is None:
            row = self.cache[ci] = tuple(dict.fromkeys(self.of[ci]))
        return row


class StepDanger:
    """The bookkeeping both ``UnreadReach`` share: the danger bitmap of each step,
    computed in order (:meth:`swept` of the representation), named in the meter's phase
    while computed, and each distinct bitmap stored once."""

    def __init__(self, problem: GridProblem, meter: Meter, n_obstacles: int) -> None:
        self.problem = problem
        self.meter = meter
        self.n_cells = problem.width * problem.height
        self.zero = bytes((self.n_cells + 7) // 8)
        self.n_obstacles = n_obstacles
        self._danger: list[bytes] = []
        self._distinct: dict[bytes, bytes] = {self.zero: self.zero}

    def start(self, i: int) -> int:
        """The start cell index of obstacle ``i``."""
        x, y = self.problem.obstacles[i].start
        return y * self.problem.width + x

    def danger(self, t: int) -> bytes:
        """Packed bitmap (bit ``c`` of byte ``c >> 3``) of every cell some unread
        obstacle can sweep at step ``t``."""
        while len(self._danger) <= t:
            self._advance()
        return self._danger[t]

    def _advance(self) -> None:
        t = len(self._danger)
        if not self.n_obstacles:
            self._danger.append(self.zero)
            return
        phase = self.meter.phase
        self.meter.phase = f"the unread obstacles' reachable cells (step {t})"
        b = self.swept(t)
        self._danger.append(self._distinct.setdefault(b, b))
        self.meter.phase = phase

    def swept(self, t: int) -> bytes:
        """The packed bitmap of step ``t`` (called for t = 0, 1, 2, ... in order)."""
        raise NotImplementedError


class PeriodicReach:
    """One unread obstacle's reachable cells, advanced step by step, in a
    representation's own set type (:meth:`sweep`, :meth:`successors`, :meth:`same`).

    A set sequence is a function of its current set, so once the set equals the one one
    or two steps earlier (a saturated reach, with or without ``stay``) its sweeps repeat
    with that period and are no longer computed; only the last two sweeps are kept."""

    def __init__(self, start: Any) -> None:
        self.cur = start
        self.prev: Any = None
        self.packed: list[Any] = []  # the sweeps of the last steps (at most 2)
        self.period: int | None = None
        self.t = 0

    def sweeps(self, t: int, meter: Meter) -> Any:
        """The cells this obstacle can sweep at step ``t`` (called for t = 0, 1, 2, ...
        in order)."""
        assert t == self.t, "sweeps are advanced one step at a time"
        self.t += 1
        if self.period is not None:
            out = self.packed[-self.period]
            self.packed = (self.packed + [out])[-2:]
            return out
        cells = self.cur
        out = self.sweep(cells, meter)
        self.packed = (self.packed + [out])[-2:]
        nxt = self.successors(cells, meter)
        if self.same(nxt, cells):
            self.period = 1
        elif self.prev is not None and self.same(nxt, self.prev):
            self.period = 2
        self.prev, self.cur = cells, nxt
        return out

    def sweep(self, cells: Any, meter: Meter) -> Any:
        """Every cell some move from ``cells`` sweeps."""
        raise NotImplementedError

    def successors(self, cells: Any, meter: Meter) -> Any:
        """Every cell some move from ``cells`` ends in."""
        raise NotImplementedError

    def same(self, a: Any, b: Any) -> bool:
        raise NotImplementedError

"""What the search asks of a move table and of the unread obstacles' reachable sets.

Two representations provide it, with the same answers (tests/grid/test_verify.py):
:mod:`.python_tables` (dicts and integer bitsets, for small grids: no numpy import) and
:mod:`.numpy_tables` (lazily filled arrays, for large ones). Each module has a
``Table`` (:class:`MoveTable`), an ``UnreadReach`` (:class:`UnreadDanger`) and a
``goal_distances`` function.
"""

from __future__ import annotations

from typing import Protocol

__all__ = ["Cells", "Sets", "Row", "MoveTable", "UnreadDanger", "Distinct"]

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
    successors: "Distinct"

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

"""Move tables and reachable sets as numpy arrays, for large grids: a table is filled
lazily (only the cells the search meets: a 1000 x 1000 grid has a million cells and the
robot and obstacles usually visit few of them), reachable sets are index arrays and a
step's danger is a packed bitmap. The same answers, cell for cell, as
:mod:`.python_tables`; importing this module imports numpy."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.tables import Cells, Distinct, PeriodicReach, Row, StepDanger

__all__ = ["Table", "UnreadReach", "goal_distances", "bitmap"]

Move = Callable[[Cell, int], tuple[Cell, Sequence[Cell]]]


class Table:
    """The moves of one agent over cell indices, filled lazily from
    :mod:`plansynth.grid.semantics` (only for the cells the search meets).

    ``end[k, c]`` is 1 + the end index of move ``k`` from cell ``c`` (0: not computed
    yet) and ``swept[k][c]`` its swept cell indices (padded by repeating the first one);
    ``table[c]`` is the row as Python values, ``(end, frozenset of swept cells)`` per
    move, and ``table.successors[c]`` its distinct pairs.
    """

    #: Cells computed between two budget checks.
    CHUNK = 64

    def __init__(self, problem: GridProblem, move: Move, moves: Sequence, meter: Meter) -> None:
        self.width = problem.width
        self.move = move
        self.n_moves = len(moves)
        self.meter = meter
        n = problem.width * problem.height
        meter.check()
        self.end = np.zeros((self.n_moves, n), dtype=np.int32)
        self.swept = [np.zeros((n, len(m.offsets())), dtype=np.int32) for m in moves]
        self.rows: dict[int, Row] = {}
        self.successors = Distinct(self)

    def fill(self, cells: np.ndarray) -> None:
        """Compute the moves of every cell of ``cells`` (an index array) not yet computed."""
        if cells.size == 0:
            return
        missing = cells[self.end[0, cells] == 0]  # callers pass distinct cells
        for i in range(0, missing.size, self.CHUNK):
            self.meter.tick(self.CHUNK * self.n_moves * Meter.SEMANTICS_CALL)
            self._fill(missing[i : i + self.CHUNK])

    def _fill(self, missing: np.ndarray) -> None:
        w = self.width
        xy = [(c % w, c // w) for c in missing.tolist()]
        for k in range(self.n_moves):
            ncol = self.swept[k].shape[1]
            ends = []
            swept = []
            for c in xy:
                end, cells_k = self.move(c, k)
                ends.append(end[1] * w + end[0] + 1)
                row = [y * w + x for x, y in cells_k]
                if len(row) > ncol:  # pragma: no cover - semantics sweeps the offsets or the start
                    raise AssertionError(f"move {k} from {c} sweeps more cells than its offsets")
                swept.append(row + row[:1] * (ncol - len(row)))
            self.swept[k][missing] = swept
            self.end[k, missing] = ends

    def __getitem__(self, c: int) -> Row:
        row = self.rows.get(c)
        if row is None:
            if self.end[0, c] == 0:
                self.fill(np.array([c]))
            row = self.rows[c] = tuple(
                (int(self.end[k, c]) - 1, frozenset(self.swept[k][c].tolist())) for k in range(self.n_moves)
            )
        return row


def bitmap(cells: np.ndarray, n: int) -> np.ndarray:
    """A boolean array of ``n`` cells, true on ``cells``."""
    b = np.zeros(n, dtype=bool)
    b[cells] = True
    return b


class Reach(PeriodicReach):
    """One unread obstacle's reachable cells as a sorted index array (see :class:`UnreadReach`);
    its sweeps are packed bitmaps of the ``n`` cells."""

    def __init__(self, table: Table, start: np.ndarray, n: int) -> None:
        super().__init__(start)
        self.table = table
        self.n = n

    def successors(self, cells: np.ndarray, meter: Meter) -> np.ndarray:
        meter.tick(int(cells.size) * self.table.n_moves)
        self.table.fill(cells)
        ends = (self.table.end[:, cells] - 1).ravel()
        if ends.size < 4096:
            return np.unique(ends)
        return np.flatnonzero(bitmap(ends, self.table.end.shape[1])).astype(np.int32)  # 4 bytes a cell

    def sweep(self, cells: np.ndarray, meter: Meter) -> np.ndarray:
        meter.tick(int(cells.size) * self.table.n_moves)
        self.table.fill(cells)
        mask = np.zeros(self.n, dtype=bool)
        for col in self.table.swept:
            mask[col[cells].ravel()] = True
        return np.packbits(mask, bitorder="little")

    def same(self, a: np.ndarray, b: np.ndarray) -> bool:
        return np.array_equal(a, b)


class UnreadReach(StepDanger):
    """Reduction 2 of :mod:`plansynth.grid.verify`, a step at a time: the cells each
    unread obstacle can occupy at time t (a sorted index array; only the current one is
    kept) and, per step, the packed bitmap of every cell some unread obstacle can sweep
    then.

    A set sequence is a function of its current set, so once an obstacle's set equals
    the one one or two steps earlier (a saturated reach, with or without ``stay``) its
    sweeps repeat with that period and are no longer recomputed. Identical bitmaps are
    stored once.
    """

    def __init__(self, problem: GridProblem, tables: Sequence[Table], unread: tuple[int, ...], meter: Meter) -> None:
        super().__init__(problem, meter, len(unread))
        self.tables = tables
        self.obstacles = [Reach(tables[i], self._start(i), self.n_cells) for i in unread]

    def _start(self, i: int) -> np.ndarray:
        return np.array([self.start(i)], dtype=np.int32)

    def swept(self, t: int) -> bytes:
        total = None
        for ob in self.obstacles:
            packed = ob.sweeps(t, self.meter)
            total = packed if total is None else total | packed
        return total.tobytes()

    def hit(self, i: int, t: int, r_swept: Cells) -> list[int] | None:
        """Moves of unread obstacle ``i`` for steps 0..t whose last one sweeps a cell of
        ``r_swept`` (None if it cannot). Replays its sets from the start, keeping them
        packed (cells / 8 bytes a step), and walks back through them."""
        table = self.tables[i]
        ob = Reach(table, self._start(i), self.n_cells)
        history: list[bytes] = []
        for step_t in range(t + 1):
            self.meter.tick(int(ob.cur.size))
            history.append(np.packbits(bitmap(ob.cur, self.n_cells), bitorder="little").tobytes())
            if step_t < t:
                ob.cur = ob.successors(ob.cur, self.meter)
        want = np.array(sorted(r_swept), dtype=np.int64)
        cur = ob.cur
        table.fill(cur)
        for k in range(table.n_moves):
            meets = np.isin(table.swept[k][cur], want).any(axis=1)
            if meets.any():
                c = int(cur[np.argmax(meets)])
                moves = [k]
                for step_t in range(t - 1, -1, -1):
                    cells = np.flatnonzero(
                        np.unpackbits(
                            np.frombuffer(history[step_t], dtype=np.uint8), count=self.n_cells, bitorder="little"
                        )
                    )
                    for m in range(table.n_moves):
                        prev = cells[table.end[m, cells] - 1 == c]
                        if prev.size:
                            c = int(prev[0])
                            moves.append(m)
                            break
                    else:  # pragma: no cover - each set is the image of the one before
                        raise AssertionError("verifier bug: an unread obstacle's cell has no predecessor")
                return moves[::-1]
        return None


def goal_distances(problem: GridProblem, robot: Table, goal: int, steps: int, meter: Meter) -> np.ndarray:
    """Fewest robot moves from each cell to the goal (obstacles and walls ignored;
    ``steps + 1`` when more than ``steps``): breadth-first back from the goal to depth
    ``steps``, vectorised over each frontier, move rows computed only for the cells met."""
    w, h = problem.width, problem.height
    n_cells = w * h
    meter.check()
    dist = np.full(n_cells, steps + 1, dtype=np.int32)
    dist[goal] = 0
    frontier = np.array([goal], dtype=np.int64)
    ends = robot.end
    for d in range(1, steps + 1):
        if frontier.size == 0:
            break
        ex, ey = frontier % w, frontier // w
        found = []
        for k, m in enumerate(problem.robot.moves):
            cx, cy = ex - m.to[0], ey - m.to[1]
            ok = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
            cand, target = (cy * w + cx)[ok], frontier[ok]
            fresh = dist[cand] > steps
            cand, target = cand[fresh], target[fresh]
            robot.fill(cand)
            found.append(cand[ends[k, cand] - 1 == target])
        nxt = np.concatenate(found)
        nxt = np.unique(nxt) if nxt.size < 4096 else np.flatnonzero(bitmap(nxt, n_cells))
        nxt = nxt[dist[nxt] > steps]
        dist[nxt] = d
        frontier = nxt
        meter.tick(int(nxt.size) // 8 + 1)
    return dist

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

Two shortcuts only make losses cheaper to find: a robot farther from the goal (in robot
moves, obstacles ignored) than the steps left has lost whatever the obstacles do, and a
short depth-first probe (:data:`PROBE_NODES` expansions, obstacles nearest the robot
first) runs before the exhaustive layered search. Move tables are filled lazily from
:func:`~plansynth.grid.semantics.robot_move` and
:func:`~plansynth.grid.semantics.obstacle_move`, so a 64 x 64 grid costs only the cells
visited.

When the controller loses, the verdict carries a concrete :class:`Counterexample`: the
obstacles' joint moves, the states visited and the program's choices, which replay
through :func:`~plansynth.grid.semantics.step` to the loss it describes.

**Budgets** (STYLE.md, point 4). Without a budget the verifier is complete and answers
``wins`` or ``loses``. With a :class:`~plansynth.budget.Budget` it stops once the time or
the memory is used up and answers ``unknown`` with the phase and the reason, never a
guessed ``wins``/``loses``. Memory is what the process gains while verifying (its
resident set, checked every few thousand cells of work) and defaults to
:data:`DEFAULT_MEMORY_MB` when a budget gives none. The per-cell data is kept small so
that a large grid costs only what the search touches: move tables are filled lazily
(end cell, swept cells as indices), the unread obstacles' reachable cells are advanced
one step at a time (only the current set is kept; a set sequence that becomes periodic,
as they do once an obstacle's reach saturates, is not recomputed) and each step's
danger is a packed bitmap. On a large grid the tables and sets are numpy arrays; on a
small one (:data:`PYTHON_CELLS`) they are dicts and integer bitsets, so that verifying
a small problem does not import numpy (a tenth of a second of a ``plansynth grid
solve``); both give the same verdicts and counterexamples (tests/grid/test_verify.py).

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [4, 1],
...     "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}]})
>>> verify(p, parse_program("1"), 3).wins
False
>>> print(verify(p, parse_program("1"), 3).counterexample.reason)
collision at step 1 in cell (2, 0) with obstacle 0
>>> verify(p, parse_program("1"), 3, budget=Budget(seconds=60)).status.value
'loses'
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from itertools import product

from typing import Any

from plansynth.budget import Budget
from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.programs import (
    App,
    Const,
    ProgramSyntaxError,
    Term,
    Var,
    check_program,
    compile_program,
    evaluate,
    variables_of,
)
from plansynth.grid.semantics import State, initial_state, obstacle_move, robot_end, robot_move, step

#: Memory (MB) a budgeted verification may add to the process when its budget gives none
#: (the native engine's default too).
DEFAULT_MEMORY_MB = 4096

#: Grids of at most this many cells, with at most :data:`PYTHON_OBSTACLES` obstacles,
#: keep their move tables and reachable sets in plain Python (dicts, integer bitsets):
#: on them the search itself takes milliseconds and numpy's import (0.1-0.15 s) would
#: dominate a ``plansynth grid solve``. Larger ones use numpy arrays (see ``tables`` of
#: :func:`verify`); the two representations give the same verdicts and counterexamples.
PYTHON_CELLS = 4096
PYTHON_OBSTACLES = 8

np: Any = None  # numpy, imported by _numpy() for the grids that use its tables


def _numpy() -> Any:
    global np
    if np is None:
        import numpy

        np = numpy
    return np


class VerifyStatus(str, Enum):
    """The verifier's answer. ``unknown`` (the budget ran out) is never ``loses``.

    There is deliberately no truthiness.
    """

    WINS = "wins"
    LOSES = "loses"
    UNKNOWN = "unknown"

    def __bool__(self) -> bool:
        raise TypeError("VerifyStatus has no truth value; compare with VerifyStatus.WINS etc.")


class VerdictUnknown(Exception):
    """Raised by :attr:`Verdict.wins` on an ``unknown`` verdict: it neither wins nor loses."""


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

    ``status`` is exact when it is ``wins`` or ``loses``; ``unknown`` only when a budget
    ran out, with ``phase`` (where) and ``reason`` ("time" or "memory", with figures) in
    ``message``. When it loses, ``counterexample`` shows a losing run.
    ``states_explored`` counts the (t, robot, read obstacles) nodes expanded.
    """

    status: VerifyStatus
    steps: int
    counterexample: Counterexample | None
    states_explored: int
    seconds: float
    phase: str | None = None
    message: str | None = None

    @property
    def wins(self) -> bool:
        """True if the controller wins, False if it loses; :class:`VerdictUnknown` if the
        budget ran out (check ``status`` first when a budget was given)."""
        if self.status is VerifyStatus.UNKNOWN:
            raise VerdictUnknown(self.message or "the verifier gave no answer")
        return self.status is VerifyStatus.WINS


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


def verify(
    problem: GridProblem,
    program: Term,
    steps: int,
    *,
    probe_nodes: int | None = None,
    budget: Budget | None = None,
    tables: str | None = None,
) -> Verdict:
    """Decide exactly whether ``program`` wins ``problem`` at path length ``steps``.

    ``probe_nodes`` bounds the depth-first probe for a quick counterexample that runs
    before the exhaustive search (default :data:`PROBE_NODES`; 0 disables it). It
    changes only the time taken and which counterexample is found, never the answer.

    ``budget`` bounds the time (``seconds``) and the memory (``memory_mb``, default
    :data:`DEFAULT_MEMORY_MB`) the verification may use; once either is used up the
    verdict is ``unknown`` naming the phase (see the module docstring). Without a
    budget the search runs to its exact answer.

    ``tables`` chooses how move tables and the unread obstacles' reachable sets are
    stored: ``"python"`` (dicts and integer bitsets, no numpy import) or ``"numpy"``
    (lazily filled arrays, for large grids); by default ``"python"`` on grids of at most
    :data:`PYTHON_CELLS` cells with at most :data:`PYTHON_OBSTACLES` obstacles. It changes
    only the time and memory taken, never the verdict or the counterexample.

    Raises :class:`~plansynth.grid.programs.ProgramSyntaxError` when the program is not
    a controller of the problem's grammar (for example a move number with no move).
    """
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    check_controller(problem, program)
    if tables is None:
        small = problem.width * problem.height <= PYTHON_CELLS and len(problem.obstacles) <= PYTHON_OBSTACLES
        tables = "python" if small else "numpy"
    elif tables not in ("python", "numpy"):
        raise ValueError(f"tables must be 'python' or 'numpy', got {tables!r}")
    t0 = time.perf_counter()
    meter = _Meter(budget)
    search = None
    try:
        search = _Search(problem, program, steps, PROBE_NODES if probe_nodes is None else probe_nodes, meter,
                         tables == "numpy")
        loss = search.run()
        meter.phase = "building the counterexample"
        cex = None if loss is None else search.counterexample(loss)
    except _OutOfBudget as out:
        explored = 0 if search is None else search.explored
        return Verdict(VerifyStatus.UNKNOWN, steps, None, explored, time.perf_counter() - t0, out.phase,
                       f"the verifier's budget ran out in {out.phase}: {out.reason}")
    except MemoryError:
        explored = 0 if search is None else search.explored
        return Verdict(VerifyStatus.UNKNOWN, steps, None, explored, time.perf_counter() - t0, meter.phase,
                       f"the verifier's budget ran out in {meter.phase}: out of memory")
    status = VerifyStatus.WINS if loss is None else VerifyStatus.LOSES
    return Verdict(status, steps, cex, search.explored, time.perf_counter() - t0)


class _OutOfBudget(Exception):
    def __init__(self, phase: str, reason: str) -> None:
        self.phase = phase
        self.reason = reason
        super().__init__(f"{phase}: {reason}")


def _rss_bytes() -> int:
    """The process's resident set now (Linux ``/proc/self/statm``; else its peak)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * _PAGE
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


try:
    import os as _os

    _PAGE = _os.sysconf("SC_PAGE_SIZE")
except (ValueError, OSError, AttributeError):  # pragma: no cover
    _PAGE = 4096


class _Meter:
    """The budget of one verification: time and memory, checked every :data:`CHECK_WORK`
    units of work (cells handled), so that neither overshoots by more than a few
    milliseconds or megabytes."""

    #: Work between two checks, in units of about a microsecond: a cell handled in Python
    #: is 1, a call of the semantics :data:`SEMANTICS_CALL`.
    CHECK_WORK = 1 << 14
    SEMANTICS_CALL = 8

    def __init__(self, budget: Budget | None) -> None:
        self.clock = None if budget is None else budget.clock()
        mb = None if budget is None else (budget.memory_mb or DEFAULT_MEMORY_MB)
        self.limit = None if mb is None else mb << 20
        self.base = _rss_bytes() if self.limit is not None else 0
        self.work = 0
        self.phase = "setting up"

    def tick(self, work: int = 1) -> None:
        if self.clock is None:
            return
        self.work += work
        if self.work >= self.CHECK_WORK:
            self.work = 0
            self.check()

    def check(self) -> None:
        if self.clock is None:
            return
        if self.clock.out_of_time():
            raise _OutOfBudget(self.phase, f"time ({self.clock.budget.seconds:g} s)")
        if self.limit is not None:
            used = _rss_bytes() - self.base
            if used > self.limit:
                raise _OutOfBudget(self.phase, f"memory (it grew by {used >> 20} MB, over the budget of "
                                   f"{self.limit >> 20} MB)")


# -- the search ------------------------------------------------------------------------

#: A set of cells (indices ``y * width + x``) one read obstacle may occupy.
Cells = frozenset[int]
Sets = tuple[Cells, ...]


class _Node:
    """An abstract state at one time: the robot's cell and a product of read-obstacle
    cell sets, every combination of which is reachable with the robot there.

    ``parents`` lists (node, part, robot move) one time earlier whose images make up
    ``sets``; counterexamples are rebuilt through them.
    """

    __slots__ = ("r", "sets", "parents")

    def __init__(self, r: int, sets: Sets, parents: list[tuple["_Node", Sets, int]]) -> None:
        self.r = r
        self.sets = sets
        self.parents = parents


@dataclass(frozen=True)
class _Loss:
    """Where the search lost: in ``node`` (at time ``t``), on ``part`` with robot move
    ``move``. ``kind`` is "wall", "unread", "read" (read obstacle slot ``obstacle`` can
    collide) or "doomed" (the robot can no longer stand on the goal at time ``steps``;
    ``part`` is the whole node and no move is taken at ``t``)."""

    kind: str
    t: int
    node: _Node
    part: Sets
    move: int = -1
    obstacle: int = -1


_UNDECIDED = None

#: Expansions the depth-first probe may spend before the exact layered search starts.
PROBE_NODES = 500


class _ProbeExhausted(Exception):
    pass


class _Search:
    """Breadth-first exploration of (t, robot cell, read obstacles' cell sets).

    Given the robot's history, the read obstacles' possible positions form a product
    set: the obstacles move independently, and the image of a product set under their
    moves is again one. The only thing that breaks products is the program's choice,
    which depends on the read coordinates; so each set is evaluated with intervals and
    split on an undecided comparison until the choice is constant on every part
    (reduction 3 of the module docstring; all-singleton sets are plain enumeration).
    On each part, a read obstacle can collide iff one of its cells has a move sweeping
    the robot's swept cells, exactly as for unread obstacles.

    Time is explored layer by layer (so the loss found is a shortest one, unless the
    depth-first probe run first already found one). The robot's future depends only on its cell and the obstacles' cells, not on how it got
    there, so the products reaching the same (t, robot cell) are merged where they
    differ in one factor (S x T and S' x T make (S | S') x T) or one contains another.
    """

    def __init__(self, problem: GridProblem, program: Term, steps: int, probe_nodes: int, meter: "_Meter",
                 use_numpy: bool = True) -> None:
        self.probe_nodes = probe_nodes
        self.problem = problem
        self.program = program
        self.steps = steps
        self.meter = meter
        self.width = w = problem.width
        self.n_cells = n = problem.width * problem.height
        self.walls = frozenset(c[1] * w + c[0] for c in problem.walls)
        # Move tables over cell indices, filled lazily: a 1000 x 1000 grid has a million
        # cells and the robot and obstacles usually visit few of them. Obstacles with the
        # same moves share a table (a move's effect depends only on the move and walls).
        if use_numpy:
            _numpy()
        table = _Table if use_numpy else _PyTable
        self.robot = table(problem, lambda c, k: robot_move(problem, c, k), problem.robot.moves, meter)
        tables: dict[tuple, Any] = {}
        self.obstacle = []
        for i, o in enumerate(problem.obstacles):
            if o.moves not in tables:
                tables[o.moves] = table(problem, lambda c, k, i=i: obstacle_move(problem, i, c, k), o.moves, meter)
            self.obstacle.append(tables[o.moves])
        self.goal = self.index(problem.robot.goal)
        self.read = read_obstacles(program, len(problem.obstacles))
        self.unread = tuple(i for i in range(len(problem.obstacles)) if i not in self.read)
        self.explored = 0
        meter.phase = "the unread obstacles' reachable cells"
        self.unread_reach = (_UnreadReach if use_numpy else _PyUnreadReach)(self, self.unread)
        meter.phase = "the robot's distances to the goal"
        self.distance = self._goal_distances() if use_numpy else self._goal_distances_py()
        # Per read obstacle: cell set -> (successor set, every cell it can sweep).
        self._image: list[dict[Cells, tuple[Cells, Cells]]] = [{} for _ in self.read]
        self._bounds: dict[Cells, tuple[int, int, int, int]] = {}
        # (robot, sets) -> parts on which the program's choice is constant, with it.
        self._parts: dict[tuple[int, tuple[Cells, ...]], tuple[tuple[tuple[Cells, ...], int], ...]] = {}

    def index(self, c: Cell) -> int:
        return c[1] * self.width + c[0]

    def danger(self, t: int) -> bytes:
        """Packed bitmap (bit ``c`` of byte ``c >> 3``) of every cell some unread obstacle
        can sweep at step ``t``."""
        return self.unread_reach.danger(t)

    def goal_distance(self, r: int) -> int:
        """Fewest robot moves from cell ``r`` to the goal (obstacles and walls ignored;
        ``steps + 1`` when more than ``steps``)."""
        return int(self.distance[r])

    def _goal_distances_py(self) -> list[int]:
        """:meth:`_goal_distances` in plain Python (the small grids' tables)."""
        p = self.problem
        w, h, far = p.width, p.height, self.steps + 1
        self.meter.check()
        dist = [far] * self.n_cells
        dist[self.goal] = 0
        frontier = [self.goal]
        for d in range(1, far):
            if not frontier:
                break
            found: set[int] = set()
            for k, m in enumerate(p.robot.moves):
                dx, dy = m.to
                for e in frontier:
                    cx, cy = e % w - dx, e // w - dy
                    if 0 <= cx < w and 0 <= cy < h:
                        c = cy * w + cx
                        if dist[c] == far and robot_end(p, (cx, cy), k) == (e % w, e // w):
                            found.add(c)
            for c in found:
                dist[c] = d
            frontier = sorted(found)
            self.meter.tick(len(found) // 8 + 1)
        return dist

    def _goal_distances(self) -> np.ndarray:
        """Breadth-first search back from the goal over the robot's moves, to depth ``steps``
        (vectorised over each frontier; move rows computed only for the cells met)."""
        p = self.problem
        w, h = p.width, p.height
        self.meter.check()
        dist = np.full(self.n_cells, self.steps + 1, dtype=np.int32)
        dist[self.goal] = 0
        frontier = np.array([self.goal], dtype=np.int64)
        ends = self.robot.end
        for d in range(1, self.steps + 1):
            if frontier.size == 0:
                break
            ex, ey = frontier % w, frontier // w
            found = []
            for k, m in enumerate(p.robot.moves):
                cx, cy = ex - m.to[0], ey - m.to[1]
                ok = (cx >= 0) & (cx < w) & (cy >= 0) & (cy < h)
                cand, target = (cy * w + cx)[ok], frontier[ok]
                fresh = dist[cand] > self.steps
                cand, target = cand[fresh], target[fresh]
                self.robot.fill(cand)
                found.append(cand[ends[k, cand] - 1 == target])
            nxt = np.concatenate(found)
            nxt = np.unique(nxt) if nxt.size < 4096 else np.flatnonzero(_bitmap(nxt, self.n_cells))
            nxt = nxt[dist[nxt] > self.steps]
            dist[nxt] = d
            frontier = nxt
            self.meter.tick(int(nxt.size) // 8 + 1)
        return dist

    # -- read obstacles: images, bounds, and the program's choice on a product set ----

    def image(self, j: int, cells: Cells) -> tuple[Cells, Cells]:
        """Successor set and swept cells of read obstacle number ``j`` (slot) on ``cells``."""
        cache = self._image[j]
        if cells not in cache:
            self.meter.tick(len(cells))
            cache[cells] = _image(self.obstacle[self.read[j]], cells)
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
        # Splits are hierarchical, so the parts with one move usually reassemble into
        # fewer products (often the whole set, when both branches of an undecided ite
        # choose alike); fewer, larger parts keep the next layer small.
        by_move: dict[int, dict[Sets, list]] = {}
        for part, k in out:
            by_move.setdefault(k, {})[part] = []
        result = tuple((part, k) for k, group in by_move.items() for part in _merge(group))
        self._parts[key] = result
        return result

    def _split(
        self, atom: App, r: int, part: tuple[Cells, ...], env: dict[str, tuple[int, int]], known: dict[int, bool]
    ) -> list[tuple[tuple[Cells, ...], dict[int, bool]]]:
        """Split ``part`` so that ``atom`` (undecided on its intervals) is decided on each piece."""
        self.meter.tick(sum(map(len, part)))
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
        """None if the controller wins, else a loss (a shortest one unless the probe found one)."""
        r0 = self.index(self.problem.robot.start)
        s0 = tuple(frozenset((self.index(self.problem.obstacles[i].start),)) for i in self.read)
        if self.read and self.probe_nodes > 0:
            self.meter.phase = "the depth-first probe"
            try:
                return self._probe(_Node(r0, s0, []), 0, set())
            except _ProbeExhausted:
                pass
        return self._layers(_Node(r0, s0, []))

    def _step(self, t: int, node: _Node, part: Sets, k: int) -> _Loss | tuple[int, list[Cells]]:
        """Take move ``k`` on ``part`` at time ``t``: a loss, or (robot end, successor sets)."""
        self.explored += 1
        self.meter.tick(8)
        r_end, r_swept = self.robot[node.r][k]
        if not self.walls.isdisjoint(r_swept):
            return _Loss("wall", t, node, part, k)
        danger = self.danger(t)
        if any(danger[c >> 3] >> (c & 7) & 1 for c in r_swept):
            return _Loss("unread", t, node, part, k)
        nxt = []
        for j, cells in enumerate(part):
            succ, swept = self.image(j, cells)
            if not swept.isdisjoint(r_swept):
                return _Loss("read", t, node, part, k, j)
            nxt.append(succ)
        return r_end, nxt

    def _doomed(self, t: int, node: _Node) -> _Loss | None:
        # Whatever the obstacles do, the robot can no longer stand on the goal at time
        # `steps` (at t == steps this is the goal check itself).
        if self.goal_distance(node.r) > self.steps - t:
            return _Loss("doomed", t, node, node.sets)
        return None

    def _layers(self, root: _Node) -> _Loss | None:
        """The exact search: time layer by layer, products merged per (t, robot cell)."""
        layer = [root]
        for t in range(self.steps + 1):
            self.meter.phase = f"the layered search (step {t} of {self.steps})"
            self.meter.check()
            successors: dict[int, dict[Sets, list[tuple[_Node, Sets, int]]]] = {}
            for node in layer:
                loss = self._doomed(t, node)
                if loss is not None:
                    return loss
                if t == self.steps:
                    continue
                for part, k in self.parts(node.r, node.sets):
                    out = self._step(t, node, part, k)
                    if isinstance(out, _Loss):
                        return out
                    r_end, nxt = out
                    successors.setdefault(r_end, {}).setdefault(tuple(nxt), []).append((node, part, k))
            layer = [
                _Node(r, sets, parents) for r, boxes in successors.items() for sets, parents in _merge(boxes).items()
            ]
        return None

    def _probe(self, node: _Node, t: int, safe: set) -> _Loss | None:
        """A cheap depth-first hunt for a loss over single combinations, given up after
        PROBE_NODES expansions (a losing program is often caught long before the exact
        layered search would reach its last layer). Raises _ProbeExhausted when given up."""
        loss = self._doomed(t, node)
        if loss is not None or t == self.steps:
            return loss
        key = (t, node.r, node.sets)
        if key in safe:
            return None
        if self.explored >= self.probe_nodes or t > 500:
            raise _ProbeExhausted
        # Heuristic order: moves that leave the robot farthest from the goal first, and
        # obstacle cells nearest to the robot first.
        robot = self.robot[node.r]
        parts = sorted(self.parts(node.r, node.sets), key=lambda pk: -self.goal_distance(robot[pk[1]][0]))
        for part, k in parts:
            out = self._step(t, node, part, k)
            if isinstance(out, _Loss):
                return out
            r_end, nxt = out
            rx, ry = r_end % self.width, r_end // self.width
            near = lambda c: abs(c % self.width - rx) + abs(c // self.width - ry)  # noqa: E731
            for combo in product(*(sorted(c, key=near) for c in nxt)):
                child = _Node(r_end, tuple(frozenset((c,)) for c in combo), [(node, part, k)])
                loss = self._probe(child, t + 1, safe)
                if loss is not None:
                    return loss
        safe.add(key)
        return None

    # -- counterexamples -------------------------------------------------------------

    def counterexample(self, loss: _Loss) -> Counterexample:
        """Turn a loss into a concrete run of all obstacles, and replay it with step()."""
        p = self.problem
        steps_taken = loss.t if loss.kind == "doomed" else loss.t + 1
        joint: list[list[int]] = [[0] * len(p.obstacles) for _ in range(steps_taken)]
        robot_moves = [0] * steps_taken
        # Cells of the read obstacles at time loss.t (and their moves then, if a step is taken).
        cells = [min(s) for s in loss.part]
        if loss.kind != "doomed":
            robot_moves[loss.t] = loss.move
            r_swept = self.robot[loss.node.r][loss.move][1]
            if loss.kind == "read":
                j = loss.obstacle
                table = self.obstacle[self.read[j]]
                cells[j], joint[loss.t][self.read[j]] = next(
                    (c, k) for c in sorted(loss.part[j]) for k, (_, m) in enumerate(table[c])
                    if not m.isdisjoint(r_swept)
                )
        # Walk back through the parents: a parent part whose image holds the cells, and
        # for each obstacle a cell there with a move into its current cell.
        node, t = loss.node, loss.t
        while t > 0:
            for parent, part, k in node.parents:
                back = self._preimage(part, cells)
                if back is not None:
                    break
            else:  # pragma: no cover - the parents' images make up the node's sets
                raise AssertionError("verifier bug: no parent leads to the losing state")
            t -= 1
            robot_moves[t] = k
            cells = []
            for j, (c, m) in enumerate(back):
                cells.append(c)
                joint[t][self.read[j]] = m
            node = parent
        if loss.kind == "unread":
            # Steer one unread obstacle into the robot's swept cells at the last step.
            for i in self.unread:
                hit = self.unread_reach.hit(i, loss.t, r_swept)
                if hit is not None:
                    for s, k in enumerate(hit):
                        joint[s][i] = k
                    break
            else:  # pragma: no cover - the danger mask promised a hit
                raise AssertionError("verifier bug: no unread obstacle realises the danger mask")
        if loss.kind == "doomed":
            # Any continuation loses: run the program on, every obstacle taking move 0.
            state = _replay(p, robot_moves, joint, self.steps)[0][-1]
            controller = compile_program(self.program, p.variables)
            for _ in range(loss.t, self.steps):
                k = controller(*state.inputs())
                zero = (0,) * len(p.obstacles)
                robot_moves.append(k)
                joint.append(list(zero))
                state, collided = step(p, state, k, zero)
                if collided:
                    break
        moves = tuple(robot_moves)
        obstacle_moves = tuple(tuple(j) for j in joint)
        states, reason = _replay(p, moves, obstacle_moves, self.steps)
        if reason is None:  # pragma: no cover - would mean the search and step() disagree
            raise AssertionError("verifier bug: the counterexample does not lose when replayed")
        return Counterexample(obstacle_moves, states, moves, reason)

    def _preimage(self, part: Sets, cells: list[int]) -> list[tuple[int, int]] | None:
        """Per read obstacle, a (cell in ``part``, move) ending in ``cells``; None if some
        obstacle cannot get there from ``part``."""
        out = []
        for j, target in enumerate(cells):
            table = self.obstacle[self.read[j]]
            found = next(
                ((c, k) for c in sorted(part[j]) for k, (e, _) in enumerate(table[c]) if e == target), None
            )
            if found is None:
                return None
            out.append(found)
        return out

def _merge(boxes: dict[Sets, list]) -> dict[Sets, list]:
    """Merge products that differ in one factor, and drop products inside another.

    The result covers exactly the same combinations; each product keeps the parents
    of the products merged into it.
    """
    if len(boxes) < 2:
        return boxes
    n = len(next(iter(boxes)))
    if len(boxes) > 256 and sum(_volume(b) for b in boxes) <= 4 * len(boxes):
        # Many small overlapping products: fall back to the combinations themselves,
        # so there are never many more products than reachable states.
        single: dict[Sets, list] = {}
        for sets, parents in boxes.items():
            for combo in product(*sets):
                single.setdefault(tuple(frozenset((c,)) for c in combo), []).extend(parents)
        boxes = single
    changed = True
    while changed and len(boxes) > 1:
        changed = False
        for j in range(n):
            groups: dict[Sets, list[Sets]] = {}
            for sets in boxes:
                groups.setdefault(sets[:j] + sets[j + 1 :], []).append(sets)
            if len(groups) == len(boxes):
                continue
            merged: dict[Sets, list] = {}
            for rest, members in groups.items():
                union = frozenset().union(*(m[j] for m in members))
                key = rest[:j] + (union,) + rest[j:]
                parents = merged.setdefault(key, [])
                for m in members:
                    parents.extend(boxes[m])
            boxes = merged
            changed = True
    if 1 < len(boxes) <= 64:
        keys = sorted(boxes, key=lambda s: -sum(len(c) for c in s))
        kept: dict[Sets, list] = {}
        for sets in keys:
            if not any(all(a <= b for a, b in zip(sets, big)) for big in kept):
                kept[sets] = boxes[sets]
        boxes = kept
    return boxes


class _Table:
    """The moves of one agent over cell indices, filled lazily from
    :mod:`plansynth.grid.semantics` (only for the cells the search meets).

    ``end[k, c]`` is 1 + the end index of move ``k`` from cell ``c`` (0: not computed
    yet) and ``swept[k][c]`` its swept cell indices (padded by repeating the first one);
    ``table[c]`` is the row as Python values, ``(end, frozenset of swept cells)`` per
    move, and ``table.successors[c]`` its distinct pairs.
    """

    def __init__(self, problem: GridProblem, move, moves: Sequence, meter: "_Meter") -> None:
        self.width = problem.width
        self.move = move
        self.n_moves = len(moves)
        self.meter = meter
        n = problem.width * problem.height
        meter.check()
        self.end = np.zeros((self.n_moves, n), dtype=np.int32)
        self.swept = [np.zeros((n, len(m.offsets())), dtype=np.int32) for m in moves]
        self.rows: dict[int, tuple[tuple[int, Cells], ...]] = {}
        self.successors = _Distinct(self)

    def fill(self, cells: np.ndarray) -> None:
        """Compute the moves of every cell of ``cells`` (an index array) not yet computed."""
        if cells.size == 0:
            return
        missing = cells[self.end[0, cells] == 0]  # callers pass distinct cells
        for i in range(0, missing.size, self.CHUNK):
            self.meter.tick(self.CHUNK * self.n_moves * _Meter.SEMANTICS_CALL)
            self._fill(missing[i : i + self.CHUNK])

    #: Cells computed between two budget checks.
    CHUNK = 64

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

    def __getitem__(self, c: int) -> tuple[tuple[int, Cells], ...]:
        row = self.rows.get(c)
        if row is None:
            if self.end[0, c] == 0:
                self.fill(np.array([c]))
            row = self.rows[c] = tuple(
                (int(self.end[k, c]) - 1, frozenset(self.swept[k][c].tolist())) for k in range(self.n_moves)
            )
        return row


class _Distinct:
    """``successors[c]``: the distinct (end, swept cells) pairs of a :class:`_Table` row."""

    def __init__(self, rows: _Table) -> None:
        self.of = rows
        self.cache: dict[int, tuple[tuple[int, Cells], ...]] = {}

    def __getitem__(self, ci: int) -> tuple[tuple[int, Cells], ...]:
        row = self.cache.get(ci)
        if row is None:
            row = self.cache[ci] = tuple(dict.fromkeys(self.of[ci]))
        return row


class _UnreadReach:
    """Reduction 2 of the module docstring, a step at a time: the cells each unread
    obstacle can occupy at time t (a sorted index array; only the current one is kept)
    and, per step, the packed bitmap of every cell some unread obstacle can sweep then.

    A set sequence is a function of its current set, so once an obstacle's set equals
    the one one or two steps earlier (a saturated reach, with or without ``stay``) its
    sweeps repeat with that period and are no longer recomputed. Identical bitmaps are
    stored once.
    """

    def __init__(self, search: "_Search", unread: tuple[int, ...]) -> None:
        self.search = search
        self.n = search.n_cells
        self.zero = bytes((self.n + 7) // 8)
        self.obstacles = [
            _Reach(search.obstacle[i], np.array([search.index(search.problem.obstacles[i].start)], dtype=np.int32))
            for i in unread
        ]
        self._danger: list[bytes] = []
        self._distinct: dict[bytes, bytes] = {self.zero: self.zero}

    def danger(self, t: int) -> bytes:
        while len(self._danger) <= t:
            self._advance()
        return self._danger[t]

    def _advance(self) -> None:
        t = len(self._danger)
        if not self.obstacles:
            self._danger.append(self.zero)
            return
        meter = self.search.meter
        phase = meter.phase
        meter.phase = f"the unread obstacles' reachable cells (step {t})"
        total = None
        for ob in self.obstacles:
            packed = ob.sweeps(t, self.n, meter)
            total = packed if total is None else total | packed
        b = total.tobytes()
        self._danger.append(self._distinct.setdefault(b, b))
        meter.phase = phase

    def hit(self, i: int, t: int, r_swept: Cells) -> list[int] | None:
        """Moves of unread obstacle ``i`` for steps 0..t whose last one sweeps a cell of
        ``r_swept`` (None if it cannot). Replays its sets from the start, keeping them
        packed (cells / 8 bytes a step), and walks back through them."""
        s = self.search
        table = s.obstacle[i]
        ob = _Reach(table, np.array([s.index(s.problem.obstacles[i].start)], dtype=np.int32))
        history: list[bytes] = []
        for step_t in range(t + 1):
            s.meter.tick(int(ob.cur.size))
            history.append(np.packbits(_bitmap(ob.cur, self.n), bitorder="little").tobytes())
            if step_t < t:
                ob.cur = ob.successors(ob.cur, s.meter)
        want = np.array(sorted(r_swept), dtype=np.int64)
        cur = ob.cur
        table.fill(cur)
        for k in range(table.n_moves):
            meets = np.isin(table.swept[k][cur], want).any(axis=1)
            if meets.any():
                c = int(cur[np.argmax(meets)])
                moves = [k]
                for step_t in range(t - 1, -1, -1):
                    cells = np.flatnonzero(np.unpackbits(np.frombuffer(history[step_t], dtype=np.uint8),
                                                         count=self.n, bitorder="little"))
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


class _Reach:
    """One unread obstacle's reachable cells, advanced step by step (see :class:`_UnreadReach`)."""

    def __init__(self, table: _Table, start: np.ndarray) -> None:
        self.table = table
        self.cur = start
        self.prev: np.ndarray | None = None
        self.packed: list[np.ndarray] = []  # the sweeps of the last steps (at most 2)
        self.period: int | None = None
        self.t = 0

    def successors(self, cells: np.ndarray, meter: "_Meter") -> np.ndarray:
        meter.tick(int(cells.size) * self.table.n_moves)
        self.table.fill(cells)
        ends = (self.table.end[:, cells] - 1).ravel()
        if ends.size < 4096:
            return np.unique(ends)
        return np.flatnonzero(_bitmap(ends, self.table.end.shape[1])).astype(np.int32)  # 4 bytes a cell

    def sweeps(self, t: int, n: int, meter: "_Meter") -> np.ndarray:
        """The packed bitmap of the cells this obstacle can sweep at step ``t`` (called
        for t = 0, 1, 2, ... in order)."""
        assert t == self.t, "sweeps are advanced one step at a time"
        self.t += 1
        if self.period is not None:
            out = self.packed[-self.period]
            self.packed = (self.packed + [out])[-2:]
            return out
        cells = self.cur
        meter.tick(int(cells.size) * self.table.n_moves)
        self.table.fill(cells)
        bitmap = np.zeros(n, dtype=bool)
        for col in self.table.swept:
            bitmap[col[cells].ravel()] = True
        out = np.packbits(bitmap, bitorder="little")
        self.packed = (self.packed + [out])[-2:]
        nxt = self.successors(cells, meter)
        if np.array_equal(nxt, cells):
            self.period = 1
        elif self.prev is not None and np.array_equal(nxt, self.prev):
            self.period = 2
        self.prev, self.cur = cells, nxt
        return out


class _PyTable:
    """:class:`_Table` in plain Python, for small grids: ``table[c]`` is the row of cell
    ``c`` (``(end, frozenset of swept cells)`` per move), computed from the semantics on
    first use; ``masks(c)`` the same row as two integer bitsets (every end cell, every
    swept cell), for :class:`_PyReach`."""

    def __init__(self, problem: GridProblem, move, moves: Sequence, meter: "_Meter") -> None:
        self.width = problem.width
        self.move = move
        self.n_moves = len(moves)
        self.meter = meter
        self.rows: dict[int, tuple[tuple[int, Cells], ...]] = {}
        self._masks: dict[int, tuple[int, int]] = {}
        self.successors = _Distinct(self)

    def __getitem__(self, c: int) -> tuple[tuple[int, Cells], ...]:
        row = self.rows.get(c)
        if row is None:
            self.meter.tick(self.n_moves * _Meter.SEMANTICS_CALL)
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


def _cells_of(mask: int) -> list[int]:
    """The cell indices of an integer bitset, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return out


class _PyReach:
    """:class:`_Reach` in plain Python: the current reachable set is an integer bitset."""

    def __init__(self, table: _PyTable, start: int) -> None:
        self.table = table
        self.cur = 1 << start
        self.prev: int | None = None
        self.packed: list[int] = []
        self.period: int | None = None
        self.t = 0

    def successors(self, cells: int, meter: "_Meter") -> int:
        out = 0
        masks = self.table.masks
        listed = _cells_of(cells)
        meter.tick(len(listed) * self.table.n_moves)
        for c in listed:
            out |= masks(c)[0]
        return out

    def sweeps(self, t: int, meter: "_Meter") -> int:
        """The bitset of the cells this obstacle can sweep at step ``t`` (t = 0, 1, ...)."""
        assert t == self.t, "sweeps are advanced one step at a time"
        self.t += 1
        if self.period is not None:
            out = self.packed[-self.period]
            self.packed = (self.packed + [out])[-2:]
            return out
        cells = self.cur
        listed = _cells_of(cells)
        meter.tick(len(listed) * self.table.n_moves)
        masks = self.table.masks
        out = 0
        for c in listed:
            out |= masks(c)[1]
        self.packed = (self.packed + [out])[-2:]
        nxt = self.successors(cells, meter)
        if nxt == cells:
            self.period = 1
        elif self.prev is not None and nxt == self.prev:
            self.period = 2
        self.prev, self.cur = cells, nxt
        return out


class _PyUnreadReach:
    """:class:`_UnreadReach` in plain Python (integer bitsets); ``danger(t)`` is the same
    packed bitmap (bit ``c`` of byte ``c >> 3``)."""

    def __init__(self, search: "_Search", unread: tuple[int, ...]) -> None:
        self.search = search
        self.n_bytes = (search.n_cells + 7) // 8
        self.zero = bytes(self.n_bytes)
        self.obstacles = [_PyReach(search.obstacle[i], search.index(search.problem.obstacles[i].start)) for i in unread]
        self._danger: list[bytes] = []
        self._distinct: dict[bytes, bytes] = {self.zero: self.zero}

    def danger(self, t: int) -> bytes:
        while len(self._danger) <= t:
            self._advance()
        return self._danger[t]

    def _advance(self) -> None:
        t = len(self._danger)
        if not self.obstacles:
            self._danger.append(self.zero)
            return
        meter = self.search.meter
        phase = meter.phase
        meter.phase = f"the unread obstacles' reachable cells (step {t})"
        total = 0
        for ob in self.obstacles:
            total |= ob.sweeps(t, meter)
        b = total.to_bytes(self.n_bytes, "little")
        self._danger.append(self._distinct.setdefault(b, b))
        meter.phase = phase

    def hit(self, i: int, t: int, r_swept: Cells) -> list[int] | None:
        """As :meth:`_UnreadReach.hit`, choosing the same moves (lowest move, then lowest
        cell, at each step)."""
        s = self.search
        table = s.obstacle[i]
        ob = _PyReach(table, s.index(s.problem.obstacles[i].start))
        history: list[int] = []
        for step_t in range(t + 1):
            history.append(ob.cur)
            if step_t < t:
                ob.cur = ob.successors(ob.cur, s.meter)
        cur = _cells_of(ob.cur)
        for k in range(table.n_moves):
            c = next((c for c in cur if not table[c][k][1].isdisjoint(r_swept)), None)
            if c is not None:
                moves = [k]
                for step_t in range(t - 1, -1, -1):
                    cells = _cells_of(history[step_t])
                    s.meter.tick(len(cells))
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


def _bitmap(cells: np.ndarray, n: int) -> np.ndarray:
    b = np.zeros(n, dtype=bool)
    b[cells] = True
    return b


def _volume(sets: Sets) -> int:
    v = 1
    for c in sets:
        v *= len(c)
    return v


def _image(table: _Table, cells: Cells) -> tuple[Cells, Cells]:
    """The cells reachable in one move from ``cells`` and every cell swept on the way."""
    succ = table.successors
    nxt: set[int] = set()
    swept: set[int] = set()
    for c in cells:
        for end, sw in succ[c]:
            nxt.add(end)
            swept |= sw
    return frozenset(nxt), frozenset(swept)


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

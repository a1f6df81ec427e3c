"""The grid problem value: the model of Chasins & Newcomb, SYNT 2016, Section 3.1 (a
robot and adversarial obstacles on a grid, each moving by its own motion primitives),
with the plansynth extensions (objectives, periods, glitches, keep-out cells), the
documented limits, and the checks a problem passes when it is made, from a file or in
code. The loader is :mod:`plansynth.grid.problem`, which exports these names too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from plansynth.errors import InvalidProblem
from plansynth.grid.objective import CollisionRule, ObjectiveKind, Schedule
from plansynth.io import MAX_NAME_LENGTH

Cell = tuple[int, int]

#: Default upper end of the path-length search when a file gives neither ``steps`` nor
#: ``max_steps`` (the spec's example uses 40).
DEFAULT_MAX_STEPS = 40

#: Documented limits (README, "Formats and extensions"), checked at the door so that no
#: input can make plansynth allocate beyond what a budget can stop: the grid's sides,
#: the path length ``steps``/``max_steps``, the number of obstacles, and the offsets of
#: a custom move (a move jumps at most across the largest grid).
MAX_GRID_SIDE = 1000
MAX_STEPS = 1000
MAX_OBSTACLES = 100
MAX_MOVES = 100
MAX_VIA = 100
#: Limits of the plansynth extensions: an obstacle's ``period`` and ``glitches``, the
#: number of ``goals`` of a recurrence objective, cells in an obstacle's ``keep_out``.
MAX_PERIOD = 100
MAX_GLITCHES = 1000
MAX_GOALS = 100
MAX_KEEP_OUT = 100_000


@dataclass(frozen=True)
class Move:
    """A motion primitive: final offset ``to`` and intermediate offsets ``via``.

    The cells an agent at ``p`` sweeps are ``p``, ``p + to`` and ``p + v`` for ``v`` in
    ``via`` (spec, Semantics).
    """

    name: str
    to: Cell
    via: tuple[Cell, ...] = ()

    def offsets(self) -> tuple[Cell, ...]:
        """Every offset swept, the start (0, 0) first, without repeats."""
        out: list[Cell] = [(0, 0)]
        for o in (self.to, *self.via):
            if o not in out:
                out.append(o)
        return tuple(out)

    def to_spec(self) -> str | dict[str, Any]:
        """The move as written in a problem file (a built-in name where possible)."""
        if BUILTIN_MOVES.get(self.name) == self:
            return self.name
        d: dict[str, Any] = {"name": self.name, "to": list(self.to)}
        if self.via:
            d["via"] = [list(v) for v in self.via]
        return d


BUILTIN_MOVES: dict[str, Move] = {
    m.name: m
    for m in (
        Move("stay", (0, 0)),
        Move("up", (0, 1)),
        Move("down", (0, -1)),
        Move("right", (1, 0)),
        Move("left", (-1, 0)),
        Move("up-right", (1, 1)),
        Move("up-left", (-1, 1)),
        Move("down-right", (1, -1)),
        Move("down-left", (-1, -1)),
    )
}


@dataclass(frozen=True)
class Robot:
    """The robot: ``goal`` for the objectives ``exact`` and ``reach``, ``goals`` (visited
    in this order, forever) for ``recurrence``, neither for ``safety``."""

    start: Cell
    goal: Cell | None
    moves: tuple[Move, ...]
    goals: tuple[Cell, ...] = ()


@dataclass(frozen=True)
class Obstacle:
    """An obstacle (spec: grid-problem.md; the fields after ``moves`` are plansynth's).

    ``size`` (w, h): it covers the block of cells ``(x + a, y + b)``, 0 <= a < w,
    0 <= b < h, of its position (x, y). ``period``, ``schedule``, ``phase`` and
    ``glitches``: when it may change its cell (:class:`~plansynth.grid.objective.Schedule`;
    ``phase`` None means ``period - 1``). ``keep_out``: cells its block never covers (a
    move onto one leaves it where it is, as a wall does)."""

    start: Cell
    moves: tuple[Move, ...]
    size: Cell = (1, 1)
    period: int = 1
    schedule: Schedule = Schedule.REST
    phase: int | None = None
    glitches: int = 0
    keep_out: frozenset[Cell] = frozenset()

    @property
    def initial_phase(self) -> int:
        return self.period - 1 if self.phase is None else self.phase

    @property
    def periodic(self) -> bool:
        """Whether the controller reads its wait counter ``o<i>p`` (period > 1)."""
        return self.period > 1

    @property
    def glitching(self) -> bool:
        """Whether the controller reads its glitches left ``o<i>g`` (glitches > 0)."""
        return self.glitches > 0

    @property
    def plain(self) -> bool:
        """The paper's obstacle: one cell, moving every step, no cells kept out."""
        return self.size == (1, 1) and self.period == 1 and not self.keep_out

    def block(self, p: Cell) -> tuple[Cell, ...]:
        """The cells it covers at position ``p``."""
        w, h = self.size
        return tuple((p[0] + a, p[1] + b) for b in range(h) for a in range(w))


@dataclass(frozen=True)
class GridProblem:
    """A reactive grid problem (spec: grid-problem.md). Immutable and validated.

    ``steps`` fixes the path length l; otherwise l is searched in 1..``max_steps``.
    ``source`` is the file it was read from (for messages), ``name`` a short label.
    """

    width: int
    height: int
    robot: Robot
    obstacles: tuple[Obstacle, ...] = ()
    walls: frozenset[Cell] = frozenset()
    steps: int | None = None
    max_steps: int | None = None
    name: str = "problem"
    source: str | None = field(default=None, compare=False)
    objective: ObjectiveKind = ObjectiveKind.EXACT
    fair: bool = False
    collision: CollisionRule = CollisionRule.SWEEP

    def __post_init__(self) -> None:
        _validate(self)

    # -- derived views -------------------------------------------------------------
    @property
    def variables(self) -> tuple[str, ...]:
        """Controller inputs in order: ``rx ry``, then per obstacle ``o<i>x o<i>y`` and,
        where the game depends on them, its wait counter ``o<i>p`` (period > 1) and its
        glitches left ``o<i>g``; then the mode ``m`` (recurrence with two or more goals)
        and the fairness counter ``f`` (``fair`` with two or more obstacles). A paper
        problem has ``rx ry o0x o0y o1x o1y ...`` (spec)."""
        names = ["rx", "ry"]
        for i, o in enumerate(self.obstacles):
            names += [f"o{i}x", f"o{i}y"]
            if o.periodic:
                names.append(f"o{i}p")
            if o.glitching:
                names.append(f"o{i}g")
        if self.mode_count > 1:
            names.append("m")
        if self.fair_count > 1:
            names.append("f")
        return tuple(names)

    @property
    def mode_count(self) -> int:
        """Values of the mode m: the number of goals of a recurrence objective, else 1."""
        return len(self.robot.goals) if self.objective is ObjectiveKind.RECURRENCE else 1

    @property
    def fair_count(self) -> int:
        """Values of the fairness counter f: the number of obstacles under ``fair``, else 1."""
        return len(self.obstacles) if self.fair and len(self.obstacles) > 1 else 1

    @property
    def stateful(self) -> bool:
        """Whether some obstacle has a wait counter or glitches (a state beyond its cell)."""
        return any(o.periodic or o.glitching for o in self.obstacles)

    @property
    def paper_model(self) -> bool:
        """The paper's model (Chasins & Newcomb, SYNT 2016, Section 3.1): the exact-l
        objective, swept-cell collisions and plain obstacles. Everything plansynth added
        before the objectives (walls, custom moves) is inside it."""
        return (
            self.objective is ObjectiveKind.EXACT
            and self.collision is CollisionRule.SWEEP
            and all(o.plain and not o.glitching for o in self.obstacles)
        )

    @property
    def max_constant(self) -> int:
        """d - 1, the largest constant of the grammar: d = max(width, height), or the
        range of an extra input (a period, glitches + 1, the number of goals) if larger."""
        extra = [o.period for o in self.obstacles] + [o.glitches + 1 for o in self.obstacles]
        return max([self.width, self.height, self.mode_count, self.fair_count, *extra]) - 1

    def path_lengths(self) -> range:
        """The path lengths l to try, in order (none for safety and recurrence)."""
        if not self.objective.bounded:
            return range(0)
        if self.steps is not None:
            return range(self.steps, self.steps + 1)
        return range(1, (self.max_steps or DEFAULT_MAX_STEPS) + 1)

    def in_grid(self, c: Cell) -> bool:
        return 0 <= c[0] < self.width and 0 <= c[1] < self.height

    def with_steps(self, steps: int | None) -> GridProblem:
        """The same problem with a fixed path length."""
        from dataclasses import replace

        return replace(self, steps=steps)

    def to_dict(self) -> dict[str, Any]:
        """The problem as a spec document; ``grid_problem_from_dict`` reads it back.
        plansynth's keys are written only where they differ from their defaults, so a
        paper problem's document is the shared format's."""
        robot: dict[str, Any] = {"start": list(self.robot.start)}
        if self.robot.goal is not None:
            robot["goal"] = list(self.robot.goal)
        if self.robot.goals:
            robot["goals"] = [list(g) for g in self.robot.goals]
        robot["moves"] = [m.to_spec() for m in self.robot.moves]
        d: dict[str, Any] = {
            "grid": [self.width, self.height],
            "robot": robot,
            "obstacles": [_obstacle_doc(o) for o in self.obstacles],
            "walls": [list(w) for w in sorted(self.walls)],
        }
        if self.objective is not ObjectiveKind.EXACT:
            d["objective"] = self.objective.value
        if self.fair:
            d["fair"] = True
        if self.collision is not CollisionRule.SWEEP:
            d["collision"] = self.collision.value
        if self.steps is not None:
            d["steps"] = self.steps
        if self.max_steps is not None:
            d["max_steps"] = self.max_steps
        if self.name != "problem":  # the default label; any other one survives a round trip
            d["name"] = self.name
        return d


def _obstacle_doc(o: Obstacle) -> dict[str, Any]:
    d: dict[str, Any] = {"start": list(o.start), "moves": [m.to_spec() for m in o.moves]}
    if o.size != (1, 1):
        d["size"] = list(o.size)
    if o.period != 1:
        d["period"] = o.period
        if o.schedule is not Schedule.REST:
            d["schedule"] = o.schedule.value
        if o.phase is not None:
            d["phase"] = o.phase
    if o.glitches:
        d["glitches"] = o.glitches
    if o.keep_out:
        d["keep_out"] = [list(c) for c in sorted(o.keep_out)]
    return d


def _validate(p: GridProblem) -> None:
    """Checks that hold for problems built in code as well as from files."""
    f = p.source
    if p.width < 1 or p.height < 1:
        raise InvalidProblem(f, "grid", f"width and height must be >= 1, got {p.width}x{p.height}")
    if p.width > MAX_GRID_SIDE or p.height > MAX_GRID_SIDE:
        raise InvalidProblem(f, "grid", f"width and height must be <= {MAX_GRID_SIDE}, got {p.width}x{p.height}")
    if len(p.obstacles) > MAX_OBSTACLES:
        raise InvalidProblem(f, "obstacles", f"at most {MAX_OBSTACLES} obstacles, got {len(p.obstacles)}")
    size = f"the {p.width}x{p.height} grid"
    if not p.robot.moves:
        raise InvalidProblem(f, "robot.moves", "the robot has no moves")
    _validate_objective(p)
    cells = [("robot.start", p.robot.start)]
    if p.robot.goal is not None:
        cells.append(("robot.goal", p.robot.goal))
    cells += [(f"robot.goals[{j}]", g) for j, g in enumerate(p.robot.goals)]
    for name, c in cells:
        if not p.in_grid(c):
            raise InvalidProblem(f, name, f"{list(c)} is outside {size}")
        if c in p.walls:
            raise InvalidProblem(f, name, f"{list(c)} is on a wall")
    for i, o in enumerate(p.obstacles):
        _validate_obstacle(p, i, o, size)
    for w in sorted(p.walls):
        if not p.in_grid(w):
            raise InvalidProblem(f, "walls", f"{list(w)} is outside {size}")
    for where, moves in [("robot.moves", p.robot.moves)] + [
        (f"obstacles[{i}].moves", o.moves) for i, o in enumerate(p.obstacles)
    ]:
        seen: set[str] = set()
        for j, m in enumerate(moves):
            if m.name in seen:
                raise InvalidProblem(f, f"{where}[{j}]", f"duplicated move name {m.name!r}")
            seen.add(m.name)
    for key, value in (("steps", p.steps), ("max_steps", p.max_steps)):
        if value is not None and value < 1:
            raise InvalidProblem(f, key, f"must be >= 1, got {value}")
        if value is not None and value > MAX_STEPS:
            raise InvalidProblem(f, key, f"must be <= {MAX_STEPS}, got {value}")
    if len(p.name) > MAX_NAME_LENGTH:
        raise InvalidProblem(f, "name", f"at most {MAX_NAME_LENGTH} characters, got {len(p.name)}")


def _validate_objective(p: GridProblem) -> None:
    """The objective's own fields: which goal keys it needs, path lengths, fairness."""
    f, kind = p.source, p.objective
    if kind.has_goal and p.robot.goal is None:
        raise InvalidProblem(f, "robot.goal", f"objective {kind.value} needs a goal")
    if not kind.has_goal and p.robot.goal is not None:
        hint = "goals (a list)" if kind is ObjectiveKind.RECURRENCE else "no goal"
        raise InvalidProblem(f, "robot.goal", f"objective {kind.value} takes {hint}, not goal")
    if kind is ObjectiveKind.RECURRENCE:
        if not p.robot.goals:
            raise InvalidProblem(f, "robot.goals", "objective recurrence needs at least one goal")
        if len(p.robot.goals) > MAX_GOALS:
            raise InvalidProblem(f, "robot.goals", f"at most {MAX_GOALS} goals, got {len(p.robot.goals)}")
    elif p.robot.goals:
        raise InvalidProblem(f, "robot.goals", f"objective {kind.value} takes no goals (recurrence does)")
    if not kind.bounded:
        for key, value in (("steps", p.steps), ("max_steps", p.max_steps)):
            if value is not None:
                raise InvalidProblem(f, key, f"objective {kind.value} has no path length")
    if p.fair and kind is not ObjectiveKind.RECURRENCE:
        raise InvalidProblem(f, "fair", f"fairness is an assumption of the recurrence objective, not of {kind.value}")


def _validate_obstacle(p: GridProblem, i: int, o: Obstacle, size: str) -> None:
    f = p.source
    where = f"obstacles[{i}]"
    w, h = o.size
    if not (1 <= w <= p.width and 1 <= h <= p.height):
        raise InvalidProblem(f, f"{where}.size", f"{[w, h]} does not fit {size}")
    if not all(p.in_grid(c) for c in o.block(o.start)):
        what = "" if o.size == (1, 1) else f"the {w}x{h} block at "
        raise InvalidProblem(f, f"{where}.start", f"{what}{list(o.start)} is outside {size}")
    if not o.moves:
        raise InvalidProblem(f, f"{where}.moves", "the obstacle has no moves")
    if not 1 <= o.period <= MAX_PERIOD:
        raise InvalidProblem(f, f"{where}.period", f"must be in 1..{MAX_PERIOD}, got {o.period}")
    if o.period > 1 and not any(m.to == (0, 0) for m in o.moves):
        raise InvalidProblem(
            f,
            f"{where}.moves",
            "an obstacle with a period must be able to wait: give it a move that ends where it starts (stay)",
        )
    if o.phase is not None and not 0 <= o.phase < o.period:
        raise InvalidProblem(f, f"{where}.phase", f"must be in 0..{o.period - 1} (the period less one), got {o.phase}")
    if not 0 <= o.glitches <= MAX_GLITCHES:
        raise InvalidProblem(f, f"{where}.glitches", f"must be in 0..{MAX_GLITCHES}, got {o.glitches}")
    if o.glitches and o.period == 1:
        raise InvalidProblem(
            f, f"{where}.glitches", "an obstacle that may move every step has nothing to glitch (give it a period > 1)"
        )
    if len(o.keep_out) > MAX_KEEP_OUT:
        raise InvalidProblem(f, f"{where}.keep_out", f"at most {MAX_KEEP_OUT} cells, got {len(o.keep_out)}")
    for c in sorted(o.keep_out):
        if not p.in_grid(c):
            raise InvalidProblem(f, f"{where}.keep_out", f"{list(c)} is outside {size}")


# -- loading ---------------------------------------------------------------------------

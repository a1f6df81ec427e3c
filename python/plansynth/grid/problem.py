"""Grid reactive planning problems: the frozen problem value and its loader.

Implements the problem file of ``shared/spec/grid-problem.md`` (the model of Chasins &
Newcomb, SYNT 2016, Section 3.1: a robot and adversarial obstacles on a grid, each
moving by its own motion primitives). Every bad input is rejected at the door with
:class:`~plansynth.errors.InvalidProblem` naming the file, the field and the reason.

>>> p = grid_problem_from_dict({
...     "grid": [5, 7],
...     "robot": {"start": [1, 1], "goal": [4, 4], "moves": ["stay", "up", "right", "down", "left"]},
...     "obstacles": [{"start": [2, 5], "moves": ["up", "down"]}],
... })
>>> p.width, p.height, p.robot.start, p.obstacles[0].moves[1].to
(5, 7, (1, 1), (0, -1))
>>> p.variables
('rx', 'ry', 'o0x', 'o0y')
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from plansynth.errors import InvalidProblem
from plansynth.io import MAX_NAME_LENGTH, Fields, as_int, as_int_vector, as_name, load_document, show, type_name

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
    start: Cell
    goal: Cell
    moves: tuple[Move, ...]


@dataclass(frozen=True)
class Obstacle:
    start: Cell
    moves: tuple[Move, ...]


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

    def __post_init__(self) -> None:
        _validate(self)

    # -- derived views -------------------------------------------------------------
    @property
    def variables(self) -> tuple[str, ...]:
        """Controller inputs in order: ``rx ry o0x o0y o1x o1y ...`` (spec)."""
        names = ["rx", "ry"]
        for i in range(len(self.obstacles)):
            names += [f"o{i}x", f"o{i}y"]
        return tuple(names)

    @property
    def max_constant(self) -> int:
        """d - 1 where d = max(width, height): the largest constant of the grammar."""
        return max(self.width, self.height) - 1

    def path_lengths(self) -> range:
        """The path lengths l to try, in order."""
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
        """The problem as a spec document; ``grid_problem_from_dict`` reads it back."""
        d: dict[str, Any] = {
            "grid": [self.width, self.height],
            "robot": {
                "start": list(self.robot.start),
                "goal": list(self.robot.goal),
                "moves": [m.to_spec() for m in self.robot.moves],
            },
            "obstacles": [{"start": list(o.start), "moves": [m.to_spec() for m in o.moves]} for o in self.obstacles],
            "walls": [list(w) for w in sorted(self.walls)],
        }
        if self.steps is not None:
            d["steps"] = self.steps
        if self.max_steps is not None:
            d["max_steps"] = self.max_steps
        if self.name != "problem":  # the default label; any other one survives a round trip
            d["name"] = self.name
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
    for name, c in (("robot.start", p.robot.start), ("robot.goal", p.robot.goal)):
        if not p.in_grid(c):
            raise InvalidProblem(f, name, f"{list(c)} is outside {size}")
        if c in p.walls:
            raise InvalidProblem(f, name, f"{list(c)} is on a wall")
    for i, o in enumerate(p.obstacles):
        if not p.in_grid(o.start):
            raise InvalidProblem(f, f"obstacles[{i}].start", f"{list(o.start)} is outside {size}")
        if not o.moves:
            raise InvalidProblem(f, f"obstacles[{i}].moves", "the obstacle has no moves")
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


# -- loading ---------------------------------------------------------------------------

_TOP_KEYS = {"grid", "robot", "obstacles", "walls", "steps", "max_steps", "name"}


def load_grid_problem(path: str | Path) -> GridProblem:
    """Read a grid problem from a YAML or JSON file (spec: grid-problem.md)."""
    doc, name = load_document(path)
    return grid_problem_from_dict(doc, source=name, name=Path(path).stem)


def grid_problem_from_dict(doc: Any, source: str | None = None, name: str | None = None) -> GridProblem:
    """Build a :class:`GridProblem` from a parsed document, validating every field."""
    top = Fields(doc, source, "")
    top.reject_unknown(_TOP_KEYS)
    width, height = as_int_vector(top.require("grid"), source, "grid", 2, hi=MAX_GRID_SIDE)

    r = Fields(top.require("robot"), source, "robot")
    r.reject_unknown({"start", "goal", "moves"})
    robot = Robot(
        start=_cell(r.require("start"), source, "robot.start"),
        goal=_cell(r.require("goal"), source, "robot.goal"),
        moves=_moves(r.require("moves"), source, "robot.moves"),
    )

    obstacles = []
    raw_obstacles = top.optional("obstacles", [])
    if not isinstance(raw_obstacles, Sequence) or isinstance(raw_obstacles, (str, bytes)):
        raise InvalidProblem(source, "obstacles", f"expected a list, got {type_name(raw_obstacles)}")
    if len(raw_obstacles) > MAX_OBSTACLES:
        raise InvalidProblem(source, "obstacles", f"at most {MAX_OBSTACLES} obstacles, got {len(raw_obstacles)}")
    for i, raw in enumerate(raw_obstacles):
        o = Fields(raw, source, f"obstacles[{i}]")
        o.reject_unknown({"start", "moves"})
        obstacles.append(
            Obstacle(
                start=_cell(o.require("start"), source, f"obstacles[{i}].start"),
                moves=_moves(o.require("moves"), source, f"obstacles[{i}].moves"),
            )
        )

    raw_walls = top.optional("walls", [])
    if not isinstance(raw_walls, Sequence) or isinstance(raw_walls, (str, bytes)):
        raise InvalidProblem(source, "walls", f"expected a list of cells, got {type_name(raw_walls)}")
    walls = frozenset(_cell(w, source, f"walls[{i}]") for i, w in enumerate(raw_walls))

    steps = top.optional("steps")
    max_steps = top.optional("max_steps")
    label = as_name(top.optional("name", name or "problem"), source, numbers=True)
    return GridProblem(
        width=width,
        height=height,
        robot=robot,
        obstacles=tuple(obstacles),
        walls=walls,
        steps=None if steps is None else as_int(steps, source, "steps", lo=1, hi=MAX_STEPS),
        max_steps=None if max_steps is None else as_int(max_steps, source, "max_steps", lo=1, hi=MAX_STEPS),
        name=label,
        source=source,
    )


def _cell(value: Any, file: str | None, field_: str) -> Cell:
    # Cells and offsets beyond any grid are refused here, before arithmetic on them.
    x, y = as_int_vector(value, file, field_, 2, lo=-MAX_GRID_SIDE, hi=MAX_GRID_SIDE)
    return (x, y)


def _moves(value: Any, file: str | None, field_: str) -> tuple[Move, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field_, f"expected a list of moves, got {type_name(value)}")
    if len(value) == 0:
        raise InvalidProblem(file, field_, "no moves given")
    if len(value) > MAX_MOVES:
        raise InvalidProblem(file, field_, f"at most {MAX_MOVES} moves, got {len(value)}")
    return tuple(_move(v, file, f"{field_}[{i}]") for i, v in enumerate(value))


def _move(value: Any, file: str | None, field_: str) -> Move:
    if isinstance(value, str):
        if value not in BUILTIN_MOVES:
            raise InvalidProblem(file, field_, f"unknown move {show(value)} (built-in: {', '.join(BUILTIN_MOVES)})")
        return BUILTIN_MOVES[value]
    if isinstance(value, Mapping):
        m = Fields(value, file, field_)
        m.reject_unknown({"name", "to", "via"})
        name = m.require("name")
        if not isinstance(name, str) or not name:
            raise InvalidProblem(file, f"{field_}.name", f"expected a non-empty string, got {show(name)}")
        to = _cell(m.require("to"), file, f"{field_}.to")
        raw_via = m.optional("via", [])
        if not isinstance(raw_via, Sequence) or isinstance(raw_via, (str, bytes)):
            raise InvalidProblem(file, f"{field_}.via", f"expected a list of offsets, got {type_name(raw_via)}")
        if len(raw_via) > MAX_VIA:
            raise InvalidProblem(file, f"{field_}.via", f"at most {MAX_VIA} offsets, got {len(raw_via)}")
        via = tuple(_cell(v, file, f"{field_}.via[{i}]") for i, v in enumerate(raw_via))
        return Move(name, to, via)
    raise InvalidProblem(file, field_, f"expected a move name or mapping, got {show(value)}")

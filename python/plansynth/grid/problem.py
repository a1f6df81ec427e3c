"""Grid reactive planning problems: the frozen problem value and its loader.

Implements the problem file of ``shared/spec/grid-problem.md`` (the model of Chasins &
Newcomb, SYNT 2016, Section 3.1: a robot and adversarial obstacles on a grid, each
moving by its own motion primitives). Every bad input is rejected at the door with
:class:`~plansynth.errors.InvalidProblem` naming the file, the field and the reason.

The values and their checks are :mod:`plansynth.grid.model`; this module reads files
into them (and exports them, as it always has).

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
from pathlib import Path
from typing import Any

from plansynth.errors import InvalidProblem
from plansynth.grid.model import (  # noqa: F401 - the values and limits, imported from here too
    BUILTIN_MOVES,
    DEFAULT_MAX_STEPS,
    MAX_GLITCHES,
    MAX_GOALS,
    MAX_GRID_SIDE,
    MAX_KEEP_OUT,
    MAX_MOVES,
    MAX_OBSTACLES,
    MAX_PERIOD,
    MAX_STEPS,
    MAX_VIA,
    Cell,
    GridProblem,
    Move,
    Obstacle,
    Robot,
)
from plansynth.grid.objective import CollisionRule, ObjectiveKind, Schedule
from plansynth.io import Fields, as_int, as_int_vector, as_name, load_document, show, type_name

_TOP_KEYS = {"grid", "robot", "obstacles", "walls", "steps", "max_steps", "name", "objective", "fair", "collision"}
_OBSTACLE_KEYS = {"start", "moves", "size", "period", "schedule", "phase", "glitches", "keep_out"}


def load_grid_problem(path: str | Path) -> GridProblem:
    """Read a grid problem from a YAML or JSON file (spec: grid-problem.md)."""
    doc, name = load_document(path)
    return grid_problem_from_dict(doc, source=name, name=Path(path).stem)


def grid_problem_from_dict(doc: Any, source: str | None = None, name: str | None = None) -> GridProblem:
    """Build a :class:`GridProblem` from a parsed document, validating every field."""
    top = Fields(doc, source, "")
    top.reject_unknown(_TOP_KEYS)
    width, height = as_int_vector(top.require("grid"), source, "grid", 2, hi=MAX_GRID_SIDE)

    objective = _choice(top.optional("objective", "exact"), ObjectiveKind, source, "objective")
    collision = _choice(top.optional("collision", "sweep"), CollisionRule, source, "collision")
    fair = top.optional("fair", False)
    if not isinstance(fair, bool):
        raise InvalidProblem(source, "fair", f"expected true or false, got {show(fair)}")
    r = Fields(top.require("robot"), source, "robot")
    r.reject_unknown({"start", "goal", "goals", "moves"})
    raw_goal = r.require("goal") if objective.has_goal else r.optional("goal")
    raw_goals = r.require("goals") if objective is ObjectiveKind.RECURRENCE else r.optional("goals")
    robot = Robot(
        start=_cell(r.require("start"), source, "robot.start"),
        goal=None if raw_goal is None else _cell(raw_goal, source, "robot.goal"),
        moves=_moves(r.require("moves"), source, "robot.moves"),
        goals=() if raw_goals is None else _cells(raw_goals, source, "robot.goals", MAX_GOALS),
    )

    obstacles = []
    raw_obstacles = top.optional("obstacles", [])
    if not isinstance(raw_obstacles, Sequence) or isinstance(raw_obstacles, (str, bytes)):
        raise InvalidProblem(source, "obstacles", f"expected a list, got {type_name(raw_obstacles)}")
    if len(raw_obstacles) > MAX_OBSTACLES:
        raise InvalidProblem(source, "obstacles", f"at most {MAX_OBSTACLES} obstacles, got {len(raw_obstacles)}")
    for i, raw in enumerate(raw_obstacles):
        obstacles.append(_obstacle(raw, source, f"obstacles[{i}]"))

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
        objective=objective,
        fair=fair,
        collision=collision,
    )


def _obstacle(raw: Any, source: str | None, where: str) -> Obstacle:
    o = Fields(raw, source, where)
    o.reject_unknown(_OBSTACLE_KEYS)
    w, h = as_int_vector(o.optional("size", [1, 1]), source, f"{where}.size", 2, lo=1, hi=MAX_GRID_SIDE)
    period = as_int(o.optional("period", 1), source, f"{where}.period", lo=1, hi=MAX_PERIOD)
    phase = o.optional("phase")
    return Obstacle(
        start=_cell(o.require("start"), source, f"{where}.start"),
        moves=_moves(o.require("moves"), source, f"{where}.moves"),
        size=(w, h),
        period=period,
        schedule=_choice(o.optional("schedule", "rest"), Schedule, source, f"{where}.schedule"),
        phase=None if phase is None else as_int(phase, source, f"{where}.phase", lo=0, hi=MAX_PERIOD),
        glitches=as_int(o.optional("glitches", 0), source, f"{where}.glitches", lo=0, hi=MAX_GLITCHES),
        keep_out=frozenset(_cells(o.optional("keep_out", []), source, f"{where}.keep_out", MAX_KEEP_OUT)),
    )


def _choice(value: Any, kind: type, file: str | None, field_: str) -> Any:
    """A value of the str enum ``kind`` (one of its values, written as text)."""
    names = [e.value for e in kind]
    if not isinstance(value, str) or value not in names:
        raise InvalidProblem(file, field_, f"expected one of {', '.join(names)}, got {show(value)}")
    return kind(value)


def _cells(value: Any, file: str | None, field_: str, limit: int) -> tuple[Cell, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field_, f"expected a list of cells, got {type_name(value)}")
    if len(value) > limit:
        raise InvalidProblem(file, field_, f"at most {limit} cells, got {len(value)}")
    return tuple(_cell(c, file, f"{field_}[{i}]") for i, c in enumerate(value))


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

"""The file format of team problems: the reach-avoid format (:mod:`plansynth.reach.fileformat`)
with ``robots``, ``separation`` and ``moving_obstacles`` (docs/reference/reach-format.md,
"Teams of robots and moving obstacles").

A document with none of those keys is a reach-avoid problem and means exactly what it
meant before (:func:`load_problem` returns a :class:`~plansynth.reach.problem.ReachProblem`
for it). With ``robots``, the ``robot`` block (optional) holds what every robot has
unless it says otherwise (dynamics, input bound, state bounds, size, ``stop``); each
entry of ``robots`` gives its start and goal (or mission), and may override the rest.
Without ``robots`` but with moving obstacles or a separation, the one ``robot`` (with
the top-level ``goal`` or ``mission``) is a team of one.

>>> p = team_problem_from_dict({
...     "workspace": {"min": [0, 0], "max": [10, 2]},
...     "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "input_bound": 1},
...     "robots": [{"start": [1, 1], "goal": {"min": [8, 0], "max": [10, 2]}},
...                {"start": [9, 1], "goal": {"point": [1, 1]}}],
...     "separation": 0.5})
>>> [r.name for r in p.robots], p.separation.distance, p.robots[1].goal
(['r0', 'r1'], 0.5, GoalPoint(point=(1.0, 1.0)))
>>> team_problem_from_dict(team_problem_to_dict(p)) == p
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.io import Fields, as_float, as_float_vector, as_int, as_name, load_document, type_name
from plansynth.reach.fileformat import (
    _box_to_dict,
    _disturbance_to_dict,
    _num,
    _parse_box,
    _parse_disturbance,
    _parse_dynamics,
    _parse_labels,
    _parse_polygon,
    _parse_shape,
    _parse_world,
    _shape_to_dict,
    reach_problem_from_dict,
    reach_problem_to_dict,
)
from plansynth.reach.geometry import Box, Shape
from plansynth.reach.problem import DEFAULT_MAX_HORIZON, MAX_COORDINATE, MAX_HORIZON, ReachProblem
from plansynth.reach.robot import RobotShape
from plansynth.reach.team.problem import (
    MAX_ROBOTS,
    MAX_WAYPOINTS,
    GoalPoint,
    MovingObstacle,
    Separation,
    TeamProblem,
    TeamRobot,
)

__all__ = [
    "TEAM_KEYS",
    "is_team_document",
    "load_problem",
    "problem_from_dict",
    "team_problem_from_dict",
    "team_problem_to_dict",
]

#: The keys that make a document a team problem.
TEAM_KEYS = ("robots", "separation", "moving_obstacles")
_TOP_KEYS = {"workspace", "obstacles", "goal", "robot", "robots", "separation", "moving_obstacles"}
_TOP_KEYS |= {"max_horizon", "name", "labels", "mission"}
_DEFAULT_KEYS = {"dynamics", "input_bound", "state_bounds", "radius", "half_extent", "stop", "disturbance"}
_ROBOT_KEYS = _DEFAULT_KEYS | {"name", "start", "goal", "mission"}


def is_team_document(doc: Any) -> bool:
    """Does the document use a team key (``robots``, ``separation``, ``moving_obstacles``)?"""
    return isinstance(doc, Mapping) and any(k in doc for k in TEAM_KEYS)


def load_problem(path: str | Path) -> ReachProblem | TeamProblem:
    """Read a problem file: a team problem when it uses a team key, else a reach-avoid
    problem (:func:`~plansynth.reach.fileformat.load_reach_problem`)."""
    doc, name = load_document(path)
    return problem_from_dict(doc, source=name, default_name=Path(path).stem)


def problem_from_dict(
    doc: Any, source: str | None = None, *, default_name: str = "reach"
) -> ReachProblem | TeamProblem:
    """:func:`team_problem_from_dict` or :func:`~plansynth.reach.fileformat.reach_problem_from_dict`."""
    if is_team_document(doc):
        return team_problem_from_dict(doc, source, default_name=default_name)
    return reach_problem_from_dict(doc, source, default_name=default_name)


def team_problem_from_dict(doc: Any, source: str | None = None, *, default_name: str = "team") -> TeamProblem:
    """Build a team problem from a parsed document; every bad input raises InvalidProblem."""
    top = Fields(doc, source, "")
    top.reject_unknown(_TOP_KEYS)
    workspace, obstacles = _parse_world(top, source)
    d = workspace.dim
    labels, margins = _parse_labels(top.optional("labels", {}), source, d)
    if margins:  # (a team's robots read their missions as a string: segment reading, no margins)
        raise InvalidProblem(source, f"labels.{margins[0][0]}.margin", "label margins are for one robot's mission")
    defaults = top.optional("robot", {})
    if "robots" in doc:
        for key in ("goal", "mission"):
            if key in doc:
                raise InvalidProblem(source, key, f"with robots, each robot has its own {key} (robots[i].{key})")
        raw_robots = top.require("robots")
        if not isinstance(raw_robots, Sequence) or isinstance(raw_robots, (str, bytes)) or not raw_robots:
            raise InvalidProblem(source, "robots", f"expected a non-empty list of robots, got {type_name(raw_robots)}")
        if len(raw_robots) > MAX_ROBOTS:
            raise InvalidProblem(source, "robots", f"at most {MAX_ROBOTS} robots, got {len(raw_robots)}")
        Fields(defaults, source, "robot").reject_unknown(_DEFAULT_KEYS)
        robots = tuple(
            _parse_robot(raw, defaults, source, f"robots[{i}]", f"r{i}", d) for i, raw in enumerate(raw_robots)
        )
    else:  # one robot among moving obstacles: the reach-avoid layout
        one = dict(Fields(top.require("robot"), source, "robot").value)
        for key in ("goal", "mission"):
            if key in doc:
                one[key] = doc[key]
        robots = (_parse_robot(one, {}, source, "robot", "r0", d),)
    separation = _parse_separation(top.optional("separation", 0.0), source, d)
    raw_moving = top.optional("moving_obstacles", [])
    if not isinstance(raw_moving, Sequence) or isinstance(raw_moving, (str, bytes)):
        raise InvalidProblem(source, "moving_obstacles", f"expected a list, got {type_name(raw_moving)}")
    if len(raw_moving) > MAX_ROBOTS:
        raise InvalidProblem(
            source, "moving_obstacles", f"at most {MAX_ROBOTS} moving obstacles, got {len(raw_moving)}"
        )
    moving = tuple(_parse_moving(o, source, f"moving_obstacles[{k}]", d, k) for k, o in enumerate(raw_moving))
    max_horizon = as_int(top.optional("max_horizon", DEFAULT_MAX_HORIZON), source, "max_horizon", hi=MAX_HORIZON)
    if max_horizon <= 0:
        raise InvalidProblem(source, "max_horizon", f"must be positive, got {max_horizon}")
    name = as_name(top.optional("name", default_name), source)
    return TeamProblem(
        workspace=workspace,
        obstacles=obstacles,
        robots=robots,
        separation=separation,
        moving_obstacles=moving,
        labels=labels,
        max_horizon=max_horizon,
        name=name,
        source=source,
    )


def _parse_robot(raw: Any, defaults: Any, src: str | None, where: str, default_name: str, d: int) -> TeamRobot:
    f = Fields(raw, src, where)
    f.reject_unknown(_ROBOT_KEYS)
    merged = {**dict(defaults), **{k: v for k, v in f.value.items() if v is not None}}
    if "radius" in f.value or "half_extent" in f.value:  # a robot's own size replaces the default one
        for key in ("radius", "half_extent"):
            if key not in f.value:
                merged.pop(key, None)

    def at(key: str) -> str:
        return f"{where}.{key}" if key in f.value or where == "robot" else f"robot.{key}"

    if "dynamics" not in merged:
        raise InvalidProblem(src, f"{where}.dynamics", "missing required field (here or in robot.dynamics)")
    try:
        dynamics = _parse_dynamics(merged["dynamics"], src, d)
    except InvalidProblem as exc:
        raise InvalidProblem(src, exc.field.replace("robot.dynamics", at("dynamics"), 1), exc.reason) from None
    n = dynamics.n_states
    start = as_float_vector(f.require("start"), src, f"{where}.start", n, max_abs=MAX_COORDINATE)
    if "input_bound" not in merged:
        raise InvalidProblem(src, f"{where}.input_bound", "missing required field (here or in robot.input_bound)")
    input_bound = as_float(merged["input_bound"], src, at("input_bound"), positive=True, max_abs=MAX_COORDINATE)
    sb_raw = merged.get("state_bounds")
    state_bounds = None if sb_raw is None else _parse_box(sb_raw, src, at("state_bounds"), allow_flat=True)
    if state_bounds is not None and state_bounds.dim != n:
        raise InvalidProblem(src, at("state_bounds"), f"must be {n}-dimensional like the state, got {state_bounds.dim}")
    robot_shape = None
    if merged.get("radius") is not None and merged.get("half_extent") is not None:
        raise InvalidProblem(src, at("radius"), "give either radius (a disc) or half_extent (a box), not both")
    if merged.get("radius") is not None:
        r = as_float(merged["radius"], src, at("radius"))
        if r < 0:
            raise InvalidProblem(src, at("radius"), f"must be a non-negative number, got {r}")
        robot_shape = RobotShape(radius=r)
    elif merged.get("half_extent") is not None:
        robot_shape = RobotShape(half_extent=tuple(as_float_vector(merged["half_extent"], src, at("half_extent"), d)))
    mission = merged.get("mission")
    goal_raw = merged.get("goal")
    goal = None if goal_raw is None else _parse_goal(goal_raw, src, f"{where}.goal", d)
    stop = merged.get("stop", False)
    if not isinstance(stop, bool):
        raise InvalidProblem(src, at("stop"), f"expected true or false, got {type_name(stop)}")
    name = as_name(merged.get("name", default_name), src, f"{where}.name")
    disturbance = None
    if merged.get("disturbance") is not None:
        try:
            disturbance = _parse_disturbance(merged["disturbance"], src, n, dynamics.n_inputs)
        except InvalidProblem as exc:
            raise InvalidProblem(
                src, exc.field.replace("robot.disturbance", at("disturbance"), 1), f"robot {name}: {exc.reason}"
            ) from None
    return TeamRobot(
        name=name,
        dynamics=dynamics,
        start=np.array(start),
        input_bound=input_bound,
        goal=goal,
        state_bounds=state_bounds,
        robot_shape=robot_shape,
        mission=mission,
        stop=stop,
        disturbance=disturbance,
    )


def _parse_goal(value: Any, src: str | None, where: str, d: int) -> Shape | GoalPoint:
    if isinstance(value, Mapping) and "point" in value:
        Fields(value, src, where).reject_unknown({"point"})
        return GoalPoint(as_float_vector(value["point"], src, f"{where}.point", d, max_abs=MAX_COORDINATE))
    return _parse_shape(value, src, where, d)


def _parse_separation(value: Any, src: str | None, d: int) -> Separation:
    """``separation: 0.5`` (the infinity norm) or ``{distance: 0.5, norm: inf}`` or
    ``{distance: 0.5, norm: [[x, y], ...]}`` (the unit ball of a polygonal norm)."""
    if not isinstance(value, Mapping):
        return Separation(as_float(value, src, "separation", max_abs=MAX_COORDINATE))
    f = Fields(value, src, "separation")
    f.reject_unknown({"distance", "norm"})
    distance = as_float(f.require("distance"), src, "separation.distance", max_abs=MAX_COORDINATE)
    norm = f.optional("norm", "inf")
    if norm in ("inf", "infinity"):
        return Separation(distance)
    if isinstance(norm, str):
        raise InvalidProblem(src, "separation.norm", f"unknown norm {norm!r} (inf, or a polygon: the unit ball)")
    return Separation(distance, _parse_polygon(norm, src, "separation.norm", d))


def _parse_moving(value: Any, src: str | None, where: str, d: int, k: int) -> MovingObstacle:
    f = Fields(value, src, where)
    f.reject_unknown({"name", "shape", "path", "separation"})
    raw_shape = f.require("shape")
    if isinstance(raw_shape, Mapping) and "vertices" not in raw_shape:  # a box, possibly a point
        shape: Shape = _parse_box(raw_shape, src, f"{where}.shape", dim=d, allow_flat=True)
    else:
        shape = _parse_shape(raw_shape, src, f"{where}.shape", d)
    path = f.require("path")
    if not isinstance(path, Sequence) or isinstance(path, (str, bytes)) or not path:
        raise InvalidProblem(
            src, f"{where}.path", f"expected a non-empty list of waypoints {{t, at}}, got {type_name(path)}"
        )
    if len(path) > MAX_WAYPOINTS:
        raise InvalidProblem(src, f"{where}.path", f"at most {MAX_WAYPOINTS} waypoints, got {len(path)}")
    times, positions = [], []
    for w, wp in enumerate(path):
        g = Fields(wp, src, f"{where}.path[{w}]")
        g.reject_unknown({"t", "at"})
        times.append(as_float(g.require("t"), src, f"{where}.path[{w}].t", max_abs=MAX_COORDINATE))
        positions.append(as_float_vector(g.require("at"), src, f"{where}.path[{w}].at", d, max_abs=MAX_COORDINATE))
    sep_raw = f.optional("separation")
    sep = None if sep_raw is None else as_float(sep_raw, src, f"{where}.separation", max_abs=MAX_COORDINATE)
    name = as_name(f.optional("name", f"m{k}"), src, f"{where}.name")
    return MovingObstacle(shape, tuple(times), tuple(positions), name, sep)


# --------------------------------------------------------------------------- writing


def _goal_to_dict(goal: Shape | GoalPoint) -> Any:
    if isinstance(goal, GoalPoint):
        return {"point": [_num(v) for v in goal.point]}
    return _shape_to_dict(goal)


def team_problem_to_dict(problem: TeamProblem) -> dict:
    """The document of a team problem (every robot written in full, no ``robot``
    defaults); :func:`team_problem_from_dict` reads it back equal."""
    robots = []
    for r in problem.robots:
        single = ReachProblem(
            workspace=problem.workspace,
            obstacles=(),
            goal=problem.workspace,
            dynamics=r.dynamics,
            start=r.start,
            input_bound=r.input_bound,
            state_bounds=r.state_bounds,
            robot_shape=r.robot_shape,
        )
        entry: dict[str, Any] = {"name": r.name, **reach_problem_to_dict(single)["robot"]}
        if r.goal is not None:
            entry["goal"] = _goal_to_dict(r.goal)
        if r.mission is not None:
            entry["mission"] = r.mission
        if r.stop:
            entry["stop"] = True
        if r.disturbance is not None:
            entry["disturbance"] = _disturbance_to_dict(r.disturbance)
        robots.append(entry)
    sep = problem.separation
    out: dict[str, Any] = {
        "name": problem.name,
        "workspace": _box_to_dict(problem.workspace),
        "obstacles": [_shape_to_dict(o) for o in problem.obstacles],
        "robots": robots,
        "separation": _num(sep.distance)
        if sep.norm is None
        else {"distance": _num(sep.distance), "norm": _shape_to_dict(sep.norm)},
        "max_horizon": problem.max_horizon,
    }
    if problem.moving_obstacles:
        out["moving_obstacles"] = [
            {
                "name": o.name,
                "shape": _shape_to_dict(o.shape),
                "path": [{"t": _num(t), "at": [_num(v) for v in p]} for t, p in zip(o.times, o.positions)],
                **({} if o.separation is None else {"separation": _num(o.separation)}),
            }
            for o in problem.moving_obstacles
        ]
    if problem.labels:
        out["labels"] = {
            k: (_box_to_dict(v) if isinstance(v, Box) else {"polygon": _shape_to_dict(v)}) for k, v in problem.labels
        }
    return out

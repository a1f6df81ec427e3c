"""The checks a :class:`~plansynth.reach.problem.ReachProblem` passes when it is made
(Shoukry et al., CDC 2016, Section II, Definition 2.3, and the documented limits of
:mod:`plansynth.reach.limits`): the workspace, shapes, dynamics, start and bounds, the
robot's extent, the disturbance and the mission, each failure an
:class:`~plansynth.errors.InvalidProblem` naming the field. The problem is passed in as
it is being made (this module sits below :mod:`plansynth.reach.problem`, which calls
:func:`check_problem`).
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import shapely
from shapely.geometry import box as _sh_box

from plansynth.errors import InvalidProblem
from plansynth.io import MAX_NAME_LENGTH, type_name  # noqa: F401 - MAX_NAME_LENGTH: a documented limit, with the others
from plansynth.reach.disturbance import MAX_VERTICES as MAX_DISTURBANCE_VERTICES
from plansynth.reach.disturbance import Disturbance, origin_inside
from plansynth.reach.geometry import (
    Box,
    Polygon,
    _measure_in_workspace,
    free_measure,
    is_convex,
    point_in_interior,
    polygon_problem,
    shape_to_shapely,
)
from plansynth.reach.limits import MAX_COORDINATE, MAX_LABEL_VERTICES, MAX_LABELS, MISSION_ENDS, MISSION_READINGS
from plansynth.reach.robot import configuration_space

__all__ = ["check_problem"]


def check_problem(p: Any) -> None:
    """Raise :class:`~plansynth.errors.InvalidProblem` for the first field of the
    problem value ``p`` that is out of its bounds."""
    src = p.source
    ws = p.workspace
    if not isinstance(ws, Box):
        raise InvalidProblem(src, "workspace", "must be a box {min, max}")
    if ws.dim not in (2, 3):
        raise InvalidProblem(src, "workspace", f"must be 2-D or 3-D, got {ws.dim}-D")
    if ws.is_degenerate():
        raise InvalidProblem(src, "workspace", f"empty or flat box: min {ws.lo} is not below max {ws.hi}")
    d = ws.dim
    for i, ob in enumerate(p.obstacles):
        _check_shape(ob, d, src, f"obstacles[{i}]")
    if p.goal is None and p.mission is None:
        raise InvalidProblem(src, "goal", "missing required field (a problem without a mission needs a goal)")
    if p.goal is not None:
        _check_shape(p.goal, d, src, "goal")
        if not is_convex(p.goal):
            raise InvalidProblem(src, "goal", "must be convex (a box or a convex polygon)")
    _check_mission(p, d)

    dyn = p.dynamics
    A, B = dyn.A, dyn.B
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise InvalidProblem(src, "robot.dynamics.A", f"must be a square n x n matrix, got shape {A.shape}")
    n = A.shape[0]
    if B.ndim != 2 or B.shape[0] != n or B.shape[1] == 0:
        raise InvalidProblem(
            src, "robot.dynamics.B", f"must be an {n} x m matrix (A is {n} x {n}), got shape {B.shape}"
        )
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
        raise InvalidProblem(src, "robot.dynamics", "matrices must be finite")
    if len(dyn.position) != d:
        raise InvalidProblem(
            src,
            "robot.dynamics.position",
            f"must name {d} state components (the workspace is {d}-D), got {len(dyn.position)}",
        )
    if len(set(dyn.position)) != d or any(not 0 <= i < n for i in dyn.position):
        raise InvalidProblem(
            src,
            "robot.dynamics.position",
            f"must be {d} distinct state indices in 0..{n - 1}, got {list(dyn.position)}",
        )
    if dyn.dt is not None and not dyn.dt > 0:
        raise InvalidProblem(src, "robot.dynamics.dt", f"must be positive, got {dyn.dt}")

    if p.start.shape != (n,) or not np.all(np.isfinite(p.start)):
        raise InvalidProblem(src, "robot.start", f"must be a state of {n} finite numbers, got {p.start.shape[0]}")
    if not math.isfinite(p.input_bound) or not p.input_bound > 0:
        raise InvalidProblem(src, "robot.input_bound", f"must be positive, got {p.input_bound}")
    if p.state_bounds is not None:
        sb = p.state_bounds
        if sb.dim != n:
            raise InvalidProblem(src, "robot.state_bounds", f"must be {n}-dimensional like the state, got {sb.dim}")
        if any(not l <= h for l, h in zip(sb.lo, sb.hi)):
            raise InvalidProblem(src, "robot.state_bounds", f"min {sb.lo} exceeds max {sb.hi}")
    if isinstance(p.max_horizon, bool) or not isinstance(p.max_horizon, int) or p.max_horizon <= 0:
        raise InvalidProblem(src, "max_horizon", f"must be a positive integer, got {p.max_horizon!r}")
    if p.disturbance is not None:
        _check_disturbance(p, n)

    pos = p.start[list(dyn.position)]
    if p.robot_shape is not None and not p.robot_shape.is_point:
        _check_robot(p, pos)
        return
    if not ws.contains(pos):
        raise InvalidProblem(src, "robot.start", f"position {_fmt(pos)} lies outside the workspace {ws.lo}..{ws.hi}")
    for i, ob in enumerate(p.obstacles):
        if point_in_interior(ob, pos):
            raise InvalidProblem(src, "robot.start", f"position {_fmt(pos)} lies inside obstacles[{i}]")
    if p.state_bounds is not None and not p.state_bounds.contains(p.start):
        raise InvalidProblem(src, "robot.start", f"state {_fmt(p.start)} violates robot.state_bounds")
    if p.goal is not None and free_measure(ws, p.obstacles, p.goal) <= 0.0:
        reason = "lies outside the workspace" if _measure_in_workspace(ws, p.goal) <= 0.0 else "lies inside obstacles"
        raise InvalidProblem(src, "goal", f"unreachable: it {reason} (no free area/volume)")


def _check_disturbance(p: Any, n: int) -> None:
    """``robot.disturbance`` at the door: W of the state's dimension, finite, containing
    0; the feedback design's weights or gain of the right sizes."""
    src, w = p.source, p.disturbance
    where = "robot.disturbance"
    if not isinstance(w, Disturbance):
        raise InvalidProblem(src, where, f"expected a Disturbance, got {type_name(w)}")
    if w.dim != n:
        raise InvalidProblem(src, where, f"must have {n} components like the state, got {w.dim}")
    if p.dim != 2:
        raise InvalidProblem(src, where, "disturbances need a 2-D workspace (3-D is not supported)")
    if w.box is not None:
        if any(not math.isfinite(v) or v < 0 or v > MAX_COORDINATE for v in w.box):
            raise InvalidProblem(src, f"{where}.box", f"half-widths must be numbers in [0, {MAX_COORDINATE:g}]")
    else:
        V = np.asarray(w.vertices)
        if len(V) > MAX_DISTURBANCE_VERTICES:
            raise InvalidProblem(src, f"{where}.polytope", f"at most {MAX_DISTURBANCE_VERTICES} vertices, got {len(V)}")
        if not np.all(np.isfinite(V)) or np.any(np.abs(V) > MAX_COORDINATE):
            raise InvalidProblem(src, f"{where}.polytope", f"vertices must be numbers within +-{MAX_COORDINATE:g}")
        if not origin_inside(V):
            raise InvalidProblem(
                src,
                f"{where}.polytope",
                "must contain 0 (a disturbance that can be absent; a constant drift belongs in the dynamics)",
            )
    m = p.dynamics.n_inputs
    for key, size in (("q", n), ("r", m)):
        value = getattr(w, key)
        if value is not None and (len(value) != size or any(not (math.isfinite(v) and v > 0) for v in value)):
            raise InvalidProblem(
                src, f"{where}.feedback.lqr.{key}", f"must be {size} positive numbers (a diagonal weight), got {value}"
            )
    if w.gain is not None and (w.gain.shape != (m, n) or not np.all(np.isfinite(w.gain))):
        raise InvalidProblem(
            src, f"{where}.feedback.gain", f"must be an {m} x {n} matrix of finite numbers, got shape {w.gain.shape}"
        )
    if p.mission is not None:
        for name, shape in p.labels:
            if not is_convex(shape):
                raise InvalidProblem(
                    src, f"labels.{name}", "a mission under disturbances needs convex labels (boxes or convex polygons)"
                )


def _check_robot(p: Any, pos: np.ndarray) -> None:
    """The start and goal checks for a sized robot (the robot's extent, not its point)."""
    src, rb = p.source, p.robot_shape
    assert rb is not None
    if rb.radius is not None:
        if not math.isfinite(rb.radius) or rb.radius < 0:
            raise InvalidProblem(src, "robot.radius", f"must be a non-negative number, got {rb.radius}")
        if p.dim != 2:
            raise InvalidProblem(
                src, "robot.radius", "a disc robot needs a 2-D workspace (give robot.half_extent in 3-D)"
            )
    else:
        h = rb.half_extent or ()
        if len(h) != p.dim:
            raise InvalidProblem(
                src, "robot.half_extent", f"must give {p.dim} half-extents (one per workspace axis), got {len(h)}"
            )
        if any(not math.isfinite(v) or v < 0 for v in h):
            raise InvalidProblem(src, "robot.half_extent", f"half-extents must be non-negative numbers, got {list(h)}")
    what = (
        f"disc of radius {rb.radius:g}"
        if rb.radius is not None
        else f"box of half-extents {list(rb.half_extent or ())}"
    )
    m = np.array(rb.margins(p.dim))
    ws = p.workspace
    if np.any(pos - m < np.array(ws.lo)) or np.any(pos + m > np.array(ws.hi)):
        raise InvalidProblem(src, "robot.start", f"the robot ({what}) at {_fmt(pos)} does not fit in the workspace")
    for i, ob in enumerate(p.obstacles):
        if rb.radius is not None:
            if shape_to_shapely(ob).distance(
                shapely.Point(float(pos[0]), float(pos[1]))
            ) < rb.radius - 1e-12 or point_in_interior(ob, pos):
                raise InvalidProblem(src, "robot.start", f"the robot ({what}) at {_fmt(pos)} overlaps obstacles[{i}]")
        elif isinstance(ob, Box):
            if all(l - e < x < u + e for l, u, e, x in zip(ob.lo, ob.hi, m, pos)):
                raise InvalidProblem(src, "robot.start", f"the robot ({what}) at {_fmt(pos)} overlaps obstacles[{i}]")
        else:
            body = _sh_box(pos[0] - m[0], pos[1] - m[1], pos[0] + m[0], pos[1] + m[1])
            if shapely.relate_pattern(shape_to_shapely(ob), body, "T********"):
                raise InvalidProblem(src, "robot.start", f"the robot ({what}) at {_fmt(pos)} overlaps obstacles[{i}]")
    try:
        configuration_space(p)  # the point-robot problem the planners solve, checked in turn
    except InvalidProblem as exc:
        if exc.field == "goal":
            raise InvalidProblem(
                src,
                "goal",
                f"unreachable for the robot ({what}): no free area of the goal is at "
                "the robot's clearance from the obstacles and the workspace's border",
            ) from None
        raise InvalidProblem(
            src,
            exc.field,
            f"for the robot ({what}), in its configuration space (obstacles grown "
            f"by an outer approximation): {exc.reason}",
        ) from None


def _check_mission(p: Any, d: int) -> None:
    """Labels and mission at the door: names, shapes, margins, the reading and the end,
    the formula's syntax, size and names (the limits of :mod:`plansynth.reach.ltl.syntax`
    and :data:`MAX_LABELS`)."""
    src = p.source
    if p.mission is None:
        for name, value, default in (
            ("reading", p.reading, "segment"),
            ("end", p.end, "rest"),
            ("margin", p.margin, 0.0),
            ("obstacle_margin", p.obstacle_margin, 0.0),
        ):
            if value != default:
                raise InvalidProblem(src, f"mission.{name}", "only a problem with a mission reads it")
    if not p.labels and p.mission is None:
        return
    # imported here: a problem without a mission needs no parser
    from plansynth.reach.ltl.syntax import (
        KEYWORDS,
        MAX_FORMULA_SIZE,
        MAX_MISSION_CHARS,
        LtlSyntaxError,
        parse,
        props,
        unrolled_size,
    )

    if len(p.labels) > MAX_LABELS:
        raise InvalidProblem(src, "labels", f"at most {MAX_LABELS} labels, got {len(p.labels)}")
    seen: set[str] = set()
    for name, shape in p.labels:
        where = f"labels.{name}"
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) or name in KEYWORDS:
            raise InvalidProblem(
                src,
                where,
                "a label name is a letter or _ followed by letters, digits or _, and not one of X F G U R true false",
            )
        if name in seen:
            raise InvalidProblem(src, where, "label defined twice")
        if name == "goal" and p.goal is not None:
            raise InvalidProblem(src, where, "the goal is already the label 'goal'")
        seen.add(name)
        if d != 2:
            raise InvalidProblem(src, where, "labels need a 2-D workspace (3-D missions are not supported)")
        _check_shape(shape, d, src, where)
        if isinstance(shape, Polygon) and len(shape.vertices) > MAX_LABEL_VERTICES:
            raise InvalidProblem(
                src, where, f"at most {MAX_LABEL_VERTICES} vertices in a label, got {len(shape.vertices)}"
            )
    if p.reading not in MISSION_READINGS:
        raise InvalidProblem(
            src, "mission.reading", f"unknown reading {p.reading!r} (known: {', '.join(MISSION_READINGS)})"
        )
    if p.end not in MISSION_ENDS:
        raise InvalidProblem(src, "mission.end", f"unknown end {p.end!r} (known: {', '.join(MISSION_ENDS)})")
    for where, value in (("mission.margin", p.margin), ("mission.obstacle_margin", p.obstacle_margin)):
        _check_margin(value, src, where)
    known_labels = dict(p.labels)
    for name, value in p.label_margins:
        if name not in known_labels:
            raise InvalidProblem(src, f"labels.{name}.margin", "a margin for a label that does not exist")
        _check_margin(value, src, f"labels.{name}.margin")
    for name, shape in p.mission_labels.items():
        if p.label_margin(name) > 0 and not is_convex(shape):
            field = f"labels.{name}.margin" if name in dict(p.label_margins) else "mission.margin"
            raise InvalidProblem(
                src,
                field,
                f"a margin needs a convex label, and {name} is not: write it as several convex labels "
                "(a margin is the depth below, or the distance beyond, the label's edges)",
            )
    if p.mission is None:
        return
    if not isinstance(p.mission, str):
        raise InvalidProblem(src, "mission", f"expected an LTL formula as a string, got {type_name(p.mission)}")
    if d != 2:
        raise InvalidProblem(src, "mission", "missions need a 2-D workspace (3-D missions are not supported)")
    if len(p.mission) > MAX_MISSION_CHARS:
        raise InvalidProblem(src, "mission", f"at most {MAX_MISSION_CHARS:,} characters, got {len(p.mission):,}")
    try:
        formula = parse(p.mission)
    except LtlSyntaxError as exc:
        raise InvalidProblem(src, "mission", str(exc)) from None
    size = unrolled_size(formula)
    if size > MAX_FORMULA_SIZE:
        raise InvalidProblem(
            src,
            "mission",
            f"at most {MAX_FORMULA_SIZE:,} distinct subformulas (bounded operators unrolled), got about {size:,}",
        )
    known = p.mission_labels
    unknown = sorted(props(formula) - set(known))
    if unknown:
        have = ", ".join(sorted(known)) or "none"
        raise InvalidProblem(src, "mission", f"unknown label {unknown[0]!r} (labels: {have})")


def _check_margin(value: Any, src: str | None, where: str) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InvalidProblem(src, where, f"expected a finite number, got {value!r}")
    if value < 0 or value > MAX_COORDINATE:
        raise InvalidProblem(src, where, f"must lie in [0, {MAX_COORDINATE:g}], got {value!r}")


def _fmt(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:g}" for x in v) + ")"


def _check_shape(shape: Any, d: int, src: str | None, where: str) -> None:
    if isinstance(shape, Box):
        if shape.dim != d:
            raise InvalidProblem(src, where, f"is {shape.dim}-D but the workspace is {d}-D")
        if any(not (math.isfinite(v)) for v in shape.lo + shape.hi):
            raise InvalidProblem(src, where, "box corners must be finite")
        if shape.is_degenerate():
            raise InvalidProblem(src, where, f"degenerate box: min {shape.lo} is not below max {shape.hi}")
    elif isinstance(shape, Polygon):
        if d != 2:
            raise InvalidProblem(src, where, f"polygons are 2-D but the workspace is {d}-D (use boxes)")
        if any(not math.isfinite(c) for v in shape.vertices for c in v):
            raise InvalidProblem(src, where, "polygon vertices must be finite")
        why = polygon_problem(shape)
        if why is not None:
            raise InvalidProblem(src, where, why)
    else:
        raise InvalidProblem(src, where, f"expected a Box or Polygon, got {type_name(shape)}")

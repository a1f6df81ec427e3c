"""Reach-avoid problems: the immutable problem value (Shoukry et al., CDC 2016,
Section II, Definition 2.3).

A :class:`ReachProblem` is a box workspace, obstacles (boxes, or simple polygons in
2-D, possibly non-convex), a convex goal, and a discrete-time linear robot
``x' = A x + B u`` with ``||u||_inf <= input_bound``; it is checked when it is made.
The shapes live in :mod:`plansynth.reach.geometry`, the dynamics in
:mod:`plansynth.reach.dynamics`, the robot's extent in :mod:`plansynth.reach.robot` and
the mission language in :mod:`plansynth.reach.ltl`, all below this module; the file
format (:mod:`plansynth.reach.fileformat`: ``load_reach_problem``,
``reach_problem_from_dict``, ``reach_problem_to_dict``) sits above it and reads files
into problems, so a problem value knows nothing of files.

Equality: problems, dynamics and shapes compare by value (arrays element-wise) and are
hashable, so a problem round-trips through the file format.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import shapely
from shapely.geometry import box as _sh_box

from plansynth.errors import InvalidProblem
from plansynth.io import MAX_NAME_LENGTH, type_name  # noqa: F401 - MAX_NAME_LENGTH: a documented limit, with the others
from plansynth.reach.disturbance import MAX_VERTICES as MAX_DISTURBANCE_VERTICES
from plansynth.reach.disturbance import Disturbance, origin_inside
from plansynth.reach.dynamics import NAMED_MODELS, LinearDynamics
from plansynth.reach.geometry import (
    Box,
    Polygon,
    Shape,
    _array_key,
    _frozen_array,
    _measure_in_workspace,
    free_measure,
    halfspaces,
    is_convex,
    point_in_interior,
    polygon_problem,
    shape_to_shapely,
)
from plansynth.reach.robot import RobotShape, configuration_space
from plansynth.reach.tube import Tube

__all__ = [
    "Box",
    "Polygon",
    "Shape",
    "LinearDynamics",
    "RobotShape",
    "ReachProblem",
    "halfspaces",
    "is_convex",
    "shape_to_shapely",
    "DEFAULT_MAX_HORIZON",
    "NAMED_MODELS",
]

DEFAULT_MAX_HORIZON = 200

#: Documented limits (README, "Formats and extensions"), checked at the door. Every
#: coordinate (workspace, obstacles, goal, start state, state bounds) and the input bound
#: lie within +-MAX_COORDINATE, so areas, volumes and LP data stay far from overflow
#: (a workspace of 1e200 would have an infinite area); so do the entries of explicit
#: A and B matrices.
MAX_COORDINATE = 1.0e6
#: Largest time step ``dt`` of a named model.
MAX_DT = 1.0e3
#: Largest integrator-chain order (and so at most 3 * MAX_ORDER states).
MAX_ORDER = 50
#: Largest number of states (and of inputs) of explicit dynamics.
MAX_STATES = 3 * MAX_ORDER
#: Largest ``max_horizon``.
MAX_HORIZON = 10_000
#: Most obstacles, and most vertices of one polygon.
MAX_OBSTACLES = 10_000
MAX_VERTICES = 100_000


# --------------------------------------------------------------------------- problem


@dataclass(frozen=True, eq=False)
class ReachProblem:
    """A reach-avoid problem (paper, Definition 2.3), checked on construction.

    Construction validates the semantics (shapes of matrices, start free and inside the
    workspace, goal with free area, positive bounds); a violation raises InvalidProblem
    naming ``source`` and the file field that would hold the bad value.
    """

    workspace: Box
    obstacles: tuple[Shape, ...]
    goal: Shape | None
    dynamics: LinearDynamics
    start: np.ndarray
    input_bound: float
    state_bounds: Box | None = None
    max_horizon: int = DEFAULT_MAX_HORIZON
    name: str = "reach"
    source: str | None = field(default=None)
    robot_shape: RobotShape | None = None
    # LTL missions (plansynth.reach.mission): named label shapes and the
    # mission text over their names. With a mission the goal is optional: it is then
    # only the label "goal", and the mission alone says what a plan must do.
    labels: tuple[tuple[str, Shape], ...] = ()
    mission: str | None = None
    # Bounded disturbances (plansynth.reach.robust): the set W of x' = A x + B u + w and
    # the feedback design of the file's robot.disturbance. A problem with one is planned
    # robustly: solve() plans its tightened problem, which carries the tube instead.
    disturbance: Disturbance | None = None
    # The tube of a tightened problem (set by plansynth.reach.robust.tighten, never read
    # from a file): the planners that plan under disturbances tighten the state bounds,
    # the workspace, the input bound and the goal by its error sets at every step.
    tube: Tube | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(
            self,
            "labels",
            tuple((str(k), v) for k, v in (self.labels.items() if isinstance(self.labels, Mapping) else self.labels)),
        )
        object.__setattr__(self, "start", _frozen_array(np.asarray(self.start, dtype=float).reshape(-1)))
        object.__setattr__(self, "input_bound", float(self.input_bound))
        _check_problem(self)

    @property
    def dim(self) -> int:
        """Workspace dimension (2 or 3)."""
        return self.workspace.dim

    @property
    def mission_labels(self) -> dict[str, Shape]:
        """The labels the mission may name: ``labels`` and, when there is a goal, ``goal``."""
        out = dict(self.labels)
        if self.goal is not None:
            out.setdefault("goal", self.goal)
        return out

    @property
    def start_position(self) -> np.ndarray:
        return self.start[list(self.dynamics.position)]

    @property
    def starts_at_rest(self) -> bool:
        """Is the start an equilibrium (``A x_0 = x_0``, so that u = 0 keeps the robot
        there)? Then whatever the robot can do from the start it can also do later, after
        waiting: start-anchored facts hold shifted earlier."""
        if self.tube is not None and self.tube.varies:
            # the constraints tighten as the tube grows: what the robot can do from the
            # start it need not be able to do later, after waiting
            return False
        A = np.asarray(self.dynamics.A, float)
        return bool(np.allclose(A @ self.start, self.start, rtol=0.0, atol=1e-12))

    @cached_property
    def state_box(self) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi): the bounds of every state, the state bounds met with the workspace
        on the position components (+-inf where nothing bounds a state). Computed once;
        the arrays are read-only.

        >>> from plansynth.reach.families import maze
        >>> [a.tolist() for a in maze(1).state_box]
        [[0.0, 0.0, -2.0, -2.0], [30.0, 30.0, 2.0, 2.0]]
        """
        pos = list(self.dynamics.position)
        lo = np.full(self.dynamics.n_states, -np.inf)
        hi = np.full(self.dynamics.n_states, np.inf)
        if self.state_bounds is not None:
            lo = np.maximum(lo, self.state_bounds.lo)
            hi = np.minimum(hi, self.state_bounds.hi)
        lo[pos] = np.maximum(lo[pos], self.workspace.lo)
        hi[pos] = np.minimum(hi[pos], self.workspace.hi)
        return _frozen_array(lo), _frozen_array(hi)

    def position_of(self, states: np.ndarray) -> np.ndarray:
        """Workspace coordinates of one state or of a (T x n) array of states."""
        return np.asarray(states)[..., list(self.dynamics.position)]

    def _key(self) -> tuple:
        return (
            self.workspace,
            self.obstacles,
            self.goal,
            self.dynamics,
            _array_key(self.start),
            self.input_bound,
            self.state_bounds,
            self.max_horizon,
            self.name,
            None if self.robot_shape is None or self.robot_shape.is_point else self.robot_shape,
            self.labels,
            self.mission,
            self.disturbance,
            self.tube,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ReachProblem):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


def _check_problem(p: ReachProblem) -> None:
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


def _check_disturbance(p: ReachProblem, n: int) -> None:
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


def _check_robot(p: ReachProblem, pos: np.ndarray) -> None:
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


def _check_mission(p: ReachProblem, d: int) -> None:
    """Labels and mission at the door: names, shapes, the formula's syntax and names."""
    if not p.labels and p.mission is None:
        return
    # imported here: a problem without a mission needs no parser
    from plansynth.reach.ltl.syntax import KEYWORDS, LtlSyntaxError, parse, props

    src = p.source
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
    if p.mission is None:
        return
    if not isinstance(p.mission, str):
        raise InvalidProblem(src, "mission", f"expected an LTL formula as a string, got {type_name(p.mission)}")
    if d != 2:
        raise InvalidProblem(src, "mission", "missions need a 2-D workspace (3-D missions are not supported)")
    try:
        formula = parse(p.mission)
    except LtlSyntaxError as exc:
        raise InvalidProblem(src, "mission", str(exc)) from None
    known = p.mission_labels
    unknown = sorted(props(formula) - set(known))
    if unknown:
        have = ", ".join(sorted(known)) or "none"
        raise InvalidProblem(src, "mission", f"unknown label {unknown[0]!r} (labels: {have})")


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

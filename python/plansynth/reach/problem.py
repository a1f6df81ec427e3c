"""Reach-avoid problems: the immutable problem value and its file format.

A :class:`ReachProblem` is the data of Definition 2.3 of Shoukry et al., "Scalable
Motion Planning Using Lazy SMT-Based Solving" (CDC 2016, Section II): a box workspace,
obstacles (boxes, or simple polygons in 2-D, possibly non-convex), a convex goal, and a
discrete-time linear robot ``x' = A x + B u`` with ``||u||_inf <= input_bound``.

Files follow the interchange format of the project's reach-problem spec (YAML or JSON).
:func:`load_reach_problem` checks every field at the door; every bad input raises
:class:`~plansynth.errors.InvalidProblem` naming the file, the field and the reason:

>>> reach_problem_from_dict({
...     "workspace": {"min": [0, 0], "max": [10, 10]},
...     "obstacles": [{"min": [2, 2], "max": [4, 4]}],
...     "goal": {"min": [8, 8], "max": [9, 9]},
...     "robot": {"dynamics": {"model": "single-integrator", "dt": 1.0},
...               "start": [3, 3], "input_bound": 1.0}}, source="p.yaml")
Traceback (most recent call last):
...
plansynth.errors.InvalidProblem: p.yaml: robot.start: position (3, 3) lies inside obstacles[0]

Equality: problems, dynamics and shapes compare by value (arrays element-wise) and are
hashable, so a problem round-trips through :func:`reach_problem_to_dict`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

import numpy as np
import shapely
from shapely.geometry import Polygon as _ShPolygon
from shapely.geometry import box as _sh_box

from plansynth.errors import InvalidProblem
from plansynth.io import Fields, as_float, as_float_vector, as_int, as_int_vector, load_document, show, type_name

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
    "load_reach_problem",
    "reach_problem_from_dict",
    "reach_problem_to_dict",
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
MAX_NAME_LENGTH = 200
NAMED_MODELS = ("single-integrator", "double-integrator", "integrator-chain")
MODELS = NAMED_MODELS + ("explicit",)


def _frozen_array(a: Any, dtype: Any = float) -> np.ndarray:
    arr = np.array(a, dtype=dtype, copy=True)
    arr.flags.writeable = False
    return arr


def _array_key(a: np.ndarray | None) -> Any:
    return None if a is None else (a.shape, a.tobytes())


# --------------------------------------------------------------------------- shapes


@dataclass(frozen=True)
class Box:
    """An axis-aligned box ``{p : lo <= p <= hi}``; ``dim = len(lo)``.

    >>> Box((0, 0), (2, 1)).dim
    2
    >>> Box((0, 0), (2, 1)).contains((2, 0.5))
    True
    """

    lo: tuple[float, ...]
    hi: tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "lo", tuple(float(v) for v in self.lo))
        object.__setattr__(self, "hi", tuple(float(v) for v in self.hi))
        if len(self.lo) != len(self.hi):
            raise ValueError(f"box corners of different dimensions: {self.lo} and {self.hi}")

    @property
    def dim(self) -> int:
        return len(self.lo)

    def is_degenerate(self) -> bool:
        """True when some side has zero (or negative) length."""
        return any(not h > l for l, h in zip(self.lo, self.hi))

    def contains(self, p: Sequence[float], tol: float = 0.0) -> bool:
        """Closed containment, enlarged by ``tol`` on every side."""
        return all(l - tol <= x <= h + tol for l, h, x in zip(self.lo, self.hi, p))

    def volume(self) -> float:
        return float(np.prod([h - l for l, h in zip(self.lo, self.hi)]))


@dataclass(frozen=True)
class Polygon:
    """A simple 2-D polygon (possibly non-convex), vertices stored counter-clockwise.

    The constructor reorders clockwise input; it does not check simplicity (the loader
    does, see :func:`polygon_problem`).

    >>> Polygon(((0, 0), (0, 1), (1, 0))).vertices   # given clockwise
    ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0))
    """

    vertices: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        vs = tuple((float(x), float(y)) for x, y in self.vertices)
        if len(vs) >= 2 and vs[0] == vs[-1]:
            vs = vs[:-1]  # a closing repeat of the first vertex is allowed
        if _signed_area(vs) < 0:
            vs = (vs[0],) + tuple(reversed(vs[1:]))
        object.__setattr__(self, "vertices", vs)

    @property
    def dim(self) -> int:
        return 2

    def area(self) -> float:
        return _signed_area(self.vertices)


Shape = Union[Box, Polygon]


def _signed_area(vs: Sequence[tuple[float, float]]) -> float:
    s = 0.0
    for i in range(len(vs)):
        x0, y0 = vs[i]
        x1, y1 = vs[(i + 1) % len(vs)]
        s += x0 * y1 - x1 * y0
    return 0.5 * s


def polygon_problem(poly: Polygon) -> str | None:
    """Why ``poly`` is not a proper simple polygon, or None when it is.

    >>> polygon_problem(Polygon(((0, 0), (1, 1), (2, 2))))
    'degenerate polygon (zero area)'
    >>> polygon_problem(Polygon(((0, 0), (2, 2), (2, 0), (0, 2))))
    'self-intersecting polygon'
    """
    vs = poly.vertices
    if len(vs) < 3:
        return f"a polygon needs at least 3 vertices, got {len(vs)}"
    if len(set(vs)) != len(vs):
        return "repeated vertex"
    sh = _ShPolygon(vs)
    if not sh.convex_hull.area > 0:
        return "degenerate polygon (zero area)"
    if not sh.is_valid or not sh.exterior.is_simple:
        return "self-intersecting polygon"
    if sh.area <= 1e-12 * max(1.0, sh.length**2):
        return "degenerate polygon (zero area)"
    return None


def is_convex(shape: Shape) -> bool:
    """Boxes are convex; a polygon is convex when it makes no right turn (CCW order).

    >>> is_convex(Polygon(((0, 0), (2, 0), (1, 1))))
    True
    >>> is_convex(Polygon(((0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2))))
    False
    """
    if isinstance(shape, Box):
        return True
    vs = shape.vertices
    k = len(vs)
    for i in range(k):
        (ax, ay), (bx, by), (cx, cy) = vs[i - 1], vs[i], vs[(i + 1) % k]
        if (bx - ax) * (cy - by) - (by - ay) * (cx - bx) < 0:
            return False
    return True


def halfspaces(shape: Shape) -> tuple[np.ndarray, np.ndarray]:
    """``(H, h)`` with ``shape = {p : H p <= h}`` for a convex shape; rows of H have unit norm.

    Raises ValueError for a non-convex polygon.

    >>> H, h = halfspaces(Box((0, 1), (2, 3)))
    >>> H.tolist(), h.tolist()
    ([[1.0, 0.0], [0.0, 1.0], [-1.0, -0.0], [-0.0, -1.0]], [2.0, 3.0, -0.0, -1.0])
    """
    if isinstance(shape, Box):
        d = shape.dim
        eye = np.eye(d)
        H = np.vstack([eye, -eye])
        h = np.concatenate([np.array(shape.hi), -np.array(shape.lo)])
        return H, h
    if not is_convex(shape):
        raise ValueError("halfspaces() needs a convex shape; this polygon is not convex")
    return polygon_halfspaces(np.array(shape.vertices))


def polygon_halfspaces(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Half-spaces of a convex CCW polygon: one unit-normal row per non-degenerate edge."""
    rows, rhs = [], []
    k = len(vertices)
    for i in range(k):
        a, b = vertices[i], vertices[(i + 1) % k]
        e = b - a
        nrm = math.hypot(e[0], e[1])
        if nrm == 0.0:
            continue
        n = np.array([e[1], -e[0]]) / nrm  # outward normal of a CCW edge
        rows.append(n)
        rhs.append(float(n @ a))
    return np.array(rows), np.array(rhs)


def shape_to_shapely(shape: Shape) -> shapely.Geometry:
    """The 2-D shapely geometry of a shape (boxes must be 2-D)."""
    if isinstance(shape, Box):
        if shape.dim != 2:
            raise ValueError("shapely geometry only for 2-D shapes")
        return _sh_box(shape.lo[0], shape.lo[1], shape.hi[0], shape.hi[1])
    return _ShPolygon(shape.vertices)


# --------------------------------------------------------------------------- dynamics


@dataclass(frozen=True, eq=False)
class LinearDynamics:
    """Discrete-time linear dynamics ``x' = A x + B u`` (paper, eq. (1)).

    ``position`` names the state components that are the workspace coordinates.
    ``model`` records where the matrices come from ("explicit" for matrices given in a
    file; named models are built by :mod:`plansynth.reach.dynamics`), ``dt`` the time
    step of a named model (None for explicit matrices) and ``order`` the chain order.
    Arrays are read-only copies; equality compares them element-wise.
    """

    A: np.ndarray
    B: np.ndarray
    position: tuple[int, ...]
    dt: float | None = None
    model: str = "explicit"
    order: int | None = None

    def __post_init__(self) -> None:
        A = _frozen_array(self.A)
        B = _frozen_array(self.B)
        if B.ndim == 1:
            B = _frozen_array(B.reshape(-1, 1))
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", B)
        object.__setattr__(self, "position", tuple(int(i) for i in self.position))
        if self.dt is not None:
            object.__setattr__(self, "dt", float(self.dt))
        if self.model not in MODELS:
            raise ValueError(f"unknown dynamics model {self.model!r} (known: {', '.join(MODELS)})")

    @property
    def n_states(self) -> int:
        return int(self.A.shape[0])

    @property
    def n_inputs(self) -> int:
        return int(self.B.shape[1])

    def step(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """One step ``A x + B u``."""
        return self.A @ np.asarray(x, dtype=float) + self.B @ np.asarray(u, dtype=float)

    def _key(self) -> tuple:
        return (_array_key(self.A), _array_key(self.B), self.position, self.dt, self.model, self.order)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, LinearDynamics):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


# --------------------------------------------------------------------------- robot


@dataclass(frozen=True)
class RobotShape:
    """The robot's extent around its reference point: a disc (``radius``, 2-D) or an
    axis-aligned box (``half_extent`` per axis); neither (or zero) is a point robot.
    File keys ``robot.radius`` / ``robot.half_extent``; see :mod:`plansynth.reach.robot`.

    >>> RobotShape(radius=0.5).margins(2), RobotShape(half_extent=(0.2, 0.3)).margins(2)
    ((0.5, 0.5), (0.2, 0.3))
    """

    radius: float | None = None
    half_extent: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if self.radius is not None and self.half_extent is not None:
            raise ValueError("a robot is a disc (radius) or a box (half_extent), not both")
        if self.radius is not None:
            object.__setattr__(self, "radius", float(self.radius))
        if self.half_extent is not None:
            object.__setattr__(self, "half_extent", tuple(float(v) for v in self.half_extent))

    @property
    def is_point(self) -> bool:
        if self.radius is not None:
            return self.radius == 0.0
        return self.half_extent is None or all(v == 0.0 for v in self.half_extent)

    def margins(self, dim: int) -> tuple[float, ...]:
        """How far the robot reaches from its reference point along each axis."""
        if self.radius is not None:
            return (self.radius,) * dim
        if self.half_extent is None:
            return (0.0,) * dim
        return self.half_extent


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
    # LTL missions (issue 14; plansynth.reach.mission): named label shapes and the
    # mission text over their names. With a mission the goal is optional: it is then
    # only the label "goal", and the mission alone says what a plan must do.
    labels: tuple[tuple[str, Shape], ...] = ()
    mission: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(self, "labels", tuple((str(k), v) for k, v in (self.labels.items() if isinstance(self.labels, Mapping) else self.labels)))
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
        A = np.asarray(self.dynamics.A, float)
        return bool(np.allclose(A @ self.start, self.start, rtol=0.0, atol=1e-12))

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
        raise InvalidProblem(src, "robot.dynamics.B", f"must be an {n} x m matrix (A is {n} x {n}), got shape {B.shape}")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B))):
        raise InvalidProblem(src, "robot.dynamics", "matrices must be finite")
    if len(dyn.position) != d:
        raise InvalidProblem(src, "robot.dynamics.position", f"must name {d} state components (the workspace is {d}-D), got {len(dyn.position)}")
    if len(set(dyn.position)) != d or any(not 0 <= i < n for i in dyn.position):
        raise InvalidProblem(src, "robot.dynamics.position", f"must be {d} distinct state indices in 0..{n - 1}, got {list(dyn.position)}")
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


def _check_robot(p: ReachProblem, pos: np.ndarray) -> None:
    """The start and goal checks for a sized robot (the robot's extent, not its point)."""
    from plansynth.reach.robot import configuration_space

    src, rb = p.source, p.robot_shape
    assert rb is not None
    if rb.radius is not None:
        if not math.isfinite(rb.radius) or rb.radius < 0:
            raise InvalidProblem(src, "robot.radius", f"must be a non-negative number, got {rb.radius}")
        if p.dim != 2:
            raise InvalidProblem(src, "robot.radius", "a disc robot needs a 2-D workspace (give robot.half_extent in 3-D)")
    else:
        h = rb.half_extent or ()
        if len(h) != p.dim:
            raise InvalidProblem(src, "robot.half_extent", f"must give {p.dim} half-extents (one per workspace axis), got {len(h)}")
        if any(not math.isfinite(v) or v < 0 for v in h):
            raise InvalidProblem(src, "robot.half_extent", f"half-extents must be non-negative numbers, got {list(h)}")
    what = f"disc of radius {rb.radius:g}" if rb.radius is not None else f"box of half-extents {list(rb.half_extent or ())}"
    m = np.array(rb.margins(p.dim))
    ws = p.workspace
    if np.any(pos - m < np.array(ws.lo)) or np.any(pos + m > np.array(ws.hi)):
        raise InvalidProblem(src, "robot.start", f"the robot ({what}) at {_fmt(pos)} does not fit in the workspace")
    for i, ob in enumerate(p.obstacles):
        if rb.radius is not None:
            if shape_to_shapely(ob).distance(shapely.Point(float(pos[0]), float(pos[1]))) < rb.radius - 1e-12 \
                    or point_in_interior(ob, pos):
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
            raise InvalidProblem(src, "goal", f"unreachable for the robot ({what}): no free area of the goal is at "
                                              "the robot's clearance from the obstacles and the workspace's border") from None
        raise InvalidProblem(src, exc.field, f"for the robot ({what}), in its configuration space (obstacles grown "
                                             f"by an outer approximation): {exc.reason}") from None


def _check_mission(p: ReachProblem, d: int) -> None:
    """Labels and mission at the door: names, shapes, the formula's syntax and names."""
    from plansynth.reach.mission.ltl import KEYWORDS, LtlSyntaxError, parse, props

    src = p.source
    seen: set[str] = set()
    for name, shape in p.labels:
        where = f"labels.{name}"
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) or name in KEYWORDS:
            raise InvalidProblem(src, where, "a label name is a letter or _ followed by letters, digits or _, and not one of X F G U R true false")
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


# ---------------------------------------------------------------- small geometry kernel
# Shared with the validator's tolerant tests; exact enough for the door checks.


def point_in_interior(shape: Shape, p: Sequence[float], tol: float = 0.0) -> bool:
    """Is ``p`` in the interior of ``shape``, deeper than ``tol``?

    A point on the boundary is not in the interior.

    >>> point_in_interior(Box((0, 0), (1, 1)), (1, 0.5))
    False
    >>> point_in_interior(Polygon(((0, 0), (2, 0), (0, 2))), (0.5, 0.5))
    True
    """
    if isinstance(shape, Box):
        return all(l + tol < x < h - tol for l, h, x in zip(shape.lo, shape.hi, p))
    sh = _ShPolygon(shape.vertices)
    pt = shapely.Point(float(p[0]), float(p[1]))
    if not sh.contains(pt):
        return False
    return tol <= 0.0 or sh.exterior.distance(pt) > tol


def _box_intersection(a: Box, b: Box) -> Box | None:
    lo = tuple(max(x, y) for x, y in zip(a.lo, b.lo))
    hi = tuple(min(x, y) for x, y in zip(a.hi, b.hi))
    if any(not h > l for l, h in zip(lo, hi)):
        return None
    return Box(lo, hi)


def box_difference(a: Box, b: Box) -> list[Box]:
    """``a`` minus the interior of ``b`` as at most 2d interior-disjoint boxes.

    >>> [(x.lo, x.hi) for x in box_difference(Box((0, 0), (3, 1)), Box((1, -1), (2, 2)))]
    [((0.0, 0.0), (1.0, 1.0)), ((2.0, 0.0), (3.0, 1.0))]
    """
    inter = _box_intersection(a, b)
    if inter is None:
        return [a]
    out: list[Box] = []
    lo, hi = list(a.lo), list(a.hi)
    for k in range(a.dim):
        if lo[k] < inter.lo[k]:
            nh = hi.copy()
            nh[k] = inter.lo[k]
            out.append(Box(tuple(lo), tuple(nh)))
        if inter.hi[k] < hi[k]:
            nl = lo.copy()
            nl[k] = inter.hi[k]
            out.append(Box(tuple(nl), tuple(hi)))
        lo[k], hi[k] = inter.lo[k], inter.hi[k]
    return out


def _measure_in_workspace(ws: Box, shape: Shape) -> float:
    if isinstance(shape, Box):
        inter = _box_intersection(ws, shape)
        return 0.0 if inter is None else inter.volume()
    return float(shape_to_shapely(ws).intersection(shape_to_shapely(shape)).area)


def free_measure(ws: Box, obstacles: Sequence[Shape], shape: Shape) -> float:
    """Area (2-D) or volume (3-D) of ``shape`` inside the workspace and outside obstacles.

    Tiny results (below 1e-12 of the workspace measure) count as zero.
    """
    tiny = 1e-12 * ws.volume()
    if ws.dim == 2:
        geom = shape_to_shapely(ws).intersection(shape_to_shapely(shape))
        if obstacles:
            geom = geom.difference(shapely.union_all([shape_to_shapely(o) for o in obstacles]))
        a = float(geom.area)
        return a if a > tiny else 0.0
    assert isinstance(shape, Box)
    first = _box_intersection(ws, shape)
    pieces = [] if first is None else [first]
    for ob in obstacles:
        assert isinstance(ob, Box)
        pieces = [q for pc in pieces for q in box_difference(pc, ob)]
    v = sum(pc.volume() for pc in pieces)
    return v if v > tiny else 0.0


# --------------------------------------------------------------------------- loading

_TOP_KEYS = {"workspace", "obstacles", "goal", "robot", "max_horizon", "name", "labels", "mission"}
_ROBOT_KEYS = {"dynamics", "start", "input_bound", "state_bounds", "radius", "half_extent"}


def load_reach_problem(path: str | Path) -> ReachProblem:
    """Read a reach-avoid problem file (YAML or JSON) per the spec.

    The problem's ``name`` defaults to the file's stem.
    """
    doc, name = load_document(path)
    return reach_problem_from_dict(doc, source=name, default_name=Path(path).stem)


def reach_problem_from_dict(doc: Any, source: str | None = None, *, default_name: str = "reach") -> ReachProblem:
    """Build a problem from a parsed document; every bad input raises InvalidProblem."""
    top = Fields(doc, source, "")
    top.reject_unknown(_TOP_KEYS)
    workspace = _parse_box(top.require("workspace"), source, "workspace")
    d = workspace.dim
    if d not in (2, 3):
        raise InvalidProblem(source, "workspace", f"must be 2-D or 3-D, got {d}-D")
    raw_obs = top.optional("obstacles", [])
    if not isinstance(raw_obs, Sequence) or isinstance(raw_obs, (str, bytes)):
        raise InvalidProblem(source, "obstacles", f"expected a list of boxes or polygons, got {type_name(raw_obs)}")
    if len(raw_obs) > MAX_OBSTACLES:
        raise InvalidProblem(source, "obstacles", f"at most {MAX_OBSTACLES} obstacles, got {len(raw_obs)}")
    obstacles = tuple(_parse_shape(o, source, f"obstacles[{i}]", d) for i, o in enumerate(raw_obs))
    mission = top.optional("mission")
    goal_raw = top.optional("goal") if mission is not None else top.require("goal")
    goal = None if goal_raw is None else _parse_shape(goal_raw, source, "goal", d)
    labels = _parse_labels(top.optional("labels", {}), source, d)

    robot = Fields(top.require("robot"), source, "robot")
    robot.reject_unknown(_ROBOT_KEYS)
    dynamics = _parse_dynamics(robot.require("dynamics"), source, d)
    n = dynamics.n_states
    start = as_float_vector(robot.require("start"), source, "robot.start", n, max_abs=MAX_COORDINATE)
    input_bound = as_float(robot.require("input_bound"), source, "robot.input_bound", positive=True, max_abs=MAX_COORDINATE)
    sb_raw = robot.optional("state_bounds")
    state_bounds = None if sb_raw is None else _parse_box(sb_raw, source, "robot.state_bounds", allow_flat=True)
    if state_bounds is not None and state_bounds.dim != n:
        raise InvalidProblem(source, "robot.state_bounds", f"must be {n}-dimensional like the state, got {state_bounds.dim}")
    radius_raw, half_raw = robot.optional("radius"), robot.optional("half_extent")
    robot_shape = None
    if radius_raw is not None and half_raw is not None:
        raise InvalidProblem(source, "robot.radius", "give either radius (a disc) or half_extent (a box), not both")
    if radius_raw is not None:
        r = as_float(radius_raw, source, "robot.radius")
        if not math.isfinite(r) or r < 0:
            raise InvalidProblem(source, "robot.radius", f"must be a non-negative number, got {r}")
        robot_shape = RobotShape(radius=r)
    elif half_raw is not None:
        robot_shape = RobotShape(half_extent=tuple(as_float_vector(half_raw, source, "robot.half_extent", d)))
    max_horizon = as_int(top.optional("max_horizon", DEFAULT_MAX_HORIZON), source, "max_horizon", hi=MAX_HORIZON)
    if max_horizon <= 0:
        raise InvalidProblem(source, "max_horizon", f"must be positive, got {max_horizon}")
    name = top.optional("name", default_name)
    if not isinstance(name, str):
        raise InvalidProblem(source, "name", f"expected a string, got {show(name)}")
    if len(name) > MAX_NAME_LENGTH:
        raise InvalidProblem(source, "name", f"at most {MAX_NAME_LENGTH} characters, got {len(name)}")
    return ReachProblem(
        workspace=workspace,
        obstacles=obstacles,
        goal=goal,
        dynamics=dynamics,
        start=np.array(start),
        input_bound=input_bound,
        state_bounds=state_bounds,
        max_horizon=max_horizon,
        name=name,
        source=source,
        robot_shape=robot_shape,
        labels=labels,
        mission=mission,
    )


def _parse_labels(value: Any, src: str | None, d: int) -> tuple[tuple[str, Shape], ...]:
    """``labels:`` maps names to boxes ``{min, max}``, polygons ``{polygon: [...]}`` (or
    ``{vertices: [...]}``, or a bare vertex list)."""
    if not isinstance(value, Mapping):
        raise InvalidProblem(src, "labels", f"expected a mapping from names to boxes or polygons, got {type_name(value)}")
    out = []
    for name, shape in value.items():
        where = f"labels.{name}"
        if isinstance(shape, Mapping) and "polygon" in shape:
            Fields(shape, src, where).reject_unknown({"polygon"})
            out.append((str(name), _parse_polygon(shape["polygon"], src, f"{where}.polygon", d)))
        else:
            out.append((str(name), _parse_shape(shape, src, where, d)))
    return tuple(out)


def _parse_box(value: Any, src: str | None, where: str, *, dim: int | None = None, allow_flat: bool = False) -> Box:
    f = Fields(value, src, where)
    f.reject_unknown({"min", "max"})
    lo = as_float_vector(f.require("min"), src, f"{where}.min", dim, max_abs=MAX_COORDINATE)
    hi = as_float_vector(f.require("max"), src, f"{where}.max", len(lo), max_abs=MAX_COORDINATE)
    if len(lo) == 0:
        raise InvalidProblem(src, f"{where}.min", "must not be empty")
    if allow_flat:
        if any(not l <= h for l, h in zip(lo, hi)):
            raise InvalidProblem(src, where, f"min {list(lo)} exceeds max {list(hi)}")
    elif any(not l < h for l, h in zip(lo, hi)):
        raise InvalidProblem(src, where, f"degenerate box: min {list(lo)} is not below max {list(hi)}")
    return Box(lo, hi)


def _parse_shape(value: Any, src: str | None, where: str, d: int) -> Shape:
    if isinstance(value, Mapping):
        if "vertices" in value:
            f = Fields(value, src, where)
            f.reject_unknown({"vertices"})
            return _parse_polygon(value["vertices"], src, f"{where}.vertices", d)
        return _parse_box(value, src, where, dim=d)
    if isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        return _parse_polygon(value, src, where, d)
    raise InvalidProblem(src, where, f"expected a box {{min, max}} or a polygon (list of vertices), got {type_name(value)}")


def _parse_polygon(value: Any, src: str | None, where: str, d: int) -> Polygon:
    if d != 2:
        raise InvalidProblem(src, where, f"polygons are 2-D but the workspace is {d}-D (use boxes)")
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(src, where, f"expected a list of [x, y] vertices, got {type_name(value)}")
    if len(value) > MAX_VERTICES:
        raise InvalidProblem(src, where, f"at most {MAX_VERTICES} vertices, got {len(value)}")
    verts = tuple(as_float_vector(v, src, f"{where}[{i}]", 2, max_abs=MAX_COORDINATE) for i, v in enumerate(value))
    poly = Polygon(verts)
    why = polygon_problem(poly)
    if why is not None:
        raise InvalidProblem(src, where, why)
    return poly


def _parse_dynamics(value: Any, src: str | None, d: int) -> LinearDynamics:
    from plansynth.reach.dynamics import named_model

    where = "robot.dynamics"
    f = Fields(value, src, where)
    if "model" in value and value["model"] != "explicit":
        f.reject_unknown({"model", "dt", "order"})
        model = f.require("model")
        if not isinstance(model, str) or model not in NAMED_MODELS:
            raise InvalidProblem(src, f"{where}.model", f"unknown model {show(model)} (known: {', '.join(NAMED_MODELS)}, or give A and B)")
        dt = as_float(f.require("dt"), src, f"{where}.dt", positive=True, max_abs=MAX_DT)
        order_raw = f.optional("order")
        order = None if order_raw is None else as_int(order_raw, src, f"{where}.order", hi=MAX_ORDER)
        implied = {"single-integrator": 1, "double-integrator": 2}.get(model)
        if implied is None and order is None:
            raise InvalidProblem(src, f"{where}.order", "missing required field (integrator-chain needs its order)")
        if order is not None and order < 1:
            raise InvalidProblem(src, f"{where}.order", f"must be a positive integer, got {order}")
        if implied is not None and order is not None and order != implied:
            raise InvalidProblem(src, f"{where}.order", f"{model} has order {implied}, got {order}")
        return named_model(model, d, dt, order)
    f.reject_unknown({"model", "A", "B", "position", "dt"})
    A = _parse_matrix(f.require("A"), src, f"{where}.A")
    B = _parse_matrix(f.require("B"), src, f"{where}.B")
    n = A.shape[0]
    if A.shape != (n, n):
        raise InvalidProblem(src, f"{where}.A", f"must be square, got {A.shape[0]} x {A.shape[1]}")
    if B.shape[0] != n:
        raise InvalidProblem(src, f"{where}.B", f"must have {n} rows like A, got {B.shape[0]} x {B.shape[1]}")
    position = as_int_vector(f.require("position"), src, f"{where}.position", d)
    if len(set(position)) != d or any(not 0 <= i < n for i in position):
        raise InvalidProblem(src, f"{where}.position", f"must be {d} distinct state indices in 0..{n - 1}, got {list(position)}")
    dt_raw = f.optional("dt")
    dt = None if dt_raw is None else as_float(dt_raw, src, f"{where}.dt", positive=True, max_abs=MAX_DT)
    return LinearDynamics(A=A, B=B, position=position, dt=dt, model="explicit", order=None)


def _parse_matrix(value: Any, src: str | None, where: str) -> np.ndarray:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)) or len(value) == 0:
        raise InvalidProblem(src, where, f"expected a non-empty list of rows, got {show(value)}")
    if len(value) > MAX_STATES:
        raise InvalidProblem(src, where, f"at most {MAX_STATES} rows, got {len(value)}")
    for i, r in enumerate(value):
        if isinstance(r, Sequence) and len(r) > MAX_STATES:
            raise InvalidProblem(src, f"{where}[{i}]", f"at most {MAX_STATES} columns, got {len(r)}")
    rows = [as_float_vector(r, src, f"{where}[{i}]", max_abs=MAX_COORDINATE) for i, r in enumerate(value)]
    width = len(rows[0])
    if width == 0:
        raise InvalidProblem(src, f"{where}[0]", "empty row")
    for i, r in enumerate(rows):
        if len(r) != width:
            raise InvalidProblem(src, f"{where}[{i}]", f"row of length {len(r)}, expected {width} like row 0")
    return np.array(rows, dtype=float)


# --------------------------------------------------------------------------- writing


def _num(x: float) -> float | int:
    return int(x) if float(x).is_integer() and abs(x) < 2**53 else float(x)


def _box_to_dict(b: Box) -> dict:
    return {"min": [_num(v) for v in b.lo], "max": [_num(v) for v in b.hi]}


def _shape_to_dict(s: Shape) -> Any:
    if isinstance(s, Box):
        return _box_to_dict(s)
    return [[_num(x), _num(y)] for x, y in s.vertices]


def reach_problem_to_dict(problem: ReachProblem) -> dict:
    """The spec document of a problem; ``reach_problem_from_dict`` reads it back equal.

    >>> from plansynth.reach.families import maze
    >>> p = maze(1)
    >>> reach_problem_from_dict(reach_problem_to_dict(p)) == p
    True
    """
    dyn = problem.dynamics
    if dyn.model == "explicit":
        dd: dict[str, Any] = {
            "A": [[_num(v) for v in row] for row in dyn.A.tolist()],
            "B": [[_num(v) for v in row] for row in dyn.B.tolist()],
            "position": list(dyn.position),
        }
        if dyn.dt is not None:
            dd["dt"] = _num(dyn.dt)
    else:
        dd = {"model": dyn.model, "dt": _num(dyn.dt)}  # type: ignore[arg-type]
        if dyn.model == "integrator-chain":
            dd["order"] = dyn.order
    robot: dict[str, Any] = {
        "dynamics": dd,
        "start": [_num(v) for v in problem.start.tolist()],
        "input_bound": _num(problem.input_bound),
    }
    if problem.state_bounds is not None:
        robot["state_bounds"] = _box_to_dict(problem.state_bounds)
    rs = problem.robot_shape
    if rs is not None and not rs.is_point:
        if rs.radius is not None:
            robot["radius"] = _num(rs.radius)
        else:
            robot["half_extent"] = [_num(v) for v in rs.half_extent]  # type: ignore[union-attr]
    out = {
        "name": problem.name,
        "workspace": _box_to_dict(problem.workspace),
        "obstacles": [_shape_to_dict(o) for o in problem.obstacles],
        "goal": None if problem.goal is None else _shape_to_dict(problem.goal),
        "robot": robot,
        "max_horizon": problem.max_horizon,
    }
    if problem.goal is None:
        del out["goal"]
    if problem.labels:
        out["labels"] = {k: (_box_to_dict(v) if isinstance(v, Box) else {"polygon": _shape_to_dict(v)}) for k, v in problem.labels}
    if problem.mission is not None:
        out["mission"] = problem.mission
    return out

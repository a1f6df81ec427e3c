"""Robot size: the configuration space of a disc or box robot (a problem's ``robot.radius``
or ``robot.half_extent``).

A robot of shape K (centred on its reference point, the position the dynamics move)
collides with an obstacle O exactly when its reference point lies in the Minkowski sum
O + K, and stays in the workspace exactly when its reference point lies in the
workspace shrunk by K. :func:`configuration_space` turns a problem with a sized robot
into the point-robot problem every planner already solves (the standard construction,
Lozano-Perez, "Spatial planning: a configuration space approach", IEEE Trans.
Computers 1983):

- a **box** robot of half-extents (hx, hy[, hz]): box obstacles grow to boxes
  ``[lo - h, hi + h]`` (exact), polygon obstacles to ``P + K`` (exact: the polygon
  united with the convex hull of each edge and the box's corners), the workspace
  shrinks to ``[lo + h, hi - h]`` (exact);
- grown obstacles are clipped to the shrunk workspace (nothing outside it is free);
- a **disc** robot of radius R (2-D only): K is covered by the regular 16-gon
  circumscribing the disc (its edges touch the circle), so every obstacle grows by a
  polygon that *contains* O + disc: an outer approximation, conservative (every plan
  keeps clearance >= R; a plan that needs clearance between R and R / cos(pi/16) =
  1.02 R is missed). The workspace shrinks by R exactly.

A non-convex inflated polygon that encloses a pocket loses the pocket (its exterior
ring is kept): conservative as well. :func:`plansynth.reach.solve` plans on this
problem and validates against the original one; the validator checks clearance itself
(distance from each sample and segment to each obstacle >= R for a disc; for a box, the
robot's box at each sample and the area it sweeps along each segment against each
obstacle), without this module.

The module sits below the problem value: :class:`RobotShape` is one of its fields, and
its check at the door asks for the configuration space (a start or goal the sized robot
cannot occupy is refused there).

>>> from plansynth.reach.families import maze
>>> p = with_robot(maze(1), RobotShape(half_extent=(0.25, 0.25)))
>>> c = configuration_space(p)
>>> c.workspace, c.obstacles[0]
(Box(lo=(0.25, 0.25), hi=(29.75, 29.75)), Box(lo=(0.25, 14.25), hi=(27.25, 15.75)))
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Protocol, TypeVar

import numpy as np
import shapely
from shapely.geometry import MultiPoint
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.geometry import Box, Polygon, Shape, shape_to_shapely

__all__ = [
    "RobotShape",
    "configuration_space",
    "with_robot",
    "disc_polygon",
    "DISC_SIDES",
    "robot_note",
    "grown_by_box",
    "clipped",
]

#: sides of the polygon circumscribing a disc robot
DISC_SIDES = 16


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


class _Problem(Protocol):
    """What :func:`configuration_space` reads of a :class:`~plansynth.reach.problem.ReachProblem`
    (this module sits below the problem value, whose check at the door asks for its
    configuration space, so it names the fields it needs instead of importing it)."""

    workspace: Box
    obstacles: tuple[Shape, ...]
    state_bounds: Box | None
    robot_shape: RobotShape | None
    dynamics: Any
    name: str


Problem = TypeVar("Problem", bound=_Problem)


def disc_polygon(radius: float, sides: int = DISC_SIDES) -> np.ndarray:
    """Vertices (CCW, centred on 0) of the regular polygon circumscribing the disc:
    its vertices lie at radius R / cos(pi / sides), its edges touch the circle.

    >>> v = disc_polygon(1.0, 4)
    >>> bool(np.allclose(np.abs(v).max(axis=0), [1.0, 1.0]))
    True
    """
    r = radius / math.cos(math.pi / sides)
    ang = math.pi / sides + 2 * math.pi * np.arange(sides) / sides
    return np.stack([r * np.cos(ang), r * np.sin(ang)], axis=1)


def _kernel(robot: RobotShape) -> np.ndarray:
    if robot.radius is not None:
        # 1e-9 larger, so that rounding the grown polygon to 1e-10 (below) stays outside
        return disc_polygon(robot.radius + 1e-9)
    hx, hy = robot.half_extent[:2]  # type: ignore[index]
    return np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])


def _inflate(shape: Shape, robot: RobotShape) -> Shape:
    if isinstance(shape, Box) and robot.half_extent is not None:
        h = robot.half_extent
        return Box(tuple(l - e for l, e in zip(shape.lo, h)), tuple(u + e for u, e in zip(shape.hi, h)))
    return _sum_with(shape, _kernel(robot))


def grown_by_box(shape: Shape, lo: tuple[float, ...], hi: tuple[float, ...]) -> Shape:
    """``shape + [lo, hi]``: the Minkowski sum of a shape and a box that contains 0
    (``lo <= 0 <= hi``), exact (a box grows to a box; a polygon to the union of itself
    with the convex hull of each edge and the box's corners, its pockets filled as in
    :func:`configuration_space`: a superset, conservative).

    >>> grown_by_box(Box((0, 0), (1, 1)), (-0.5, 0.0), (0.25, 0.0))
    Box(lo=(-0.5, 0.0), hi=(1.25, 1.0))
    """
    if isinstance(shape, Box):
        return Box(tuple(l + a for l, a in zip(shape.lo, lo)), tuple(h + b for h, b in zip(shape.hi, hi)))
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]], dtype=float)
    return _sum_with(shape, corners)


def _sum_with(shape: Shape, K: np.ndarray) -> Polygon:
    """A polygon plus the convex set with vertices ``K`` (see :func:`_inflate`)."""
    geom = shape_to_shapely(shape)
    verts = np.array(geom.exterior.coords[:-1])
    pieces = [geom]
    n = len(verts)
    for i in range(n):
        a, b = verts[i], verts[(i + 1) % n]
        pieces.append(MultiPoint(np.vstack([a + K, b + K]).tolist()).convex_hull)
    grown = shapely.union_all(pieces)
    if grown.geom_type != "Polygon":  # pragma: no cover - the union of a connected set is one polygon
        grown = grown.convex_hull
    outer = ShPolygon(grown.exterior.coords)
    outer = shapely.simplify(outer, 0.0)  # drop collinear vertices
    # round to 1e-10: mirror-image vertices computed on both sides of a gap then agree
    # exactly (the slab decomposition otherwise cuts 1e-15 slivers between them)
    return Polygon(tuple((round(float(x), 10), round(float(y), 10)) for x, y in outer.exterior.coords[:-1]))


def clipped(shape: Shape, ws: Box) -> list[Shape]:
    """``shape`` within the (shrunk) workspace: the decomposition's free-space polygon is
    cleaner without slivers of grown obstacles outside it (nothing outside is free)."""
    if isinstance(shape, Box):
        lo = tuple(max(a, b) for a, b in zip(shape.lo, ws.lo))
        hi = tuple(min(a, b) for a, b in zip(shape.hi, ws.hi))
        return [Box(lo, hi)] if all(h > l for l, h in zip(lo, hi)) else []
    g = shape_to_shapely(shape).intersection(shape_to_shapely(ws))
    out: list[Shape] = []
    for piece in getattr(g, "geoms", [g]):
        if isinstance(piece, ShPolygon) and piece.area > 1e-12 * ws.volume():
            ring = shapely.simplify(ShPolygon(piece.exterior.coords), 0.0)
            out.append(Polygon(tuple((float(x), float(y)) for x, y in ring.exterior.coords[:-1])))
    return out


def _shrink(box: Box, robot: RobotShape) -> Box:
    e = robot.margins(box.dim)
    return Box(tuple(l + m for l, m in zip(box.lo, e)), tuple(u - m for u, m in zip(box.hi, e)))


def configuration_space(problem: Problem) -> Problem:
    """The point-robot problem of a :class:`~plansynth.reach.problem.ReachProblem`'s
    sized robot (the problem itself when the robot has no size); checked like any
    problem."""
    robot = problem.robot_shape
    if robot is None or robot.is_point:
        return problem
    ws = _shrink(problem.workspace, robot)
    obstacles = tuple(c for o in problem.obstacles for c in clipped(_inflate(o, robot), ws))
    sb = problem.state_bounds
    if sb is not None:
        lo, hi = list(sb.lo), list(sb.hi)
        for axis, i in enumerate(problem.dynamics.position):
            lo[i] = max(lo[i], ws.lo[axis])
            hi[i] = min(hi[i], ws.hi[axis])
        sb = Box(tuple(lo), tuple(hi))
    return replace(
        problem,
        workspace=ws,
        obstacles=obstacles,
        state_bounds=sb,
        robot_shape=None,
        name=f"{problem.name} (configuration space)",
    )


def with_robot(problem: Problem, robot: RobotShape | None) -> Problem:
    """``problem`` with the robot's shape set (checked like a file's)."""
    return replace(problem, robot_shape=robot)


def robot_note(robot: RobotShape | None) -> str:
    """What the result guarantees about the robot's extent."""
    if robot is None or robot.is_point:
        return ""
    if robot.radius is not None:
        return (
            f"robot: a disc of radius {robot.radius:g}, planned among obstacles grown by the circumscribed "
            f"{DISC_SIDES}-gon (an outer approximation: conservative, clearance >= {robot.radius:g} "
            f"guaranteed, plans needing clearance below {robot.radius / math.cos(math.pi / DISC_SIDES):.4g} "
            "may be missed)"
        )
    return (
        f"robot: a box of half-extents {list(robot.half_extent)}, planned among obstacles grown by the box "  # type: ignore[arg-type]
        "(exact Minkowski sums)"
    )

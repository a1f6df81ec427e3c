"""The planners' side choices: the facets of the forbidden polygon of a pair of robots,
or of a robot and a moving obstacle (the SMC encoding of separation, Shoukry et al.,
CDC 2017, Section IV: ``|x_i - x_j|_inf >= d`` as "one of four half-planes", the
disjunction DIS-PLAN chooses from).

The relative position ``z`` (``p_i - p_j``, or ``p_i - c_k(t)`` for a moving obstacle)
keeps the separation when it lies outside the open polygon ``F = {z : A z < b}``; with
the facets of F as rows (unit outward normals), that is "some side k holds":
``A[k] z >= b[k]``. F is ``d P + K_i + (-K_j)`` (Minkowski sums of the norm's ball
scaled by the distance and the two shapes), the convex hull of the sums of their
vertices. A disc robot's disc is replaced by the 16-gon that circumscribes it
(:func:`~plansynth.reach.robot.disc_polygon`), so F contains the exact zone: a plan that
keeps a side of it keeps the separation (conservative, as the configuration space of a
disc robot is). In the infinity norm with box robots F is the box of half-sides
``d + h_i + h_j``: the 2d axis-aligned sides.

**Segments.** Relative motion within a step is linear (both robots move along straight
segments over the same time interval), so a side held at both ends of a step holds along
it: DIS-PLAN chooses one side per pair and *step*, CON-PLAN asks for it at both samples.
A moving obstacle's motion may bend at a waypoint inside a step: the side is then also
asked at each such time (the robot's position there is the interpolation of its two
samples), and the relative motion is linear between those times.

>>> from plansynth.reach.team.families import smc_crossing
>>> f = pair_facets(smc_crossing(), 0, 1)
>>> (f.A + 0.0).tolist(), f.b.tolist()
([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]], [0.5, 0.5, 0.5, 0.5])
>>> f.opposite
(2, 3, 0, 1)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from plansynth.reach.geometry import Box
from plansynth.reach.robot import disc_polygon
from plansynth.reach.team.problem import TeamProblem, TeamRobot

__all__ = ["Facets", "pair_facets", "obstacle_facets", "convex_hull"]


@dataclass(frozen=True, eq=False)
class Facets:
    """The sides of a forbidden polygon: side k holds at z when ``A[k] z >= b[k]``.
    ``opposite[k]``: the side whose normal is ``-A[k]`` (None: none); the two never hold
    together (F has an interior), so a pair cannot switch between them at one sample."""

    A: np.ndarray
    b: np.ndarray
    opposite: tuple[int | None, ...]

    @property
    def n_sides(self) -> int:
        return len(self.b)

    def margins(self, z: np.ndarray) -> np.ndarray:
        """``A z - b`` per side (rows of z: positions)."""
        return np.asarray(z, float) @ self.A.T - self.b


def convex_hull(points: np.ndarray) -> np.ndarray:
    """The CCW convex hull of 2-D points (Andrew's monotone chain), collinear points dropped.

    >>> convex_hull(np.array([[0, 0], [2, 0], [1, 0], [2, 2], [0, 2], [1, 1]])).tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    """
    pts = sorted({(float(x), float(y)) for x, y in np.asarray(points, float)})
    if len(pts) < 3:
        return np.array(pts, float).reshape(-1, 2)

    def cross(o: tuple, a: tuple, b: tuple) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1], float)


def _vertices(robot: TeamRobot, d: int) -> np.ndarray:
    """The robot's extent as points whose hull contains it (a disc: its circumscribed 16-gon)."""
    rs = robot.robot_shape
    if rs is None or rs.is_point:
        return np.zeros((1, d))
    if rs.radius is not None:
        return disc_polygon(rs.radius)
    h = np.asarray(rs.half_extent, float)
    return np.array([[sx * h[0], sy * h[1]] for sx in (-1, 1) for sy in (-1, 1)])


def _norm_ball(problem: TeamProblem) -> np.ndarray:
    if problem.separation.norm is None:
        return np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    return np.asarray(problem.separation.norm.vertices, float)


def _facets_of_hull(hull: np.ndarray) -> Facets | None:
    if len(hull) < 3:
        return None  # no area: nothing is forbidden
    A, b = [], []
    for a, c in zip(hull, np.roll(hull, -1, axis=0)):
        e = c - a
        n = np.array([e[1], -e[0]]) / float(np.hypot(e[0], e[1]))
        A.append(n)
        b.append(float(n @ a))
    return _with_opposites(np.array(A), np.array(b))


def _with_opposites(A: np.ndarray, b: np.ndarray) -> Facets:
    opp: list[int | None] = []
    for k in range(len(A)):
        match = [j for j in range(len(A)) if np.allclose(A[j], -A[k], atol=1e-12)]
        opp.append(match[0] if match else None)
    return Facets(A, b, tuple(opp))


def _box_facets(lo: np.ndarray, hi: np.ndarray) -> Facets | None:
    """F = the open box (lo, hi): sides ``z_a >= hi_a`` and ``-z_a >= -lo_a``."""
    if np.any(hi <= lo):
        return None
    d = len(lo)
    eye = np.eye(d)
    return _with_opposites(np.vstack([eye, -eye]), np.concatenate([hi, -lo]))


def _sum_sets(sets: list[np.ndarray]) -> np.ndarray:
    pts = np.zeros((1, 2))
    for s in sets:
        pts = (pts[:, None, :] + s[None, :, :]).reshape(-1, 2)
    return pts


def pair_facets(problem: TeamProblem, i: int, j: int) -> Facets | None:
    """The sides of robots i and j (relative position ``p_i - p_j``); None when nothing
    is forbidden (separation 0 between points)."""
    ri, rj = problem.robots[i], problem.robots[j]
    d = problem.separation.distance
    if problem.dim == 3 or (problem.separation.norm is None and _boxes(ri, rj)):
        half = d + _half(ri, problem.dim) + _half(rj, problem.dim)
        return _box_facets(-half, half)
    return _facets_of_hull(convex_hull(_sum_sets([d * _norm_ball(problem), _vertices(ri, 2), _vertices(rj, 2)])))


def obstacle_facets(problem: TeamProblem, i: int, k: int) -> Facets | None:
    """The sides of robot i and moving obstacle k (relative position ``p_i - c_k(t)``)."""
    ri, o = problem.robots[i], problem.moving_obstacles[k]
    d = problem.separation.distance if o.separation is None else o.separation
    if isinstance(o.shape, Box) and (problem.dim == 3 or (problem.separation.norm is None and _boxes(ri))):
        grow = d + _half(ri, problem.dim)
        return _box_facets(-np.asarray(o.shape.hi, float) - grow, -np.asarray(o.shape.lo, float) + grow)
    shape = (
        np.array([[x, y] for x in (o.shape.lo[0], o.shape.hi[0]) for y in (o.shape.lo[1], o.shape.hi[1])])
        if isinstance(o.shape, Box)
        else np.asarray(o.shape.vertices, float)
    )
    return _facets_of_hull(convex_hull(_sum_sets([d * _norm_ball(problem), _vertices(ri, 2), -shape])))


def _boxes(*robots: TeamRobot) -> bool:
    return all(r.robot_shape is None or r.robot_shape.radius is None or r.robot_shape.is_point for r in robots)


def _half(robot: TeamRobot, d: int) -> np.ndarray:
    rs = robot.robot_shape
    if rs is None or rs.is_point:
        return np.zeros(d)
    return np.asarray(rs.margins(d), float)

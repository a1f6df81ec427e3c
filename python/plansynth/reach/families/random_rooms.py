"""Small random workspaces for the property tests: random boxes and star-shaped
non-convex polygons (Shoukry et al., CDC 2016, Section II's obstacles), with start
and goal drawn in free space; deterministic in the seed.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.geometry import Box, Polygon, Shape, shape_to_shapely
from plansynth.reach.problem import ReachProblem

__all__ = ["random_workspace"]


def random_workspace(
    seed: int,
    n_obstacles: int = 5,
    *,
    dim: int = 2,
    size: float = 10.0,
    polygons: bool = True,
    order: int = 1,
    dt: float = 1.0,
    input_bound: float = 1.0,
) -> ReachProblem:
    """A small random problem: ``n_obstacles`` random boxes (and, in 2-D with
    ``polygons``, random star-shaped non-convex polygons) in ``[0, size]^dim``; start
    and goal drawn in free space (the goal is a small box around a free point).

    Deterministic in ``seed``.

    >>> p = random_workspace(3, 4)
    >>> len(p.obstacles), p.dim
    (4, 2)
    """
    if dim not in (2, 3):
        raise ValueError("dim must be 2 or 3")
    rng = np.random.default_rng(seed)
    obstacles: list[Shape] = []
    for _ in range(n_obstacles):
        if dim == 2 and polygons and rng.random() < 0.5:
            obstacles.append(_random_star(rng, size))
        else:
            lo = rng.uniform(0, size * 0.85, dim)
            ext = rng.uniform(size * 0.05, size * 0.35, dim)
            obstacles.append(Box(tuple(np.round(lo, 3)), tuple(np.round(np.minimum(lo + ext, size * 1.05), 3))))
    ws = Box((0.0,) * dim, (size,) * dim)
    free_pt = _free_point_sampler(rng, ws, obstacles)
    start_pos = free_pt()
    goal_pos = free_pt()
    half = size * 0.04
    goal = Box(tuple(goal_pos - half), tuple(goal_pos + half))
    dyn = integrator_chain(order, dim, dt)
    start = np.zeros(dyn.n_states)
    start[:dim] = start_pos
    return ReachProblem(
        workspace=ws,
        obstacles=tuple(obstacles),
        goal=goal,
        dynamics=dyn,
        start=start,
        input_bound=input_bound,
        name=f"random-{dim}d-{seed}",
    )


def _random_star(rng: np.random.Generator, size: float) -> Polygon:
    k = int(rng.integers(3, 9))
    c = rng.uniform(size * 0.1, size * 0.9, 2)
    angles = np.sort(rng.uniform(0, 2 * math.pi, k))
    # keep angular gaps below pi so the centre stays inside: star-shaped, simple
    while np.max(np.diff(np.concatenate([angles, [angles[0] + 2 * math.pi]]))) >= math.pi * 0.9:
        angles = np.sort(rng.uniform(0, 2 * math.pi, k))
    radii = rng.uniform(size * 0.04, size * 0.2, k)
    vs = tuple(
        (round(float(c[0] + r * math.cos(a)), 3), round(float(c[1] + r * math.sin(a)), 3))
        for a, r in zip(angles, radii)
    )
    return Polygon(vs)


def _free_point_sampler(rng: np.random.Generator, ws: Box, obstacles: list[Shape]):
    d = ws.dim
    geom = None
    if d == 2 and obstacles:
        geom = shapely.union_all([shape_to_shapely(o) for o in obstacles])

    def inside(p: np.ndarray) -> bool:
        if d == 2:
            return (
                geom is not None
                and geom.distance(shapely.Point(p)) < ws.hi[0] * 0.005
                or (geom is not None and geom.contains(shapely.Point(p)))
            )
        return any(all(o.lo[k] - 0.05 <= p[k] <= o.hi[k] + 0.05 for k in range(d)) for o in obstacles)  # type: ignore[union-attr]

    def sample() -> np.ndarray:
        for _ in range(10_000):
            p = np.round(rng.uniform(np.array(ws.lo) + 0.5, np.array(ws.hi) - 0.5), 3)
            if not inside(p):
                return p
        raise RuntimeError("no free point found; too many obstacles for the workspace")

    return sample

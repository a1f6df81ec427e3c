"""The overlapping convex sets of the convex-optimisation baselines
(:mod:`plansynth.reach.planners.convex_sets`): maximal free boxes grown from the obstacle
grid, checked against a brute force over the grid's cells, and IRIS regions for polygon
obstacles."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.errors import InvalidProblem
from plansynth.reach.dynamics import double_integrator
from plansynth.reach.families import gcs_maze, maze, random_workspace
from plansynth.reach.geometry import Box, Polygon, shape_to_shapely
from plansynth.reach.planners.convex_sets import (
    box_overlaps,
    maximal_free_boxes,
    obstacle_grid,
    overlapping_sets,
)
from plansynth.reach.problem import ReachProblem


def _world(obstacles: list[Box], size: float = 10.0) -> ReachProblem:
    return ReachProblem(
        workspace=Box((0.0, 0.0), (size, size)),
        obstacles=tuple(obstacles),
        goal=Box((size - 1, size - 1), (size, size)),
        dynamics=double_integrator(2, 0.5),
        start=[0.2, 0.2, 0.0, 0.0],
        input_bound=1.0,
    )


def _index_box(cuts, b: Box) -> tuple[tuple[int, ...], tuple[int, ...]]:
    lo = tuple(int(np.searchsorted(c, v)) for c, v in zip(cuts, b.lo))
    hi = tuple(int(np.searchsorted(c, v)) for c, v in zip(cuts, b.hi))
    return lo, hi


def _check_boxes(p: ReachProblem) -> None:
    """Every box free and maximal, none twice, every free cell covered, and the boxes that
    overlap connect every pair of cells that share a face (brute force over the grid)."""
    cuts, free = obstacle_grid(p)
    boxes = maximal_free_boxes(p)
    idx = [_index_box(cuts, b) for b in boxes]
    assert len(set(idx)) == len(idx)
    cover = np.zeros(free.shape, dtype=int)
    for lo, hi in idx:
        sl = tuple(slice(a, b) for a, b in zip(lo, hi))
        assert free[sl].all()  # free
        cover[sl] += 1
        for k in range(free.ndim):  # maximal: no face can move outward
            for side in (-1, 1):
                edge = lo[k] - 1 if side < 0 else hi[k]
                if 0 <= edge < free.shape[k]:
                    slab = tuple(
                        slice(a, b) if j != k else slice(edge, edge + 1) for j, (a, b) in enumerate(zip(lo, hi))
                    )
                    assert not free[slab].all()
    assert np.array_equal(cover > 0, free)
    # connectivity: union-find over the overlap graph; cells sharing a face are joined
    parent = list(range(len(boxes)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in box_overlaps(boxes):
        parent[find(i)] = find(j)
    owner = {}
    for b, (lo, hi) in enumerate(idx):
        for cell in itertools.product(*(range(a, z) for a, z in zip(lo, hi))):
            owner.setdefault(cell, find(b))
    for cell in owner:
        for k in range(free.ndim):
            nxt = tuple(c + (j == k) for j, c in enumerate(cell))
            if nxt in owner:
                assert find(owner[cell]) == find(owner[nxt])


def test_maze_boxes_are_the_corridors():
    s = overlapping_sets(maze(2))
    assert s.kind == "boxes" and s.boxes is not None
    # the three open rows and the two gap columns, each gap column crossing two rows
    assert len(s.boxes) == 5 and len(s.edges) == 4
    assert all(np.all(H @ np.array(b.lo) <= h + 1e-9) for H, h, b in zip(s.H, s.h, s.boxes))


@pytest.mark.parametrize("n", [5, 10])
def test_gcs_maze_boxes_brute_force(n):
    _check_boxes(gcs_maze(n))


def test_gcs_maze_50_box_count():
    """The 50 x 50 maze of the GCS paper: the count the module doc quotes."""
    assert len(maximal_free_boxes(gcs_maze(50))) == 1468


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(0, 9), st.integers(0, 9), st.integers(1, 4), st.integers(1, 4)), max_size=8))
def test_random_box_worlds_brute_force(rects):
    obstacles = [Box((x, y), (min(10, x + w), min(10, y + h))) for x, y, w, h in rects]
    obstacles = [o for o in obstacles if not o.contains((0.2, 0.2)) and not o.is_degenerate()]
    try:
        p = _world(obstacles)
    except InvalidProblem:  # the goal covered, say: not a problem
        return
    _check_boxes(p)


def test_box_overlaps_needs_interior():
    touching = [Box((0, 0), (1, 1)), Box((1, 0), (2, 1)), Box((0.5, 0.5), (1.5, 2))]
    assert box_overlaps(touching) == [(0, 2), (1, 2)]


def test_three_d_boxes():
    p = ReachProblem(
        workspace=Box((0, 0, 0), (4, 4, 4)),
        obstacles=(Box((1, 1, 0), (3, 3, 4)),),
        goal=Box((3.5, 3.5, 3.5), (4, 4, 4)),
        dynamics=double_integrator(3, 0.5),
        start=[0.5, 0.5, 0.5, 0, 0, 0],
        input_bound=1.0,
    )
    _check_boxes(p)
    assert len(maximal_free_boxes(p)) == 4  # a ring of four slabs around the pillar


def test_iris_regions_for_polygon_obstacles():
    """IRIS regions (Drake) where an obstacle is a polygon: each region free of the
    obstacles, the start in one, the goal met by one, and the regions connected."""
    p = random_workspace(0)
    assert any(isinstance(o, Polygon) for o in p.obstacles)
    s = overlapping_sets(p)
    assert s.kind == "iris" and s.boxes is None and len(s.H) >= 2
    rng = np.random.default_rng(1)
    for H, h in zip(s.H, s.h):
        lo, hi = np.array(p.workspace.lo), np.array(p.workspace.hi)
        pts = rng.uniform(lo, hi, size=(4000, 2))
        inside = pts[np.all(pts @ H.T <= h, axis=1)]
        assert len(inside) > 0
        for ob in p.obstacles:
            geom = shape_to_shapely(ob)
            assert not any(geom.contains(shapely.Point(*q)) for q in inside[:300])
    assert s.containing(p.start_position)
    with pytest.raises(ValueError, match="every obstacle to be a box"):
        overlapping_sets(p, "boxes")

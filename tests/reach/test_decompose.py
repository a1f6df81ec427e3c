"""Convex decomposition (Section III): properties checked against geometric oracles.

The oracles use shapely on the final regions (or exact box arithmetic in 3-D), i.e. a
different route than the decomposition's combinatorial bookkeeping.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import example, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.families import cluttered, dubins_example, maze, random_workspace
from plansynth.reach.geometry import Box, Polygon, free_measure, is_convex, point_in_interior, shape_to_shapely
from plansynth.reach.problem import ReachProblem

METHODS_2D = ["hertel-mehlhorn", "slab-y", "slab-x"]


# ------------------------------------------------------------------ oracles


def free_space(problem: ReachProblem) -> shapely.Geometry:
    ws = shape_to_shapely(problem.workspace)
    if not problem.obstacles:
        return ws
    return ws.difference(shapely.union_all([shape_to_shapely(o) for o in problem.obstacles]))


def check_2d(problem: ReachProblem, a: Abstraction) -> None:
    scale = max(h - l for l, h in zip(problem.workspace.lo, problem.workspace.hi))
    area_tol = 1e-9 * scale**2
    polys = [ShPolygon(r.vertices) for r in a.regions]
    assert [r.index for r in a.regions] == list(range(len(a.regions)))
    for r, g in zip(a.regions, polys):
        # convex, full-dimensional, CCW, H/h describe the same polygon
        assert g.is_valid and g.area > 0 and g.exterior.is_ccw
        assert is_convex(Polygon(tuple(map(tuple, r.vertices))))
        assert np.all(r.H @ r.vertices.T <= r.h[:, None] + 1e-9 * scale)
        assert np.allclose(np.linalg.norm(r.H, axis=1), 1.0)
        assert g.contains(shapely.Point(r.center))
        assert r.contains(r.center, tol=0.0)
    free = free_space(problem)
    union = shapely.union_all(polys)
    assert union.symmetric_difference(free).area < area_tol * max(1, len(polys))
    # pairwise disjoint interiors: the areas add up to the area of the union
    assert abs(sum(g.area for g in polys) - free.area) < area_tol * max(1, len(polys))
    # adjacency: symmetric, sorted, no self-loops, exactly the pairs with a shared edge
    for i, nb in enumerate(a.adjacency):
        assert list(nb) == sorted(set(nb)) and i not in nb
        for j in nb:
            assert i in a.adjacency[j]
    for i, j in itertools.combinations(range(len(polys)), 2):
        shared = polys[i].boundary.intersection(polys[j].boundary).length
        assert polys[i].intersection(polys[j]).area < area_tol
        assert (j in a.adjacency[i]) == (shared > 1e-9 * scale), (i, j, shared)
    # start and goal regions
    start = shapely.Point(problem.start_position)
    expect_start = tuple(k for k, g in enumerate(polys) if g.distance(start) <= 1e-9 * scale)
    assert a.start_regions == expect_start and len(expect_start) >= 1
    goal = shape_to_shapely(problem.goal)
    # a region whose closure meets the goal (touching counts: a plan may end on the face)
    expect_goal = tuple(k for k, g in enumerate(polys) if g.intersects(goal))
    assert a.goal_regions == expect_goal and len(expect_goal) >= 1


def box_overlap(lo1, hi1, lo2, hi2) -> np.ndarray:
    return np.minimum(hi1, hi2) - np.maximum(lo1, lo2)


def check_boxes(problem: ReachProblem, a: Abstraction) -> None:
    d = problem.dim
    boxes = [(r.vertices.min(axis=0), r.vertices.max(axis=0)) for r in a.regions]
    ws_lo, ws_hi = np.array(problem.workspace.lo), np.array(problem.workspace.hi)
    total = 0.0
    for (lo, hi), r in zip(boxes, a.regions):
        assert np.all(lo < hi) and np.all(lo >= ws_lo) and np.all(hi <= ws_hi)
        assert len(r.vertices) == 2**d
        assert r.contains(r.center, tol=0.0)
        for ob in problem.obstacles:
            assert not np.all(box_overlap(lo, hi, np.array(ob.lo), np.array(ob.hi)) > 0)
        total += float(np.prod(hi - lo))
    for (l1, h1), (l2, h2) in itertools.combinations(boxes, 2):
        assert not np.all(box_overlap(l1, h1, l2, h2) > 0)
    # disjoint regions inside the free space whose volumes add up to it cover it
    free = free_measure(problem.workspace, problem.obstacles, problem.workspace)
    assert total == pytest.approx(free, rel=1e-9)
    for i, j in itertools.combinations(range(len(boxes)), 2):
        ov = box_overlap(*boxes[i], *boxes[j])
        touching = sum(ov == 0) == 1 and sum(ov > 0) == d - 1
        assert (j in a.adjacency[i]) == touching and (i in a.adjacency[j]) == touching
    p = problem.start_position
    assert a.start_regions == tuple(k for k, (lo, hi) in enumerate(boxes) if np.all(lo <= p) and np.all(p <= hi))
    g_lo, g_hi = np.array(problem.goal.lo), np.array(problem.goal.hi)
    assert a.goal_regions == tuple(k for k, b in enumerate(boxes) if np.all(box_overlap(*b, g_lo, g_hi) >= 0))
    assert a.start_regions and a.goal_regions


# ------------------------------------------------------------------ problems


def problem_from_obstacles(obstacles, size: float, dim: int = 2) -> ReachProblem | None:
    """A problem with these obstacles and the first free half-integer points as start/goal."""
    ws = Box((0.0,) * dim, (size,) * dim)
    pts = [np.array(p) + 0.5 for p in itertools.product(range(int(size)), repeat=dim)]
    free = [
        p
        for p in pts
        if not any(point_in_interior(o, p) for o in obstacles) and not any(_on_boundary(o, p) for o in obstacles)
    ]
    if len(free) < 2:
        return None
    start, goal = free[0], free[-1]
    return ReachProblem(
        workspace=ws,
        obstacles=tuple(obstacles),
        goal=Box(tuple(goal - 0.25), tuple(goal + 0.25)),
        dynamics=single_integrator(dim, 1.0),
        start=start,
        input_bound=1.0,
    )


def _on_boundary(o, p) -> bool:
    if isinstance(o, Box):
        return all(l <= x <= h for l, h, x in zip(o.lo, o.hi, p))
    return shape_to_shapely(o).distance(shapely.Point(p)) == 0


@st.composite
def grid_boxes(draw, dim: int = 2, size: int = 8, max_n: int = 6):
    """Boxes with integer corners: touching, shared edges, sticking out of the workspace."""
    n = draw(st.integers(0, max_n))
    out = []
    for _ in range(n):
        lo = [draw(st.integers(-1, size - 1)) for _ in range(dim)]
        hi = [l + draw(st.integers(1, 4)) for l in lo]
        out.append(Box(tuple(lo), tuple(hi)))
    return out


@st.composite
def grid_polygons(draw, size: int = 8, max_n: int = 4):
    """Non-convex, integer-coordinate polygons (L shapes, notched boxes, triangles)."""
    n = draw(st.integers(0, max_n))
    out = []
    for _ in range(n):
        x, y = draw(st.integers(-1, size - 2)), draw(st.integers(-1, size - 2))
        w, h = draw(st.integers(2, 4)), draw(st.integers(2, 4))
        kind = draw(st.sampled_from(["L", "tri", "notch"]))
        if kind == "L":
            vs = ((x, y), (x + w, y), (x + w, y + 1), (x + 1, y + 1), (x + 1, y + h), (x, y + h))
        elif kind == "tri":
            vs = ((x, y), (x + w, y), (x + draw(st.integers(0, w)), y + h))
        else:
            vs = ((x, y), (x + w, y), (x + w, y + h), (x + w / 2, y + h / 2), (x, y + h))
        out.append(Polygon(vs))
    return out


# ------------------------------------------------------------------ tests


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_maze_regions_are_the_corridors_and_gaps(n: int) -> None:
    p = maze(n)
    a = abstract(p)
    check_2d(p, a)
    assert a.n_regions == 2 * n + 1  # n + 1 corridors and n gaps: optimal
    # a path graph: corridor - gap - corridor - ...
    assert sorted(len(nb) for nb in a.adjacency) == [1, 1] + [2] * (2 * n - 1)


@pytest.mark.parametrize("problem", [cluttered(), dubins_example()], ids=["cluttered", "dubins"])
@pytest.mark.parametrize("method", ["auto"] + METHODS_2D)
def test_examples_with_polygons(problem: ReachProblem, method: str) -> None:
    check_2d(problem, abstract(problem, method=method))


@pytest.mark.parametrize("method", METHODS_2D)
def test_mirrored_discs_cut_no_slivers(method: str) -> None:
    # shapely's disc puts sin(t) and sin(pi - t) on its two sides, and the mirror copy
    # repeats them: sweep levels 1e-15 apart. A slab that thin made sliver regions
    # between pieces sharing a facet, and the region graph fell apart.
    disc = shapely.Point(3.0, 3.0).buffer(1.0)
    mirror = shapely.affinity.scale(disc, -1, 1, origin=(5, 5))
    obstacles = tuple(Polygon(tuple(map(tuple, g.exterior.coords[:-1]))) for g in (disc, mirror))
    p = ReachProblem(
        workspace=Box((0.0, 0.0), (10.0, 10.0)),
        obstacles=obstacles,
        goal=Box((4.75, 9.0), (5.25, 9.5)),
        dynamics=single_integrator(2, 1.0),
        start=np.array([5.0, 0.5]),
        input_bound=1.0,
    )
    a = abstract(p, method=method)
    check_2d(p, a)
    assert min(r.measure() for r in a.regions) > 1e-6
    # the free space is connected, so is the region graph
    seen, todo = set(a.start_regions), list(a.start_regions)
    while todo:
        todo.extend(j for j in a.adjacency[todo.pop()] if j not in seen and not seen.add(j))
    assert seen == set(range(a.n_regions))


def test_auto_picks_fewest_regions() -> None:
    a = abstract(cluttered())
    counts = dict(a.candidates)
    assert a.n_regions == min(counts.values()) == counts[a.method]
    assert set(counts) == {"slab-y", "slab-x", "hertel-mehlhorn"}  # polygons: no boxes


@settings(max_examples=40)
@given(seed=st.integers(0, 10_000), n=st.integers(0, 8), method=st.sampled_from(["auto"] + METHODS_2D))
@example(seed=1940, n=5, method="slab-x")  # a slab corner inside an obstacle edge, kept at 180 deg - 1e-16
def test_random_workspaces(seed: int, n: int, method: str) -> None:
    p = random_workspace(seed, n)
    check_2d(p, abstract(p, method=method))


@settings(max_examples=40)
@given(obstacles=grid_boxes(), method=st.sampled_from(["auto", "boxes"] + METHODS_2D))
def test_aligned_boxes_2d(obstacles, method: str) -> None:
    p = problem_from_obstacles(obstacles, 8)
    if p is None:
        return
    a = abstract(p, method=method)
    check_2d(p, a)
    if method == "boxes":
        check_boxes(p, a)


@settings(max_examples=40)
@given(obstacles=grid_polygons(), boxes=grid_boxes(max_n=2), method=st.sampled_from(["auto"] + METHODS_2D))
def test_aligned_polygons_2d(obstacles, boxes, method: str) -> None:
    p = problem_from_obstacles(obstacles + boxes, 8)
    if p is None:
        return
    check_2d(p, abstract(p, method=method))


@settings(max_examples=30)
@given(obstacles=grid_boxes(dim=3, size=6, max_n=5))
def test_boxes_3d(obstacles) -> None:
    p = problem_from_obstacles(obstacles, 6, dim=3)
    if p is None:
        return
    check_boxes(p, abstract(p))


def test_3d_random_and_hand_made() -> None:
    for seed in range(5):
        p = random_workspace(seed, 6, dim=3)
        check_boxes(p, abstract(p))
    # a 3-D maze floor: a slab with one hole gives the two halves, the hole, and rim boxes
    slab = [Box((0, 0, 4), (10, 10, 5))]
    hole_floor = [
        Box((0, 0, 4), (4, 10, 5)),
        Box((6, 0, 4), (10, 10, 5)),
        Box((4, 0, 4), (6, 4, 5)),
        Box((4, 6, 4), (6, 10, 5)),
    ]
    p = problem_from_obstacles(hole_floor, 10, dim=3)
    a = abstract(p)
    check_boxes(p, a)
    assert a.n_regions == 3  # below, the hole, above
    p = problem_from_obstacles(slab, 10, dim=3)
    a = abstract(p)
    check_boxes(p, a)
    assert a.n_regions == 2 and a.adjacency == ((), ())  # disconnected halves


def test_3d_rejects_polygon_methods() -> None:
    p = random_workspace(1, 3, dim=3)
    with pytest.raises(ValueError, match="boxes"):
        abstract(p, method="hertel-mehlhorn")


def test_boxes_method_needs_boxes() -> None:
    with pytest.raises(ValueError, match="box"):
        abstract(cluttered(), method="boxes")


def test_disconnected_free_space_has_no_edges_across() -> None:
    wall = Box((4, -1), (5, 11))
    p = problem_from_obstacles([wall], 10)
    a = abstract(p)
    check_2d(p, a)
    left = {r.index for r in a.regions if r.center[0] < 4}
    for i in left:
        assert all(j in left for j in a.adjacency[i])


def test_start_on_a_region_boundary_is_in_both() -> None:
    # start exactly on the line between the corridor and the gap of maze-1
    p = maze(1)
    start = p.start.copy()
    start[:2] = (28, 14.5)
    q = ReachProblem(**{**{k: getattr(p, k) for k in p.__dataclass_fields__}, "start": start})
    a = abstract(q)
    assert len(a.start_regions) == 2

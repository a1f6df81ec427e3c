"""The overlapping convex sets of free space that the convex-optimisation planners are
given, built as their users build them (beyond Shoukry et al., CDC 2016: the sets of the
baselines ``gcs`` and ``fpp``).

Graphs of Convex Sets (Marcucci, Petersen, von Wrangel and Tedrake, "Motion planning
around obstacles with convex optimization", Science Robotics 2023, Section "Results")
and fast path planning (Marcucci, Nobel, Tedrake and Boyd, "Fast path planning through
large collections of safe boxes", IEEE T-RO 2024, Section II) plan through a collection
of convex sets that *overlap*: a curve passes from one set to the next inside their
intersection, so the sets' overlaps, not shared faces, are what makes the graph. The
lazy planner's decomposition (:func:`plansynth.reach.abstraction.abstract`) tiles the
free space with disjoint regions that meet only along faces; these sets cover it with
overlaps instead.

* :func:`maximal_free_boxes` (every obstacle a box, any dimension): the grid of all
  obstacle coordinates (the decomposition's grid, :mod:`plansynth.reach.abstraction.boxes`),
  and for every run of free cells along one axis (a maximal segment of a row, column, ...),
  that run grown along the other axes, in every axis order, in both directions, as far
  as the slab stays free. Each box is *maximal* (no face can move outward and stay
  free), so none contains another, and every free cell lies in one box per axis order;
  two cells that share a face lie together in one of them, so boxes that overlap with
  positive volume connect the whole free space. On the GCS paper's mazes these are the
  straight corridor stretches, crossing where corridors meet (50 x 50: 1,468 boxes).
* :func:`iris_regions` (polygon obstacles, 2-D): Drake's IRIS (Deits and Tedrake,
  "Computing large convex regions of obstacle-free space through semidefinite
  programming", WAFR 2014; ``pydrake.geometry.optimization.Iris``) seeded at the start,
  at the goal's centre and at the centre of every decomposition region no region grown
  so far contains, the obstacles given as their convex pieces; the GCS paper's
  environments use IRIS regions.

:func:`overlapping_sets` picks the construction (``"auto"``: boxes when every obstacle
is a box, IRIS otherwise) and returns :class:`ConvexSets`: each set in ``H p <= h``
form, and the pairs of sets whose intersection has nonempty interior.

>>> from plansynth.reach.families import maze
>>> s = overlapping_sets(maze(1))
>>> s.kind, len(s.sets), s.edges
('boxes', 3, ((0, 1), (1, 2)))
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from plansynth.budget import checkpoint
from plansynth.errors import SolverUnavailable
from plansynth.reach.abstraction.boxes import obstacle_grid
from plansynth.reach.geometry import Box, convex_pieces, halfspaces
from plansynth.reach.problem import ReachProblem

__all__ = [
    "ConvexSets",
    "SET_KINDS",
    "overlapping_sets",
    "maximal_free_boxes",
    "box_overlaps",
    "iris_regions",
    "obstacle_grid",
]

#: The constructions :func:`overlapping_sets` knows (``auto``: boxes for box worlds, IRIS
#: for polygons).
SET_KINDS = ("auto", "boxes", "iris")
#: A set must be at least this deep (relative to the workspace) in every direction to count.
MIN_THICKNESS = 1e-9
#: IRIS: at most this many regions (seeds beyond are not grown).
IRIS_MAX_REGIONS = 500


@dataclass(frozen=True)
class ConvexSets:
    """Convex subsets of the free space: set ``i`` is ``{p : H[i] p <= h[i]}``;
    ``boxes`` holds them as :class:`~plansynth.reach.geometry.Box` values when they are
    boxes (None for IRIS regions); ``edges`` the pairs ``(i, j)``, ``i < j``, whose
    intersection has nonempty interior; ``kind`` the construction; ``seconds`` its time."""

    kind: str
    H: tuple[np.ndarray, ...]
    h: tuple[np.ndarray, ...]
    edges: tuple[tuple[int, int], ...]
    boxes: tuple[Box, ...] | None = None
    seconds: float = 0.0

    @property
    def sets(self) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        return tuple(zip(self.H, self.h))

    def containing(self, p: Sequence[float], tol: float = 1e-9) -> tuple[int, ...]:
        """The sets that contain point ``p`` (closed, within ``tol``)."""
        q = np.asarray(p, float)
        return tuple(i for i, (H, h) in enumerate(zip(self.H, self.h)) if np.all(H @ q <= h + tol))


def _runs(free: np.ndarray, axis: int) -> list[tuple[tuple[int, ...], tuple[int, ...]]]:
    """The maximal runs of free cells along ``axis``, as index boxes ``(lo, hi)`` (hi
    exclusive)."""
    a = np.moveaxis(free, axis, -1)
    pad = np.zeros(a.shape[:-1] + (1,), dtype=bool)
    edges = np.diff(np.concatenate([pad, a, pad], axis=-1).astype(np.int8), axis=-1)
    starts = np.argwhere(edges == 1)
    ends = np.argwhere(edges == -1)
    out = []
    for s, e in zip(starts, ends):  # (argwhere orders both alike: row-major, one start per end)
        other = [int(v) for v in s[:-1]]
        lo = other[:axis] + [int(s[-1])] + other[axis:]
        hi = [v + 1 for v in other[:axis]] + [int(e[-1])] + [v + 1 for v in other[axis:]]
        out.append((tuple(lo), tuple(hi)))
    return out


def _grow(free: np.ndarray, lo: list[int], hi: list[int], axis: int) -> None:
    """Grow the index box ``lo..hi`` along ``axis`` in both directions while the slab
    stays free (in place)."""
    d = free.ndim

    def slab(k: int) -> tuple[slice, ...]:
        return tuple(slice(lo[j], hi[j]) if j != axis else slice(k, k + 1) for j in range(d))

    while lo[axis] > 0 and free[slab(lo[axis] - 1)].all():
        lo[axis] -= 1
    while hi[axis] < free.shape[axis] and free[slab(hi[axis])].all():
        hi[axis] += 1


def maximal_free_boxes(problem: ReachProblem) -> list[Box]:
    """The maximal free boxes of a box world grown from its obstacle grid (see the module
    doc), sorted by their lower corner (last axis first).

    >>> from plansynth.reach.families import maze
    >>> [b.lo + b.hi for b in maximal_free_boxes(maze(1))]
    [(0.0, 0.0, 30.0, 14.5), (27.0, 0.0, 29.0, 30.0), (0.0, 15.5, 30.0, 30.0)]
    """
    cuts, free = obstacle_grid(problem)
    d = free.ndim
    found: set[tuple[tuple[int, ...], tuple[int, ...]]] = set()
    for order in itertools.permutations(range(d)):
        for lo0, hi0 in _runs(free, order[0]):
            checkpoint()
            lo, hi = list(lo0), list(hi0)
            for axis in order[1:]:
                _grow(free, lo, hi, axis)
            found.add((tuple(lo), tuple(hi)))
    boxes = [
        Box(tuple(float(cuts[k][lo[k]]) for k in range(d)), tuple(float(cuts[k][hi[k]]) for k in range(d)))
        for lo, hi in found
    ]
    return sorted(boxes, key=lambda b: (b.lo[::-1], b.hi[::-1]))


def box_overlaps(boxes: Sequence[Box], *, tol: float = 0.0) -> list[tuple[int, int]]:
    """The pairs ``(i, j)``, ``i < j``, of boxes whose intersection has nonempty
    interior (deeper than ``tol`` along every axis): sorted by the first axis, each box
    compared with those that start before it ends.

    >>> box_overlaps([Box((0, 0), (2, 1)), Box((1, 0), (3, 1)), Box((2, 0), (4, 1))])
    [(0, 1), (1, 2)]
    """
    if not boxes:
        return []
    lo = np.array([b.lo for b in boxes], float)
    hi = np.array([b.hi for b in boxes], float)
    order = np.argsort(lo[:, 0], kind="stable")
    slo, shi = lo[order], hi[order]
    out = []
    for a in range(len(boxes)):
        checkpoint()
        # candidates: boxes after a in the order that start before a ends (axis 0)
        end = int(np.searchsorted(slo[:, 0], shi[a, 0] - tol, side="left"))
        if end <= a + 1:
            continue
        cand = np.arange(a + 1, end)
        deep = np.minimum(shi[cand], shi[a]) - np.maximum(slo[cand], slo[a])
        for b in cand[np.all(deep > tol, axis=1)]:
            i, j = int(order[a]), int(order[b])
            out.append((min(i, j), max(i, j)))
    return sorted(out)


def _import_iris():  # pragma: no cover - drake is a dependency of the baselines
    try:
        from pydrake.geometry.optimization import HPolyhedron, Iris, IrisOptions
    except ImportError as exc:
        raise SolverUnavailable("gcs", "IRIS regions need Drake (pip install drake)") from exc
    return HPolyhedron, Iris, IrisOptions


def iris_regions(
    problem: ReachProblem, seeds: Sequence[Sequence[float]] | None = None
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Drake's IRIS regions (see the module doc) in ``H p <= h`` form, within the
    workspace: grown from ``seeds`` (default: the start, the goal's centre, then the
    centre of every region of :func:`plansynth.reach.abstraction.abstract` that no region
    grown so far contains), a seed already inside a grown region skipped, at most
    :data:`IRIS_MAX_REGIONS`. A region that fails to contain its seed is dropped."""
    HPolyhedron, Iris, IrisOptions = _import_iris()
    ws = problem.workspace
    domain = HPolyhedron.MakeBox(np.array(ws.lo), np.array(ws.hi))
    obstacles = [HPolyhedron(H, h) for ob in problem.obstacles for H, h in convex_pieces(ob)]
    opts = IrisOptions()
    opts.require_sample_point_is_contained = True
    if seeds is None:
        from plansynth.reach.abstraction import abstract

        goal = problem.goal
        gH, gh = halfspaces(goal)  # type: ignore[arg-type]
        centre = (
            (np.asarray(goal.lo) + np.asarray(goal.hi)) / 2
            if isinstance(goal, Box)
            else np.mean(np.asarray(goal.vertices, float), axis=0)  # type: ignore[union-attr]
        )
        seed_list = [np.asarray(problem.start_position, float), centre]
        seed_list += [r.center for r in abstract(problem).regions]
    else:
        seed_list = [np.asarray(s, float) for s in seeds]
    regions: list[tuple[np.ndarray, np.ndarray]] = []
    for s in seed_list:
        checkpoint()
        if len(regions) >= IRIS_MAX_REGIONS:
            break
        if any(np.all(H @ s <= h + 1e-9) for H, h in regions):
            continue
        try:
            r = Iris(obstacles, s, domain, opts)
        except RuntimeError:
            continue  # the seed is in collision or IRIS failed there: skip it
        H, h = np.asarray(r.A(), float), np.asarray(r.b(), float)
        norms = np.linalg.norm(H, axis=1)
        keep = norms > 0
        H, h = H[keep] / norms[keep, None], h[keep] / norms[keep]
        if np.all(H @ s <= h + 1e-9):
            regions.append((H, h))
    return regions


def _interiors_meet(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray], tol: float) -> bool:
    """Do two polytopes share a ball of radius > ``tol``? (Drake's Chebyshev centre of
    their intersection.)"""
    HPolyhedron, _, _ = _import_iris()
    H, h = np.vstack([a[0], b[0]]), np.concatenate([a[1], b[1]])
    both = HPolyhedron(H, h)
    if both.IsEmpty():
        return False
    try:
        c = np.asarray(both.ChebyshevCenter(), float)
    except RuntimeError:
        return False
    return bool(np.min((h - H @ c) / np.linalg.norm(H, axis=1)) > tol)


def overlapping_sets(problem: ReachProblem, kind: str = "auto") -> ConvexSets:
    """The overlapping convex sets of ``problem``'s free space (see the module doc):
    ``kind`` ``"boxes"``, ``"iris"`` or ``"auto"`` (boxes when every obstacle is a box)."""
    if kind not in SET_KINDS:
        raise ValueError(f"unknown set construction {kind!r} (known: {', '.join(SET_KINDS)})")
    t0 = time.perf_counter()
    all_boxes = all(isinstance(o, Box) for o in problem.obstacles)
    if kind == "auto":
        kind = "boxes" if all_boxes else "iris"
    scale = max(h - l for l, h in zip(problem.workspace.lo, problem.workspace.hi))
    tol = MIN_THICKNESS * scale
    if kind == "boxes":
        if not all_boxes:
            raise ValueError("maximal free boxes need every obstacle to be a box (use iris)")
        boxes = maximal_free_boxes(problem)
        hs = [halfspaces(b) for b in boxes]
        return ConvexSets(
            "boxes",
            tuple(H for H, _ in hs),
            tuple(h for _, h in hs),
            tuple(box_overlaps(boxes, tol=tol)),
            tuple(boxes),
            time.perf_counter() - t0,
        )
    if problem.dim != 2:
        raise ValueError("IRIS regions are built for 2-D workspaces here")
    regions = iris_regions(problem)
    edges = []
    for i, j in itertools.combinations(range(len(regions)), 2):
        checkpoint()
        if _interiors_meet(regions[i], regions[j], tol):
            edges.append((i, j))
    return ConvexSets(
        "iris",
        tuple(H for H, _ in regions),
        tuple(h for _, h in regions),
        tuple(edges),
        None,
        time.perf_counter() - t0,
    )

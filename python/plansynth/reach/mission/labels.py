"""The abstraction that respects labels, in the reading a mission asks for.

The convex decomposition of the free space (:func:`plansynth.reach.abstraction.abstract`,
Shoukry et al., CDC 2016, Section III) of the problem the planners plan in
(:func:`planning_problem`: obstacles grown by the obstacle margin, the configuration
space of a sized robot) is refined by the label boundaries so that every region lies
inside or outside each label (interiors disjoint). With a margin r > 0 a label a is cut
twice, along its shrunk and its grown shape (:mod:`plansynth.reach.offsets`): a region
then lies at depth >= r in a (``a`` holds there), at distance >= r from it (``!a``
holds), or in the band between (neither). :class:`LabelledAbstraction` says which
literals hold in each region: ``labels_of`` and ``negs_of``, the mission's **label
reading per region**, which the encodings take as given (a region's letter at a sample
in it and, with segment safety, along a segment in it).

Refinement, per region and cut: a convex cut splits a region into the part inside it and
at most one convex piece outside per edge (cut off one supporting half-plane at a time);
a non-convex polygon label is cut by shapely's intersection and difference, each
decomposed into convex pieces (Hertel-Mehlhorn). Only the cuts whose bounding boxes meet
a region's are tried. Adjacency is inherited: two pieces are adjacent when they come
from the same or from adjacent regions and share an edge of positive length (collinear,
overlapping edges, within a tolerance relative to the workspace; candidate pairs from a
spatial index). The work checks the budget of the enclosing phase
(:func:`plansynth.budget.checkpoint`), so a label of a thousand vertices or a thousand
labels end within ``--timeout``.

>>> from plansynth.reach.problem import Box, ReachProblem
>>> from plansynth.reach.dynamics import single_integrator
>>> p = ReachProblem(workspace=Box((0, 0), (4, 4)), obstacles=(), goal=None,
...     dynamics=single_integrator(2, 1.0), start=[0.5, 0.5], input_bound=1.0,
...     labels=(("a", Box((1, 1), (2, 2))),), mission="F a")
>>> la = label_abstraction(p)
>>> la.n_regions, sorted(sum((list(s) for s in la.labels_of), []))
(5, ['a'])
>>> from dataclasses import replace
>>> la = label_abstraction(replace(p, margin=0.25))   # a band of 0.25 around a's edges
>>> la.n_regions, sum("a" in s for s in la.labels_of), sum("a" not in s for s in la.negs_of)
(13, 1, 5)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import Point
from shapely.geometry import Polygon as ShPolygon
from shapely.prepared import prep as prepared

from plansynth.budget import checkpoint
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.abstraction.hertel_mehlhorn import hertel_mehlhorn
from plansynth.reach.abstraction.regions import region_from_cycle
from plansynth.reach.geometry import Box, Shape, halfspaces, is_convex, shape_to_shapely
from plansynth.reach.offsets import area as _area
from plansynth.reach.offsets import clip, grown, shrunk
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robot import configuration_space

__all__ = ["LabelledAbstraction", "label_abstraction", "clip", "planning_problem", "margin_problem"]


def margin_problem(problem: ReachProblem) -> ReachProblem:
    """The problem with every obstacle grown by the mission's obstacle margin
    (:func:`plansynth.reach.offsets.grown`): the problem a trajectory is validated
    against (the robot's size included, checked by the validator itself)."""
    if problem.obstacle_margin <= 0:
        return problem
    r = problem.obstacle_margin
    return replace(problem, obstacles=tuple(grown(o, r) for o in problem.obstacles))


def planning_problem(problem: ReachProblem) -> ReachProblem:
    """The problem the reach-avoid machinery (decomposition, CON-PLAN) plans in for a
    mission: obstacles grown by the obstacle margin (:func:`margin_problem`), a sized
    robot's configuration space (:func:`plansynth.reach.robot.configuration_space`: the
    labels are read at the robot's reference point), and the goal replaced by the whole
    workspace, so that "p_N in the goal" holds for every position and the mission alone
    constrains the plan (the problem has no mission itself)."""
    return configuration_space(margin_problem(problem)).reach_view()


Pt = tuple[float, float]


@dataclass(frozen=True, eq=False)
class LabelledAbstraction:
    """Regions refined by the labels: ``abstraction`` (its ``goal_regions`` are all
    regions: a mission has no fixed goal); ``labels_of[i]``, the labels a holds in region
    i (it lies in a, at depth >= a's margin); ``negs_of[i]``, the labels whose negation
    holds there (it lies outside a, at distance >= a's margin; without margins, every
    label not in ``labels_of[i]``); ``parent[i]``, the region of the unrefined
    decomposition it came from."""

    abstraction: Abstraction
    names: tuple[str, ...]
    labels_of: tuple[frozenset[str], ...]
    parent: tuple[int, ...]
    negs_of: tuple[frozenset[str], ...] = ()

    def __post_init__(self) -> None:
        if not self.negs_of:
            names = frozenset(self.names)
            object.__setattr__(self, "negs_of", tuple(names - s for s in self.labels_of))

    @property
    def n_regions(self) -> int:
        return self.abstraction.n_regions

    def regions_with(self, name: str) -> tuple[int, ...]:
        return tuple(i for i, s in enumerate(self.labels_of) if name in s)

    @property
    def letters(self) -> tuple[tuple[frozenset[str], frozenset[str]], ...]:
        """Per region, (the labels that hold, the labels whose negation holds)."""
        return tuple(zip(self.labels_of, self.negs_of))


def _split_convex(piece: list[Pt], H: np.ndarray, h: np.ndarray, tiny: float, deep: float) -> list[list[Pt]]:
    """``piece`` cut into the part inside the convex ``{H p <= h}`` (unit rows) and the
    convex parts outside it (one per half-plane, each cut off before the next).

    A side is cut when the piece reaches beyond it by more than ``deep``: depth, not
    area, decides, since a sliver of tiny area can still reach far past a label's edge
    (a region 2e-7 wide that ran 4e-3 past it was once read as inside). An outside part
    of area at most ``tiny`` is dropped (a sliver of free space lost: the pieces then
    cover a little less, never more, than the region)."""
    out = []
    rest = piece
    for n, c in zip(H, h):
        if max(n[0] * x + n[1] * y for x, y in rest) - c <= deep:
            continue  # the piece stays on this side (within deep): nothing to cut
        outside = clip(rest, -n, -c)
        if _area(outside) > tiny:
            out.append(outside)
        rest = clip(rest, n, c)
        if _area(rest) <= tiny:
            return out
    out.append(rest)
    return out


def _split_polygon(piece: list[Pt], cut: _Cut, tiny: float, deep: float) -> list[list[Pt]]:
    """``piece`` cut along the non-convex label of ``cut``: its parts inside and outside,
    each decomposed into convex pieces (Hertel-Mehlhorn over a constrained
    triangulation). Uncut when the piece lies within ``deep`` of the label
    (:meth:`_Cut.near`) or reaches no deeper than ``deep`` into it (:meth:`_Cut.core`):
    depth, not area, decides, as in :func:`_split_convex`."""
    label = cut.geom
    assert label is not None
    g = ShPolygon(piece)
    if cut.near(deep).contains(g) or g.intersection(cut.core(deep)).area <= 0.0:
        return [piece]
    out: list[list[Pt]] = []
    for part in (g.intersection(label), g.difference(label)):
        polys = [q for q in shapely.get_parts(part) if isinstance(q, ShPolygon) and q.area > tiny]
        if not polys:
            continue
        cycles, _ = hertel_mehlhorn(polys)
        out += [[(float(x), float(y)) for x, y in c] for c in cycles if _area(c) > tiny]
    return out


@dataclass(frozen=True)
class _Cut:
    """One shape the regions are cut along: a convex one by its rows, a non-convex
    polygon by its shapely geometry; ``box`` its bounding box."""

    shape: Shape
    rows: tuple[np.ndarray, np.ndarray] | None
    geom: ShPolygon | None
    box: tuple[float, float, float, float]

    @classmethod
    def of(cls, shape: Shape) -> _Cut:
        g = shape_to_shapely(shape)
        rows = halfspaces(shape) if is_convex(shape) else None
        return cls(shape, rows, None if rows is not None else g, tuple(g.bounds))  # type: ignore[arg-type]

    def near(self, deep: float) -> ShPolygon:
        """The shape grown by ``deep``: a region inside it lies in the shape up to ``deep``."""
        return shape_to_shapely(self.shape).buffer(deep)

    def core(self, deep: float) -> ShPolygon:
        """The shape shrunk by ``deep``: a region that does not overlap it reaches no
        deeper than ``deep`` into the shape."""
        return shape_to_shapely(self.shape).buffer(-deep)

    def contains(self, c: np.ndarray) -> bool:
        """Is the interior point c of a region inside the cut (the region then is)?"""
        if isinstance(self.shape, Box):
            return all(l < x < hh for l, hh, x in zip(self.shape.lo, self.shape.hi, c))
        if self.rows is not None:
            H, h = self.rows
            return bool(np.all(H @ c < h))
        assert self.geom is not None
        return bool(self.geom.contains(Point(float(c[0]), float(c[1]))))


def _cuts(problem: ReachProblem, names: tuple[str, ...]) -> dict[str, tuple[_Cut | None, _Cut]]:
    """Per label: (the shape where it holds, the shape outside of which its negation
    holds): the label itself twice without a margin, its shrunk and grown shapes with one
    (the first None when no point lies that deep)."""
    labels = problem.mission_labels
    out = {}
    for n in names:
        r = problem.label_margin(n)
        inner = shrunk(labels[n], r)
        out[n] = (None if inner is None else _Cut.of(inner), _Cut.of(grown(labels[n], r)))
    return out


def _adjacent(a: list[Pt], b: list[Pt], tol: float) -> bool:
    """Do the convex polygons share an edge piece longer than ``tol``? (Plain float
    arithmetic: a region pair's handful of edges in numpy, one small array per vertex,
    was half the time of :func:`label_abstraction`.)"""
    na, nb = len(a), len(b)
    for i in range(na):
        px, py = a[i]
        qx, qy = a[(i + 1) % na]
        ex, ey = qx - px, qy - py
        L = math.hypot(ex, ey)
        if L <= tol:
            continue
        ux, uy = ex / L, ey / L
        nx, ny = -uy, ux
        for j in range(nb):
            rx, ry = b[j][0] - px, b[j][1] - py
            sx, sy = b[(j + 1) % nb][0] - px, b[(j + 1) % nb][1] - py
            if abs(nx * rx + ny * ry) > tol or abs(nx * sx + ny * sy) > tol:
                continue
            ur, us = ux * rx + uy * ry, ux * sx + uy * sy
            lo = max(0.0, min(ur, us))
            hi = min(L, max(ur, us))
            if hi - lo > tol:
                return True
    return False


def label_abstraction(problem: ReachProblem, base: Abstraction | None = None) -> LabelledAbstraction:
    """Refine ``base`` (default: :func:`abstract` of the :func:`planning_problem`) by the
    problem's mission labels (``problem.mission_labels``: the labels and the goal), at
    their margins. 2-D only. Checks the enclosing phase's budget as it goes."""
    t0 = time.perf_counter()
    if base is None:
        base = abstract(planning_problem(problem))
    names = tuple(problem.mission_labels)
    ws = problem.workspace
    scale = max(h - l for l, h in zip(ws.lo, ws.hi))
    tiny = 1e-10 * scale * scale
    tol = 1e-7 * scale
    deep = 1e-9 * scale  # how far a region may reach past a cut and still count as on its side
    cut_of = _cuts(problem, names)
    cuts = [c for n in names for c in cut_of[n] if c is not None]
    cuts = list({c.shape: c for c in cuts}.values())  # without a margin a label is one cut
    pieces: list[list[Pt]] = []
    parent: list[int] = []
    for reg in base.regions:
        checkpoint()
        cur = [[(float(x), float(y)) for x, y in reg.vertices]]
        V = np.asarray(reg.vertices, float)
        rx0, ry0 = V.min(axis=0)
        rx1, ry1 = V.max(axis=0)
        for cut in cuts:
            x0, y0, x1, y1 = cut.box
            if x1 <= rx0 or x0 >= rx1 or y1 <= ry0 or y0 >= ry1:
                continue  # the cut does not meet the region's box: nothing to split
            nxt = []
            for pc in cur:
                if cut.rows is not None:
                    nxt += _split_convex(pc, cut.rows[0], cut.rows[1], tiny, deep)
                else:
                    nxt += _split_polygon(pc, cut, tiny, deep)
            cur = nxt
            checkpoint()
        for pc in cur:
            pieces.append(pc)
            parent.append(reg.index)
    regions = [region_from_cycle(i, pc) for i, pc in enumerate(pieces)]
    labels_of, negs_of = _letters(regions, names, cut_of, deep)
    nbrs = _adjacency(regions, parent, base, tol)
    start = problem.start_position
    start_regions = tuple(r.index for r in regions if r.contains(start, 1e-9 * scale))
    abstraction = Abstraction(
        regions=tuple(regions),
        adjacency=tuple(tuple(sorted(n)) for n in nbrs),
        start_regions=start_regions,
        goal_regions=tuple(range(len(regions))),
        seconds=base.seconds + time.perf_counter() - t0,
        method=f"{base.method}+labels",
        candidates=base.candidates,
        exact=base.exact,  # the pieces tile the base regions: they cover what those cover
    )
    return LabelledAbstraction(abstraction, names, tuple(labels_of), tuple(parent), tuple(negs_of))


def _letters(regions, names: tuple[str, ...], cut_of: dict, deep: float) -> tuple[list, list]:
    """Per region, the labels that hold there and those whose negation does. A region's
    interior point decides which side of each cut it lies on (the pieces do not straddle
    a cut); each claim is then checked on the whole region, exactly (shapely): ``a``
    holds only if the region lies within ``deep`` of a's inner shape, ``!a`` only if it
    reaches no deeper than ``deep`` into a's outer shape. A claim that fails the check
    is not made: the region is then in a's band, where neither literal is used, so an
    error of the cutting can cost plans, never admit a wrong one."""
    near = {n: (None if inner is None else prepared(inner.near(deep))) for n, (inner, _) in cut_of.items()}
    core = {n: outer.core(deep) for n, (_, outer) in cut_of.items()}
    labels_of, negs_of = [], []
    for r in regions:
        c = r.center
        poly = ShPolygon(r.vertices)
        holds, fails = set(), set()
        for n in names:
            inner, outer = cut_of[n]
            if inner is not None and inner.contains(c) and near[n].contains(poly):
                holds.add(n)
            if not outer.contains(c) and poly.intersection(core[n]).area <= 0.0:
                fails.add(n)
        labels_of.append(frozenset(holds))
        negs_of.append(frozenset(fails))
    return labels_of, negs_of


def _adjacency(regions, parent: list[int], base: Abstraction, tol: float) -> list[list[int]]:
    """Pieces that share an edge of positive length, among pairs from the same or from
    adjacent base regions whose boxes (grown by ``tol``) meet (an R-tree query)."""
    near = {(i, j) for i in range(base.n_regions) for j in (i, *base.adjacency[i])}
    verts = [[(float(x), float(y)) for x, y in r.vertices.tolist()] for r in regions]
    boxes = [
        shapely.box(
            min(x for x, _ in v) - tol,
            min(y for _, y in v) - tol,
            max(x for x, _ in v) + tol,
            max(y for _, y in v) + tol,
        )
        for v in verts
    ]
    nbrs: list[list[int]] = [[] for _ in regions]
    if not regions:
        return nbrs
    tree = shapely.STRtree(boxes)
    left, right = tree.query(boxes, predicate="intersects")
    for i, j in zip(left.tolist(), right.tolist()):
        if j <= i or (parent[i], parent[j]) not in near:
            continue
        if _adjacent(verts[i], verts[j], tol):
            nbrs[i].append(j)
            nbrs[j].append(i)
    return nbrs

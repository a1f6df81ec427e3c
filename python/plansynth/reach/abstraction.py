"""Convex decomposition of the free space with region adjacency (paper, Section III,
Algorithm 1 line 1: the discrete abstraction).

The workspace minus the obstacles is cut into convex regions with pairwise disjoint
interiors whose union is exactly the free space. Two regions are *adjacent* when they
share a boundary piece of positive (d-1)-measure; the SAT part of the planner walks
this graph. The decomposition is obstacle-based and coarse (not a grid): fewer regions
make the Boolean search smaller, so several constructions are tried and the one with
the fewest regions is kept (``method="auto"``):

``hertel-mehlhorn``  2-D: shapely's constrained Delaunay triangulation of the free
                     polygon, then Hertel-Mehlhorn removal of every diagonal whose two
                     sides stay convex (at most 4x the optimal number of pieces).
``slab-y``, ``slab-x`` 2-D: trapezoids between consecutive vertex coordinates along the
                     sweep axis, then greedy merging of neighbours whose union is convex.
``boxes``            2-D and 3-D when every obstacle is a box: the grid of all obstacle
                     coordinates, free cells grown greedily into maximal boxes (the
                     best of all axis orders).

Adjacency is never computed by floating-point geometry on the final regions: each
construction starts from elementary pieces whose contacts are known combinatorially
(triangles of one triangulation sharing an edge; trapezoids whose intervals on a common
sweep line overlap; grid cells sharing a face), merges only pieces whose union is
convex (checked with exact orientation predicates), and lifts piece contacts to regions.

>>> from plansynth.reach.families import maze
>>> a = abstract(maze(1))
>>> len(a.regions), a.adjacency, a.start_regions, a.goal_regions
(3, ((1,), (0, 2), (1,)), (0,), (2,))
"""

from __future__ import annotations

import itertools
import math
import dataclasses
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import Polygon as ShPolygon

from plansynth.budget import checkpoint
from plansynth.errors import InvalidProblem
from plansynth.reach.geometry import Box, Polygon, is_convex, polygon_halfspaces, shape_to_shapely
from plansynth.reach.problem import ReachProblem

__all__ = ["Region", "Abstraction", "abstract", "METHODS", "outer_polygon", "OUTER_VERTICES"]

METHODS = ("auto", "hertel-mehlhorn", "slab-y", "slab-x", "boxes")
# a convex obstacle polygon with more vertices than this is decomposed around an outer
# polygon with this many sides (see :func:`outer_polygon`)
OUTER_VERTICES = 64

Pt = tuple[float, float]


# --------------------------------------------------------------------------- results


@dataclass(frozen=True, eq=False)
class Region:
    """A convex, full-dimensional region ``{p : H p <= h}`` (rows of H have unit norm).

    ``vertices``: in 2-D the CCW polygon (v x 2), in 3-D the 8 box corners.
    Regions compare by identity (they hold arrays).
    """

    index: int
    H: np.ndarray
    h: np.ndarray
    vertices: np.ndarray

    @property
    def dim(self) -> int:
        return int(self.H.shape[1])

    @cached_property
    def center(self) -> np.ndarray:
        """A point strictly inside: the area centroid (2-D) or the box centre (3-D)."""
        v = self.vertices
        if self.dim != 2:
            return (v.min(axis=0) + v.max(axis=0)) / 2
        x, y = v[:, 0], v[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        cross = x * yn - xn * y
        a = cross.sum() / 2
        return np.array([((x + xn) * cross).sum() / (6 * a), ((y + yn) * cross).sum() / (6 * a)])

    def contains(self, p: Sequence[float], tol: float = 1e-9) -> bool:
        """Closed containment with tolerance ``tol``."""
        return bool(np.all(self.H @ np.asarray(p, dtype=float) <= self.h + tol))

    def measure(self) -> float:
        """Area (2-D) or volume (3-D)."""
        v = self.vertices
        if self.dim != 2:
            return float(np.prod(v.max(axis=0) - v.min(axis=0)))
        return float(ShPolygon(v).area)


@dataclass(frozen=True, eq=False)
class Abstraction:
    """The discrete abstraction: regions, their adjacency graph, start and goal regions.

    ``adjacency[i]`` is the sorted tuple of neighbours of region i (symmetric, no
    self-loops). ``start_regions``: regions whose closure contains the start position;
    ``goal_regions``: regions whose closure meets the goal (a face or a point is
    enough: a plan may end there, where the goal's interior beside it is obstacle). ``method`` says
    which construction won; ``candidates`` gives the region count of each one tried.
    ``exact``: the regions cover exactly the free space; False when some finely sampled
    convex obstacle was decomposed around its outer polygon (:func:`outer_polygon`),
    so the regions cover a subset of the free space (sound for plans, which stay in
    the regions, but nothing about the abstraction then bounds the real problem).
    """

    regions: tuple[Region, ...]
    adjacency: tuple[tuple[int, ...], ...]
    start_regions: tuple[int, ...]
    goal_regions: tuple[int, ...]
    seconds: float
    method: str = ""
    candidates: tuple[tuple[str, int], ...] = ()
    exact: bool = True

    @property
    def n_regions(self) -> int:
        return len(self.regions)

    @property
    def n_edges(self) -> int:
        """Number of undirected adjacency edges."""
        return sum(len(a) for a in self.adjacency) // 2

    def regions_containing(self, p: Sequence[float], tol: float = 1e-9) -> tuple[int, ...]:
        return tuple(r.index for r in self.regions if r.contains(p, tol))


# --------------------------------------------------------------- exact predicates


def _orient(a: Pt, b: Pt, c: Pt) -> int:
    """Sign of the turn a -> b -> c (+1 left/CCW, 0 collinear, -1 right), exact."""
    det = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
    scale = (abs(b[0] - a[0]) + abs(b[1] - a[1])) * (abs(c[0] - b[0]) + abs(c[1] - b[1]))
    if abs(det) > 1e-12 * scale:
        return 1 if det > 0 else -1
    fa = (Fraction(a[0]), Fraction(a[1]))
    fb = (Fraction(b[0]), Fraction(b[1]))
    fc = (Fraction(c[0]), Fraction(c[1]))
    e = (fb[0] - fa[0]) * (fc[1] - fb[1]) - (fb[1] - fa[1]) * (fc[0] - fb[0])
    return (e > 0) - (e < 0)


def _drop_collinear(cycle: list[Pt]) -> list[Pt]:
    """Remove repeated and (exactly) collinear vertices of a closed cycle.

    One pass with a stack (a vertex is dropped when it is collinear with the last kept
    one and the next; the wrap-around is settled at the end), linear in the cycle's
    length: the free space of the GCS paper's 50 x 50 maze is one ring of ~10,000
    vertices, on which the restarting scan of :func:`_drop_collinear_reference` took 5 s.
    The same vertices survive, in the same order (a hypothesis test compares the two on
    cycles without spikes)."""
    pts = [p for i, p in enumerate(cycle) if p != cycle[i - 1]] if len(cycle) > 1 else list(cycle)
    if len(pts) <= 3:
        return _drop_collinear_reference(pts)
    kept: list[Pt] = []
    for p in pts:
        while len(kept) >= 2 and _orient(kept[-2], kept[-1], p) == 0:
            kept.pop()
        kept.append(p)
    changed = True
    while changed and len(kept) > 3:  # the wrap-around: the last and the first vertices
        checkpoint()
        changed = False
        if _orient(kept[-2], kept[-1], kept[0]) == 0:
            kept.pop()
            changed = True
        elif _orient(kept[-1], kept[0], kept[1]) == 0:
            del kept[0]
            changed = True
    if len(kept) < 3:  # a degenerate cycle (all on one line): as the reference leaves it
        return _drop_collinear_reference(pts)
    return kept


def _drop_collinear_reference(cycle: list[Pt]) -> list[Pt]:
    """The plain version of :func:`_drop_collinear` (quadratic: it rescans from the
    start after each removal): the reference the tests compare it with."""
    pts = [p for i, p in enumerate(cycle) if p != cycle[i - 1]] if len(cycle) > 1 else list(cycle)
    changed = True
    while changed and len(pts) > 3:
        changed = False
        for i in range(len(pts)):
            checkpoint()  # quadratic on thousands of near-collinear vertices
            a, b, c = pts[i - 1], pts[i], pts[(i + 1) % len(pts)]
            if _orient(a, b, c) == 0:
                del pts[i]
                changed = True
                break
    return pts


def _signed_area(cycle: Sequence[Pt]) -> float:
    s = 0.0
    for i in range(len(cycle)):
        (x0, y0), (x1, y1) = cycle[i - 1], cycle[i]
        s += x0 * y1 - x1 * y0
    return s / 2


def _ccw(cycle: list[Pt]) -> list[Pt]:
    """The cycle in CCW order; the sign of the area is exact for slivers, whose float
    area is all cancellation error."""
    area = _signed_area(cycle)
    mass = sum(abs(x0 * y1) + abs(x1 * y0) for (x0, y0), (x1, y1) in zip(cycle[-1:] + cycle[:-1], cycle))
    if abs(area) <= 1e-12 * mass:
        exact = sum(
            Fraction(x0) * Fraction(y1) - Fraction(x1) * Fraction(y0)
            for (x0, y0), (x1, y1) in zip(cycle[-1:] + cycle[:-1], cycle)
        )
        return cycle if exact >= 0 else cycle[::-1]
    return cycle if area >= 0 else cycle[::-1]


def _snap_levels(values: Iterable[float], tol: float) -> dict[float, float]:
    """Map each value to the least of its cluster: runs of sorted values with gaps <= tol."""
    out: dict[float, float] = {}
    rep = prev = None
    for x in sorted(set(values)):
        if prev is None or x - prev > tol:
            rep = x
        out[x] = rep
        prev = x
    return out


# ------------------------------------------------------------- free space (2-D)


def _free_polygons(problem: ReachProblem) -> list[ShPolygon]:
    ws = shape_to_shapely(problem.workspace)
    free = ws
    if problem.obstacles:
        free = ws.difference(shapely.union_all([shape_to_shapely(o) for o in problem.obstacles]))
    polys = [g for g in getattr(free, "geoms", [free]) if isinstance(g, ShPolygon) and not g.is_empty]
    out = []
    tiny = 1e-12 * ws.area
    for g in polys:
        shell = _drop_collinear([tuple(c) for c in g.exterior.coords[:-1]])
        holes = [_drop_collinear([tuple(c) for c in r.coords[:-1]]) for r in g.interiors]
        q = ShPolygon(shell, [h for h in holes if len(h) >= 3])
        if q.area > tiny:
            out.append(q)
    return out


def _rings(polys: Iterable[ShPolygon]) -> list[list[Pt]]:
    rings = []
    for g in polys:
        rings.append([tuple(c) for c in g.exterior.coords[:-1]])
        rings.extend([tuple(c) for c in r.coords[:-1]] for r in g.interiors)
    return rings


# ------------------------------------------------------------- merging (2-D)


def _longest_first(e: tuple[Pt, Pt]) -> float:
    return -math.hypot(e[1][0] - e[0][0], e[1][1] - e[0][1])


class _Pieces:
    """Convex pieces (CCW vertex cycles) with exact piece contacts; greedy convex merging.

    Two pieces can merge only along an edge that is a full edge of both (the shared
    chord of a convex union always is); the union is convex iff the turns at the two
    ends of the edge are not right turns.

    ``straight``: points known by construction to lie inside a straight edge of the free
    space's boundary (slab corners interpolated on an obstacle edge). The turn there is
    0 whatever the rounded coordinates say: asking the orientation predicate would keep
    a vertex of angle 180 degrees +- 1e-16, convex or reflex by a rounding error.
    """

    def __init__(
        self, cycles: list[list[Pt]], contacts: Iterable[tuple[int, int]], order=None, straight: Iterable[Pt] = ()
    ) -> None:
        self.order = order or _longest_first
        self.straight = frozenset(straight)
        self.cycles: dict[int, list[Pt]] = {i: c for i, c in enumerate(cycles)}
        self.parent = list(range(len(cycles)))
        self.contacts = {(min(a, b), max(a, b)) for a, b in contacts if a != b}

    def find(self, i: int) -> int:
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def merge_all(self) -> None:
        while self._merge_pass():
            pass

    def _merge_pass(self) -> bool:
        owner: dict[tuple[Pt, Pt], int] = {}
        for pid, cyc in self.cycles.items():
            for i in range(len(cyc)):
                owner[(cyc[i], cyc[(i + 1) % len(cyc)])] = pid
        diagonals = [(u, v) for (u, v), pid in owner.items() if (v, u) in owner and owner[(v, u)] != pid and u < v]
        diagonals.sort(key=self.order)
        merged_any = False
        for u, v in diagonals:
            checkpoint()  # within a budget (plansynth.budget): many thousand diagonals
            p, q = owner.get((u, v)), owner.get((v, u))
            if p is None or q is None or p == q or p not in self.cycles or q not in self.cycles:
                continue
            new = self._try_merge(self.cycles[p], self.cycles[q], u, v)
            if new is None:
                continue
            del self.cycles[q]
            self.cycles[p] = new
            self.parent[q] = p
            for i in range(len(new)):
                owner[(new[i], new[(i + 1) % len(new)])] = p
            merged_any = True
        return merged_any

    def _try_merge(self, P: list[Pt], Q: list[Pt], u: Pt, v: Pt) -> list[Pt] | None:
        """Union of P (with edge u->v) and Q (with edge v->u) if convex, else None."""
        # the owner map may hold edges that collinear-vertex removal has since dissolved
        if v not in P or u not in Q:
            return None
        i = P.index(v)
        Pr = P[i:] + P[:i]  # v ... u
        j = Q.index(u)
        Qr = Q[j:] + Q[:j]  # u ... v
        if Pr[-1] != u or Qr[-1] != v:
            return None
        # turn at u: Pr[-2] -> u -> Qr[1]; at v: Qr[-2] -> v -> Pr[1]
        tu = 0 if u in self.straight else _orient(Pr[-2], u, Qr[1])
        tv = 0 if v in self.straight else _orient(Qr[-2], v, Pr[1])
        if tu < 0 or tv < 0:
            return None
        cyc = Pr[:-1] + [u] + Qr[1:-1]
        if tu == 0:
            cyc.remove(u)
        if tv == 0:
            cyc.remove(v)
        return cyc

    def result(self) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
        ids = sorted(self.cycles)
        pos = {pid: k for k, pid in enumerate(ids)}
        adj = set()
        for a, b in self.contacts:
            ra, rb = pos[self.find(a)], pos[self.find(b)]
            if ra != rb:
                adj.add((min(ra, rb), max(ra, rb)))
        return [self.cycles[i] for i in ids], adj


# ------------------------------------------------------------- 2-D constructions


def _hertel_mehlhorn(polys: list[ShPolygon], order=None) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
    cycles: list[list[Pt]] = []
    for g in polys:
        tris = shapely.constrained_delaunay_triangles(g)
        for t in getattr(tris, "geoms", []):
            c = [tuple(x) for x in t.exterior.coords[:-1]]
            if len(c) != 3 or _orient(c[0], c[1], c[2]) == 0:
                continue
            cycles.append(_ccw(c))
    edge_owner: dict[frozenset, list[int]] = {}
    for i, c in enumerate(cycles):
        for k in range(3):
            edge_owner.setdefault(frozenset((c[k], c[(k + 1) % 3])), []).append(i)
    contacts = [(o[0], o[1]) for o in edge_owner.values() if len(o) == 2]
    pieces = _Pieces(cycles, contacts, order)
    pieces.merge_all()
    return pieces.result()


def _slabs(polys: list[ShPolygon], axis: int) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
    """Trapezoids between consecutive vertex coordinates along ``axis`` (1: horizontal
    lines, sweeping y; 0: vertical lines, sweeping x).

    Sweep coordinates closer than ``1e-12`` times the largest coordinate are snapped to one
    level: mirror-image vertices often differ by a rounding error (a shapely disc's
    ``sin(t)`` and ``sin(pi - t)``), and a level per copy would cut a slab 1e-15 thick.
    Its slivers then stand between the pieces below and above, which share a facet of
    positive length but would only be linked through a region no path can cross.
    """
    s_of = lambda p: p[axis]
    r_of = lambda p: p[1 - axis]

    def point(s: float, r: float) -> Pt:
        return (r, s) if axis == 1 else (s, r)

    raw = _rings(polys)
    if not raw:
        return [], set()
    extent = max(max(abs(c) for p in ring for c in p) for ring in raw)
    snap = _snap_levels((s_of(p) for ring in raw for p in ring), 1e-12 * max(extent, 1.0))
    rings = []
    for ring in raw:
        snapped = [point(snap[s_of(p)], r_of(p)) for p in ring]
        rings.append([p for i, p in enumerate(snapped) if p != snapped[i - 1]])

    edges = []
    for ring in rings:
        for i in range(len(ring)):
            a, b = ring[i], ring[(i + 1) % len(ring)]
            if s_of(a) == s_of(b):
                continue
            if s_of(a) > s_of(b):
                a, b = b, a
            edges.append((a, b))
    vertices = {p for ring in rings for p in ring}
    levels = sorted({s_of(p) for p in vertices})

    def r_at(e: tuple[Pt, Pt], s: float) -> float:
        a, b = e
        if s == s_of(a):
            return r_of(a)
        if s == s_of(b):
            return r_of(b)
        t = (s - s_of(a)) / (s_of(b) - s_of(a))
        return r_of(a) + t * (r_of(b) - r_of(a))

    cycles: list[list[Pt]] = []
    contacts: list[tuple[int, int]] = []
    straight: set[Pt] = set()  # corners strictly inside a boundary edge
    prev: list[tuple[int, float, float]] = []  # (piece, r_lo, r_hi) on the previous level
    for s0, s1 in zip(levels, levels[1:]):
        checkpoint()
        mid = (s0 + s1) / 2
        active = [e for e in edges if s_of(e[0]) <= s0 and s_of(e[1]) >= s1]
        active.sort(key=lambda e: r_at(e, mid))
        bottom: list[tuple[int, float, float]] = []
        top: list[tuple[int, float, float]] = []
        for lo_e, hi_e in zip(active[0::2], active[1::2]):
            a0, b0 = r_at(lo_e, s0), r_at(hi_e, s0)
            a1, b1 = r_at(lo_e, s1), r_at(hi_e, s1)
            cyc = [point(s0, a0), point(s0, b0), point(s1, b1), point(s1, a1)]
            straight.update(p for p in cyc if p not in vertices)
            # CCW by construction (r_lo < r_hi, s0 < s1); the (x, y) swap mirrors it
            cyc = _drop_collinear(cyc if axis == 1 else cyc[::-1])
            if len(cyc) < 3:
                continue
            pid = len(cycles)
            cycles.append(cyc)
            bottom.append((pid, a0, b0))
            top.append((pid, a1, b1))
        for pid, a, b in bottom:
            for qid, c, d in prev:
                if max(a, c) < min(b, d):
                    contacts.append((pid, qid))
        prev = top
    pieces = _Pieces(cycles, contacts, straight=straight)
    pieces.merge_all()
    return pieces.result()


# ------------------------------------------------------------- boxes (2-D and 3-D)


def _boxes(problem: ReachProblem) -> tuple[list[tuple[np.ndarray, np.ndarray]], set[tuple[int, int]]]:
    """Free grid cells of all obstacle coordinates, grown greedily into maximal boxes.

    Every axis order is tried; the one giving fewest boxes wins.
    """
    ws = problem.workspace
    d = ws.dim
    cuts = []
    for k in range(d):
        vals = {ws.lo[k], ws.hi[k]}
        for ob in problem.obstacles:
            assert isinstance(ob, Box)
            for v in (ob.lo[k], ob.hi[k]):
                if ws.lo[k] < v < ws.hi[k]:
                    vals.add(v)
        cuts.append(np.array(sorted(vals)))
    shape = tuple(len(c) - 1 for c in cuts)
    free = np.ones(shape, dtype=bool)
    for ob in problem.obstacles:
        assert isinstance(ob, Box)
        sl = []
        for k in range(d):
            i0 = int(np.searchsorted(cuts[k], max(ob.lo[k], ws.lo[k]), side="left"))
            i1 = int(np.searchsorted(cuts[k], min(ob.hi[k], ws.hi[k]), side="left"))
            sl.append(slice(i0, max(i0, i1)))
        free[tuple(sl)] = False

    best = None
    for order in itertools.permutations(range(d)):
        label = _grow_boxes(free, order)
        count = int(label.max()) + 1
        if best is None or count < best[0]:
            best = (count, label)
    assert best is not None
    count, label = best
    boxes = []
    for b in range(count):
        idx = np.argwhere(label == b)
        lo_i, hi_i = idx.min(axis=0), idx.max(axis=0) + 1
        boxes.append((np.array([cuts[k][lo_i[k]] for k in range(d)]), np.array([cuts[k][hi_i[k]] for k in range(d)])))
    adj = set()
    for k in range(d):
        a = np.moveaxis(label, k, 0)
        x, y = a[:-1].ravel(), a[1:].ravel()
        mask = (x >= 0) & (y >= 0) & (x != y)
        for i, j in zip(x[mask].tolist(), y[mask].tolist()):
            adj.add((min(i, j), max(i, j)))
    return boxes, adj


def _grow_boxes(free: np.ndarray, order: tuple[int, ...]) -> np.ndarray:
    """Label free cells with box ids: from each unassigned free cell (in scan order),
    grow along ``order[0]``, then ``order[1]``, ... while the slab stays free+unassigned."""
    label = np.full(free.shape, -1, dtype=np.int64)
    avail = free.copy()  # free and not yet in a box
    flat = avail.reshape(-1)  # a view: updated with avail
    d = free.ndim
    nb = 0
    ptr = 0
    while True:
        checkpoint()
        rest = flat[ptr:]
        k0 = int(np.argmax(rest))
        if not rest[k0]:
            break
        ptr += k0
        cell = np.unravel_index(ptr, free.shape)
        lo = [int(c) for c in cell]
        hi = [c + 1 for c in lo]
        for k in order:
            while hi[k] < free.shape[k]:
                sl = tuple(slice(lo[j], hi[j]) if j != k else slice(hi[k], hi[k] + 1) for j in range(d))
                if np.all(avail[sl]):
                    hi[k] += 1
                else:
                    break
        box = tuple(slice(lo[j], hi[j]) for j in range(d))
        label[box] = nb
        avail[box] = False
        nb += 1
    return label


# --------------------------------------------------------------------- assembly


def _region_from_cycle(index: int, cyc: list[Pt]) -> Region:
    v = np.array(_drop_collinear(_ccw(list(cyc))), dtype=float)
    H, h = polygon_halfspaces(v)
    return Region(index=index, H=_ro(H), h=_ro(h), vertices=_ro(v))


def _region_from_box(index: int, lo: np.ndarray, hi: np.ndarray) -> Region:
    d = len(lo)
    eye = np.eye(d)
    H = np.vstack([eye, -eye])
    h = np.concatenate([hi, -lo])
    if d == 2:
        v = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    else:
        v = np.array(
            [[(lo, hi)[bx][0], (lo, hi)[by][1], (lo, hi)[bz][2]] for bz in (0, 1) for by in (0, 1) for bx in (0, 1)]
        )
    return Region(index=index, H=_ro(H), h=_ro(h), vertices=_ro(v.astype(float)))


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


def _candidates(problem: ReachProblem, method: str) -> list[tuple[str, list[Region], set[tuple[int, int]]]]:
    all_boxes = all(isinstance(o, Box) for o in problem.obstacles)
    if problem.dim == 3:
        if method not in ("auto", "boxes"):
            raise ValueError(f"3-D workspaces are decomposed with method 'boxes', not {method!r}")
        boxes, adj = _boxes(problem)
        return [("boxes", [_region_from_box(i, lo, hi) for i, (lo, hi) in enumerate(boxes)], adj)]
    if method == "boxes" and not all_boxes:
        raise ValueError("method 'boxes' needs every obstacle to be a box")
    if method not in METHODS:
        raise ValueError(f"unknown decomposition method {method!r} (known: {', '.join(METHODS)})")
    out = []
    if method in ("auto", "boxes") and all_boxes:
        boxes, adj = _boxes(problem)
        out.append(("boxes", [_region_from_box(i, lo, hi) for i, (lo, hi) in enumerate(boxes)], adj))
    if method != "boxes":
        polys = _free_polygons(problem)
        builders = {
            "slab-y": lambda: _slabs(polys, 1),
            "slab-x": lambda: _slabs(polys, 0),
            "hertel-mehlhorn": lambda: _hertel_mehlhorn(polys),
        }
        for name, build in builders.items():
            if method in ("auto", name):
                cycles, adj = build()
                regions = []
                for i, c in enumerate(cycles):
                    checkpoint()
                    regions.append(_region_from_cycle(i, c))
                out.append((name, regions, adj))
    return out


def outer_polygon(poly: Polygon, sides: int = OUTER_VERTICES) -> Polygon:
    """A convex polygon with at most ``sides`` vertices that contains the convex
    ``poly``: the intersection of its supporting half-planes in ``sides`` evenly spaced
    directions (each pushed out by a rounding margin).

    A convex obstacle sampled with thousands of vertices (a circle) makes every
    decomposition fan out into thousands of sliver regions, which DIS-PLAN crosses at
    one region per step; around the outer polygon the free space needs few regions.
    A circle of radius r grows by at most ``r (1/cos(pi/sides) - 1)`` (0.12 % at 64).

    >>> sq = Polygon(tuple((math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 1000, endpoint=False)))
    >>> out = outer_polygon(sq, 8)
    >>> len(out.vertices), ShPolygon(out.vertices).contains(ShPolygon(sq.vertices))
    (8, True)
    """
    v = np.asarray(poly.vertices, dtype=float)
    ang = 2 * math.pi * np.arange(sides) / sides
    n = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    scale = 1.0 + float(np.abs(v).max())
    h = (v @ n.T).max(axis=0) + 1e-9 * scale
    pts: list[Pt] = []
    for k in range(sides):
        k2 = (k + 1) % sides
        p = np.linalg.solve(np.stack([n[k], n[k2]]), np.array([h[k], h[k2]]))
        q = (float(p[0]), float(p[1]))
        if not pts or math.dist(q, pts[-1]) > 1e-12 * scale:
            pts.append(q)
    if len(pts) > 1 and math.dist(pts[0], pts[-1]) <= 1e-12 * scale:
        pts.pop()
    return Polygon(tuple(pts))


def _coarsened(problem: ReachProblem) -> ReachProblem | None:
    """``problem`` with every convex polygon of more than :data:`OUTER_VERTICES`
    vertices replaced by :func:`outer_polygon` (None: nothing to replace, or the start
    or the goal would be covered)."""
    if problem.dim != 2:
        return None
    obstacles = []
    changed = False
    for ob in problem.obstacles:
        if isinstance(ob, Polygon) and len(ob.vertices) > OUTER_VERTICES and is_convex(ob):
            obstacles.append(outer_polygon(ob))
            changed = True
        else:
            obstacles.append(ob)
    if not changed:
        return None
    try:
        return dataclasses.replace(problem, obstacles=tuple(obstacles))
    except InvalidProblem:  # the outer polygon covers the start or the goal
        return None


def abstract(problem: ReachProblem, *, method: str = "auto", coarsen: bool = True) -> Abstraction:
    """Decompose the free space of ``problem`` into convex regions (Section III).

    ``method="auto"`` tries every applicable construction (see the module doc) and
    keeps the one with the fewest regions; ties go to the earlier of
    ``boxes, slab-y, slab-x, hertel-mehlhorn``. With ``coarsen`` (the default), a
    convex obstacle polygon of more than :data:`OUTER_VERTICES` vertices is replaced by
    its :func:`outer_polygon` first (the abstraction is then not ``exact``); if the
    start or the goal then has no region, the exact obstacles are used.

    Inside a budget phase (``with clock.phase(...)``, :mod:`plansynth.budget`) the
    constructions check the clock as they go and raise
    :class:`~plansynth.budget.BudgetExhausted` once it is out of time.
    """
    if coarsen:
        coarse = _coarsened(problem)
        if coarse is not None:
            a = abstract(coarse, method=method, coarsen=False)
            if a.start_regions and a.goal_regions:
                return dataclasses.replace(a, exact=False)
    t0 = time.perf_counter()
    cands = _candidates(problem, method)
    name, regions, adj = min(cands, key=lambda c: len(c[1]))
    # number regions bottom-up (last axis first), for readable pictures and logs
    order = sorted(range(len(regions)), key=lambda i: tuple(regions[i].center[::-1].round(9)))
    new_index = {old: new for new, old in enumerate(order)}
    regions = [
        Region(index=k, H=regions[o].H, h=regions[o].h, vertices=regions[o].vertices) for k, o in enumerate(order)
    ]
    adj = {(min(new_index[i], new_index[j]), max(new_index[i], new_index[j])) for i, j in adj}
    nbrs: list[list[int]] = [[] for _ in regions]
    for i, j in adj:
        nbrs[i].append(j)
        nbrs[j].append(i)
    adjacency = tuple(tuple(sorted(set(n))) for n in nbrs)

    scale = max(h - l for l, h in zip(problem.workspace.lo, problem.workspace.hi))
    start = problem.start_position
    start_regions = tuple(r.index for r in regions if r.contains(start, 1e-9 * scale))
    goal_regions = _goal_regions(problem, regions)
    return Abstraction(
        regions=tuple(regions),
        adjacency=adjacency,
        start_regions=start_regions,
        goal_regions=goal_regions,
        seconds=time.perf_counter() - t0,
        method=name,
        candidates=tuple((n, len(r)) for n, r, _ in cands),
    )


def _goal_regions(problem: ReachProblem, regions: Sequence[Region]) -> tuple[int, ...]:
    goal = problem.goal
    out = []
    if problem.dim == 2:
        g = shape_to_shapely(goal)
        gb = g.bounds
        for r in regions:
            v = r.vertices
            if v[:, 0].max() < gb[0] or v[:, 0].min() > gb[2] or v[:, 1].max() < gb[1] or v[:, 1].min() > gb[3]:
                continue
            if ShPolygon(v).intersects(g):  # closed sets: touching counts
                out.append(r.index)
        return tuple(out)
    assert isinstance(goal, Box)
    for r in regions:
        lo, hi = r.vertices.min(axis=0), r.vertices.max(axis=0)
        if np.all(np.minimum(hi, goal.hi) - np.maximum(lo, goal.lo) >= 0):  # (3-D regions are boxes)
            out.append(r.index)
    return tuple(out)

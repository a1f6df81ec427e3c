"""Exact predicates on the 2-D constructions' vertex cycles (Shoukry et al., CDC 2016,
Section III: the abstraction's regions must be convex and cover the free space exactly,
so convexity and collinearity are decided exactly, falling back to rational arithmetic
where floating point cannot tell).

:func:`drop_collinear` is linear in the cycle's length; :func:`drop_collinear_reference`,
the plain quadratic version beside it, is the oracle the tests compare it with.

>>> orient((0, 0), (1, 0), (2, 0)), orient((0, 0), (1, 0), (1, 1))
(0, 1)
>>> drop_collinear([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)])
[(0, 0), (2, 0), (2, 2), (0, 2)]
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from fractions import Fraction

from plansynth.budget import checkpoint

__all__ = ["Pt", "orient", "drop_collinear", "drop_collinear_reference", "signed_area", "ccw", "snap_levels"]

Pt = tuple[float, float]


def orient(a: Pt, b: Pt, c: Pt) -> int:
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


def drop_collinear(cycle: list[Pt]) -> list[Pt]:
    """Remove repeated and (exactly) collinear vertices of a closed cycle.

    One pass with a stack (a vertex is dropped when it is collinear with the last kept
    one and the next; the wrap-around is settled at the end), linear in the cycle's
    length: the free space of the GCS paper's 50 x 50 maze is one ring of ~10,000
    vertices, on which the restarting scan of :func:`drop_collinear_reference` took 5 s.
    The same vertices survive, in the same order (a hypothesis test compares the two on
    cycles without spikes)."""
    pts = [p for i, p in enumerate(cycle) if p != cycle[i - 1]] if len(cycle) > 1 else list(cycle)
    if len(pts) <= 3:
        return drop_collinear_reference(pts)
    kept: list[Pt] = []
    for p in pts:
        while len(kept) >= 2 and orient(kept[-2], kept[-1], p) == 0:
            kept.pop()
        kept.append(p)
    changed = True
    while changed and len(kept) > 3:  # the wrap-around: the last and the first vertices
        checkpoint()
        changed = False
        if orient(kept[-2], kept[-1], kept[0]) == 0:
            kept.pop()
            changed = True
        elif orient(kept[-1], kept[0], kept[1]) == 0:
            del kept[0]
            changed = True
    if len(kept) < 3:  # a degenerate cycle (all on one line): as the reference leaves it
        return drop_collinear_reference(pts)
    return kept


def drop_collinear_reference(cycle: list[Pt]) -> list[Pt]:
    """The plain version of :func:`drop_collinear` (quadratic: it rescans from the
    start after each removal): the reference the tests compare it with."""
    pts = [p for i, p in enumerate(cycle) if p != cycle[i - 1]] if len(cycle) > 1 else list(cycle)
    changed = True
    while changed and len(pts) > 3:
        changed = False
        for i in range(len(pts)):
            checkpoint()  # quadratic on thousands of near-collinear vertices
            a, b, c = pts[i - 1], pts[i], pts[(i + 1) % len(pts)]
            if orient(a, b, c) == 0:
                del pts[i]
                changed = True
                break
    return pts


def signed_area(cycle: Sequence[Pt]) -> float:
    s = 0.0
    for i in range(len(cycle)):
        (x0, y0), (x1, y1) = cycle[i - 1], cycle[i]
        s += x0 * y1 - x1 * y0
    return s / 2


def ccw(cycle: list[Pt]) -> list[Pt]:
    """The cycle in CCW order; the sign of the area is exact for slivers, whose float
    area is all cancellation error."""
    area = signed_area(cycle)
    mass = sum(abs(x0 * y1) + abs(x1 * y0) for (x0, y0), (x1, y1) in zip(cycle[-1:] + cycle[:-1], cycle))
    if abs(area) <= 1e-12 * mass:
        exact = sum(
            Fraction(x0) * Fraction(y1) - Fraction(x1) * Fraction(y0)
            for (x0, y0), (x1, y1) in zip(cycle[-1:] + cycle[:-1], cycle)
        )
        return cycle if exact >= 0 else cycle[::-1]
    return cycle if area >= 0 else cycle[::-1]


def snap_levels(values: Iterable[float], tol: float) -> dict[float, float]:
    """Map each value to the least of its cluster: runs of sorted values with gaps <= tol."""
    out: dict[float, float] = {}
    rep = prev = None
    for x in sorted(set(values)):
        if prev is None or x - prev > tol:
            rep = x
        out[x] = rep
        prev = x
    return out

"""The fast versions of two steps that the GCS paper's 50 x 50 maze made slow, against
their plain references (STYLE.md, point 6): the collinear-vertex removal of the
abstraction and the displacement-box sweep of the time windows."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from plansynth.reach.abstraction.predicates import drop_collinear, drop_collinear_reference
from plansynth.reach.lazy.bounds.windows import _sweep, _sweep_reference


@st.composite
def cycles(draw):
    """A convex polygon on a coarse grid (exact coordinates), with points inserted on
    its edges (collinear, no spikes), repeated points, and a random first vertex."""
    k = draw(st.integers(3, 9))
    angles = sorted(draw(st.lists(st.floats(0, 2 * math.pi, exclude_max=True), min_size=k, max_size=k, unique=True)))
    r = draw(st.integers(4, 40))
    pts = []
    for a in angles:
        p = (round(r * math.cos(a) * 4) / 4, round(r * math.sin(a) * 4) / 4)
        if not pts or p != pts[-1]:
            pts.append(p)
    area = sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(pts, pts[1:] + pts[:1]))
    assume(len(pts) >= 3 and area > 1.0)  # a polygon, not points on one line
    out = []
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        out.append(p)
        for _ in range(draw(st.integers(0, 2))):
            out.append(p)  # a repeated vertex
        for f in sorted(draw(st.lists(st.sampled_from([0.25, 0.5, 0.75]), max_size=3, unique=True))):
            out.append((p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])))
    shift = draw(st.integers(0, len(out) - 1))
    return out[shift:] + out[:shift]


@settings(max_examples=300, deadline=None)
@given(cycles())
def test_drop_collinear_agrees_with_the_reference(cycle) -> None:
    assert drop_collinear(list(cycle)) == drop_collinear_reference(list(cycle))


def test_drop_collinear_removes_the_midpoints_of_a_square() -> None:
    sq = [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.0, 0.5)]
    assert drop_collinear(sq) == [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    assert sorted(drop_collinear(sq)) == [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)]


@st.composite
def graphs(draw):
    """Random boxes in [0, 10]^2 with a random symmetric adjacency, seeds, targets and
    per-axis growth."""
    k = draw(st.integers(1, 12))
    boxes = []
    for _ in range(k):
        lo = np.array([draw(st.integers(0, 8)), draw(st.integers(0, 8))], float)
        ext = np.array([draw(st.integers(1, 4)), draw(st.integers(1, 4))], float)
        boxes.append((lo, lo + ext))
    edges = draw(st.sets(st.tuples(st.integers(0, k - 1), st.integers(0, k - 1)), max_size=3 * k))
    adj = [set() for _ in range(k)]
    for i, j in edges:
        if i != j:
            adj[i].add(j)
            adj[j].add(i)
    adjacency = [tuple(sorted(a)) for a in adj]
    seeds = {}
    for j in draw(st.sets(st.integers(0, k - 1), min_size=1, max_size=2)):
        lo, hi = boxes[j]
        p = lo + (hi - lo) * draw(st.floats(0, 1))
        seeds[j] = (p, p)
    targets = {}
    for j in draw(st.sets(st.integers(0, k - 1), max_size=2)):
        targets[j] = (boxes[j][1] - 0.5, boxes[j][1])
    g_lo = np.array([draw(st.sampled_from([0.0, 0.3, 1.0])), draw(st.sampled_from([0.0, 0.5, 2.0]))])
    g_hi = np.array([draw(st.sampled_from([0.0, 0.3, 1.0])), draw(st.sampled_from([0.0, 0.5, 2.0]))])
    return seeds, boxes, adjacency, g_lo, g_hi, draw(st.integers(0, 30)), targets


@settings(max_examples=300, deadline=None)
@given(graphs())
def test_sweep_agrees_with_the_reference(args) -> None:
    seeds, boxes, adjacency, g_lo, g_hi, limit, targets = args
    fast = _sweep(seeds, boxes, adjacency, g_lo, g_hi, limit, targets)
    ref = _sweep_reference(seeds, boxes, adjacency, g_lo, g_hi, limit, targets)
    assert fast == ref


def test_sweep_on_a_corridor() -> None:
    """Three unit boxes in a row, growth 0.5 per step from the left end: the middle box
    is reached at step 2 (x = 1), the last at step 4, the target at x >= 2.9 at step 6."""
    boxes = [(np.array([float(i), 0.0]), np.array([i + 1.0, 1.0])) for i in range(3)]
    first, hit = _sweep(
        {0: (np.zeros(2), np.zeros(2))},
        boxes,
        [(1,), (0, 2), (1,)],
        np.full(2, 0.5),
        np.full(2, 0.5),
        50,
        {2: (np.array([2.9, 0.0]), np.array([3.0, 0.1]))},
    )
    assert first == [0, 2, 4] and hit == 6

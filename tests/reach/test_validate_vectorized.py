"""The validator's vectorised box check agrees with its scalar Liang-Barsky kernel."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.collisions import (
    _Obstacle,
    hits_all,
    hits_table,
    segment_enters_open_box,
    segments_enter_open_box,
)
from plansynth.reach.geometry import Box, Polygon

coord = st.sampled_from([0.0, 1.0, 2.0, 3.0, -1.0, 0.5, 2.5]) | st.floats(-3, 4, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.tuples(coord, coord, coord, coord), min_size=1, max_size=12),
    st.tuples(coord, coord),
    st.tuples(coord, coord),
)
def test_vectorised_box_check_agrees_with_the_scalar_one(segs, lo, hi) -> None:
    S = np.array(segs, dtype=float)
    P, Q = S[:, :2], S[:, 2:]
    lo_, hi_ = np.array(lo), np.array(hi)
    got = segments_enter_open_box(P, Q, lo_, hi_)
    with np.errstate(over="ignore"):  # (tiny steps: the scalar kernel overflows to inf, as it may)
        want = [segment_enters_open_box(p, q, lo_, hi_) for p, q in zip(P, Q)]
        points = [segment_enters_open_box(p, p, lo_, hi_) for p in P]
    assert got.tolist() == want
    # samples: the segment p-p
    assert segments_enter_open_box(P, P, lo_, hi_).tolist() == points


def test_a_crossing_a_touching_and_a_missing_segment() -> None:
    lo, hi = np.array([1.0, 1.0]), np.array([2.0, 2.0])
    P = np.array([[0.0, 1.5], [0.0, 1.0], [0.0, 3.0]])
    Q = np.array([[3.0, 1.5], [3.0, 1.0], [3.0, 3.0]])
    assert segments_enter_open_box(P, Q, lo, hi).tolist() == [True, False, False]


@settings(max_examples=100, deadline=None)
@given(
    st.lists(st.tuples(coord, coord, coord, coord), min_size=0, max_size=20),
    st.lists(st.tuples(coord, coord, st.floats(0, 3), st.floats(0, 3)), min_size=0, max_size=8),
    st.booleans(),
)
def test_the_obstacle_table_agrees_with_one_obstacle_at_a_time(segs, rects, polygon) -> None:
    """Box obstacles checked together (bounding-box filter, then the exact test on the
    pairs left) give the table the plain per-obstacle check gives, samples and segments."""
    S = np.array(segs, dtype=float).reshape(-1, 4)
    P, Q = S[:, :2], S[:, 2:]
    shapes = [Box((x, y), (x + w, y + h)) for x, y, w, h in rects]
    if polygon:
        shapes.append(Polygon(((0.0, 0.0), (2.0, 0.0), (1.0, 1.5))))
    obstacles = [_Obstacle(sh, 1e-6) for sh in shapes]
    with np.errstate(over="ignore"):
        for Q_ in (None, Q):
            want = np.array([hits_all(ob, P, Q_) for ob in obstacles], dtype=bool).reshape(len(obstacles), len(P))
            assert np.array_equal(hits_table(obstacles, P, Q_), want)

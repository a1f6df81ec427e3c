"""The validator's vectorised box check agrees with its scalar Liang-Barsky kernel."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.validate import _segment_enters_open_box, _segments_enter_open_box

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
    got = _segments_enter_open_box(P, Q, lo_, hi_)
    with np.errstate(over="ignore"):  # (tiny steps: the scalar kernel overflows to inf, as it may)
        want = [_segment_enters_open_box(p, q, lo_, hi_) for p, q in zip(P, Q)]
        points = [_segment_enters_open_box(p, p, lo_, hi_) for p in P]
    assert got.tolist() == want
    # samples: the segment p-p
    assert _segments_enter_open_box(P, P, lo_, hi_).tolist() == points


def test_a_crossing_a_touching_and_a_missing_segment() -> None:
    lo, hi = np.array([1.0, 1.0]), np.array([2.0, 2.0])
    P = np.array([[0.0, 1.5], [0.0, 1.0], [0.0, 3.0]])
    Q = np.array([[3.0, 1.5], [3.0, 1.0], [3.0, 3.0]])
    assert _segments_enter_open_box(P, Q, lo, hi).tolist() == [True, False, False]

"""How deep a straight segment enters a convex set (beyond Shoukry et al., CDC 2016):
the exact test of segment safety against a convex obstacle piece that the exact
segment transitions (:mod:`plansynth.reach.lazy.segtheory`,
:mod:`plansynth.reach.lazy.bounds.segpairs`) apply to the LPs' solutions."""

from __future__ import annotations

import numpy as np

__all__ = ["segment_depth"]


def segment_depth(P: np.ndarray, Q: np.ndarray, H: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """How deep each segment [P[k], Q[k]] enters the convex set {x : H x < h} (unit rows):
    the largest over s in [0, 1] of min_f (h_f - H_f (P + s (Q - P))), and that s. A
    depth <= 0 means the segment avoids the interior. The function of s is concave and
    piecewise linear: its maximum is at 0, 1 or where two faces' slacks cross.

    >>> H = np.array([[1.0, 0], [-1.0, 0], [0, 1.0], [0, -1.0]]); h = np.array([1.0, 0, 1, 0])
    >>> d, s = segment_depth(np.array([[-1.0, 0.5], [-0.5, 0.7]]), np.array([[2.0, 0.5], [0.4, 1.6]]), H, h)
    >>> d.round(3).tolist(), s.round(3).tolist()      # through the unit square; past its corner (0, 1)
    ([0.5, -0.1], [0.5, 0.444])
    """
    a = h[None, :] - P @ H.T  # slack at s = 0, per segment and face
    b = -(Q - P) @ H.T  # its slope in s
    F = H.shape[0]
    iu, ju = np.triu_indices(F, 1)
    den = b[:, iu] - b[:, ju]
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = np.where(den != 0, (a[:, ju] - a[:, iu]) / den, 0.0)
    s = np.concatenate([np.zeros((len(P), 1)), np.ones((len(P), 1)), np.clip(cross, 0.0, 1.0)], axis=1)
    vals = np.min(a[:, None, :] + b[:, None, :] * s[:, :, None], axis=2)
    k = np.argmax(vals, axis=1)
    rows = np.arange(len(P))
    return vals[rows, k], s[rows, k]

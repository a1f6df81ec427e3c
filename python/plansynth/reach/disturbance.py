"""Bounded additive disturbances: the set W of ``x' = A x + B u + w`` (a problem's
``robot.disturbance``) and the feedback design asked for with it.

Shoukry et al. (CDC 2016, Section VII) leave "planning in the presence of uncertainties
in the dynamics and bounded disturbances" as future work. A :class:`Disturbance` says
what the world may do at every step: ``w`` in a box ``|w_i| <= box[i]`` or in a
polytope ``W = conv(vertices)``, and W must contain 0 (a disturbance that can be absent;
a constant drift belongs in the dynamics). It also names the feedback law the robot
runs around its nominal plan, ``u = v + K (x - x_nom)``: a discrete LQR gain
(``lqr``, the default, with diagonal weights), a deadbeat gain (``deadbeat``) or a gain
given outright (``gain``); :mod:`plansynth.reach.robust.feedback` designs it, and
:mod:`plansynth.reach.tube` bounds the error it leaves.

Everything here is a value: a support function and a vertex list, nothing that plans.

>>> w = Disturbance(box=(0.02, 0.02, 0.05, 0.05))
>>> w.support(np.array([[1.0, 0, 0, 0], [1.0, 0, -2.0, 0]])).tolist()
[0.02, 0.12000000000000001]
>>> Disturbance(vertices=((1.0, 0.0), (-1.0, 1.0), (0.0, -1.0))).support(np.array([[0.0, 1.0]])).tolist()
[1.0]
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product

import numpy as np

from plansynth.reach.geometry import _array_key, _frozen_array

__all__ = ["Disturbance", "FEEDBACK_DESIGNS", "MAX_VERTICES", "origin_inside"]

#: the feedback designs a disturbance may ask for (see plansynth.reach.robust.feedback)
FEEDBACK_DESIGNS = ("lqr", "deadbeat", "gain")
#: most vertices of a polytope W
MAX_VERTICES = 1000


@dataclass(frozen=True, eq=False)
class Disturbance:
    """The disturbance set W (a box or a polytope, containing 0) and the feedback design.

    ``box``: half-widths, one per state (``|w_i| <= box[i]``). ``vertices``: the
    vertices of a polytope W (one per row, n columns). Exactly one of the two is given.
    ``feedback``: ``"lqr"`` (weights ``q`` on the states and ``r`` on the inputs, the
    diagonals of Q and R; default: identities), ``"deadbeat"``, or ``"gain"`` with
    ``gain`` the m x n matrix K. Arrays are read-only; equality is by value.
    """

    box: tuple[float, ...] | None = None
    vertices: np.ndarray | None = None
    feedback: str = "lqr"
    q: tuple[float, ...] | None = None
    r: tuple[float, ...] | None = None
    gain: np.ndarray | None = None

    def __post_init__(self) -> None:
        if (self.box is None) == (self.vertices is None):
            raise ValueError("a disturbance is a box or a polytope (vertices), exactly one of the two")
        if self.box is not None:
            object.__setattr__(self, "box", tuple(float(v) for v in self.box))
        if self.vertices is not None:
            object.__setattr__(self, "vertices", _frozen_array(np.atleast_2d(np.asarray(self.vertices, float))))
        for key in ("q", "r"):
            value = getattr(self, key)
            if value is not None:
                object.__setattr__(self, key, tuple(float(v) for v in value))
        if self.gain is not None:
            object.__setattr__(self, "gain", _frozen_array(np.atleast_2d(np.asarray(self.gain, float))))
        if self.feedback not in FEEDBACK_DESIGNS:
            raise ValueError(f"unknown feedback design {self.feedback!r} (known: {', '.join(FEEDBACK_DESIGNS)})")
        if (self.feedback == "gain") != (self.gain is not None):
            raise ValueError("feedback 'gain' goes with a gain matrix, and only it")

    @property
    def dim(self) -> int:
        """The number of components of w (the state's)."""
        return len(self.box) if self.box is not None else int(self.vertices.shape[1])  # type: ignore[union-attr]

    @property
    def kind(self) -> str:
        """``"box"`` or ``"polytope"``."""
        return "box" if self.box is not None else "polytope"

    def support(self, directions: np.ndarray) -> np.ndarray:
        """``h_W(c) = max_{w in W} c . w`` for every row c of ``directions`` (k x n).

        Exact: a box's is ``|c| . box``, a polytope's the largest value at a vertex.
        """
        D = np.atleast_2d(np.asarray(directions, float))
        if self.box is not None:
            return np.abs(D) @ np.asarray(self.box)
        return np.max(D @ np.asarray(self.vertices).T, axis=1)

    def support_batch(self, directions: np.ndarray) -> np.ndarray:
        """:meth:`support` over the last axis of a (..., n) array of directions."""
        D = np.asarray(directions, float)
        if self.box is not None:
            return np.abs(D) @ np.asarray(self.box)
        return np.max(D @ np.asarray(self.vertices).T, axis=-1)

    def corners(self) -> np.ndarray:
        """The vertices of W (a box's 2^k corners over its k nonzero half-widths, 0
        on the others), one per row.

        >>> Disturbance(box=(0.5, 0.0)).corners().tolist()
        [[-0.5, 0.0], [0.5, 0.0]]
        """
        if self.vertices is not None:
            return np.array(self.vertices)
        w = np.asarray(self.box)
        live = np.nonzero(w > 0)[0]
        out = np.zeros((2 ** len(live), len(w)))
        for row, signs in enumerate(product((-1.0, 1.0), repeat=len(live))):
            out[row, live] = np.array(signs) * w[live]
        return out

    def radius(self) -> float:
        """The largest Euclidean norm of a w in W."""
        if self.box is not None:
            return float(np.linalg.norm(self.box))
        return float(np.max(np.linalg.norm(self.vertices, axis=1)))

    def _key(self) -> tuple:
        return (self.box, _array_key(self.vertices), self.feedback, self.q, self.r, _array_key(self.gain))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Disturbance):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


def origin_inside(vertices: np.ndarray, tol: float = 1e-9) -> bool:
    """Is 0 in the convex hull of the rows of ``vertices``? (A feasibility LP:
    nonnegative weights summing to 1 whose combination is 0, within ``tol``.)

    >>> origin_inside(np.array([[1.0, 0.0], [-1.0, 1.0], [0.0, -1.0]]))
    True
    >>> origin_inside(np.array([[1.0, 0.0], [2.0, 1.0]]))
    False
    """
    import highspy

    from plansynth.reach.highs import csc_lp, new_highs

    V = np.atleast_2d(np.asarray(vertices, float))
    k, n = V.shape
    rows, cols = np.nonzero(np.vstack([V.T, np.ones((1, k))]))
    vals = np.vstack([V.T, np.ones((1, k))])[rows, cols]
    lo = np.concatenate([np.full(n, -tol), [1.0]])
    hi = np.concatenate([np.full(n, tol), [1.0]])
    lp = csc_lp(k, n + 1, rows, cols, vals, np.zeros(k), np.zeros(k), np.full(k, highspy.kHighsInf), lo, hi)
    h = new_highs()
    h.passModel(lp)
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kOptimal

"""The tube around a nominal plan: the error sets of the closed loop under a bounded
disturbance, and their support functions (tube MPC's constraint tightening; Chisci,
Rossiter and Zappa, "Systems with persistent disturbances: predictive control with
restricted constraints", Automatica 2001; Mayne, Seron and Rakovic, Automatica 2005).

A robot that follows a nominal plan (x_nom, v) with the feedback law
``u_t = v_t + K (x_t - x_nom_t)`` under ``x' = A x + B u + w``, ``w in W``, keeps its
error ``e = x - x_nom`` on ``e_{t+1} = (A + B K) e_t + w_t`` from ``e_0 = 0``; so at step t

    e_t in E_t = W + A_K W + ... + A_K^{t-1} W        (A_K = A + B K, Minkowski sums)

and every such e_t is reached by some disturbance sequence. For a box W each E_t is a
zonotope (generators ``A_K^i diag(box)``), for a polytope W a sum of polytopes; either
way its support function is the sum ``h_{E_t}(c) = sum_{i<t} h_W((A_K^i)^T c)``, exact,
and with 0 in W it never decreases in t (E_t is inside E_{t+1}).

**Truncation.** The sum is computed exactly for the first ``exact_steps`` = I terms, the
first power with ``|A_K^I|_2 <= TAIL_NORM``. What any later term can add is bounded, not
dropped: ``h_{E_t}(c) - h_{E_I}(c) <= |c|_2 r_W sum_{i>=I} |A_K^i|_2`` with ``r_W`` the
largest norm in W, and with a power J whose norm q = |A_K^J|_2 is below 1,
``sum_{i>=I} |A_K^i|_2 <= sum_{j<J} |A_K^{I+j}|_2 / (1 - q)`` (submultiplicativity). So
:meth:`Tube.support` is exact up to step I and from there on the constant
``h_{E_I}(c) + |c|_2 r_W tail``, an upper bound of every later ``h_{E_t}(c)``: margins
that never decrease and end in a constant, the *cap*.

>>> from plansynth.reach.disturbance import Disturbance
>>> A_K = np.array([[0.5, 0.0], [0.0, 0.0]])
>>> tube = Tube(A_K, np.zeros((1, 2)), Disturbance(box=(1.0, 1.0)))
>>> tube.support(np.array([[1.0, 0.0], [0.0, 1.0]]), 3).tolist()
[[0.0, 0.0], [1.0, 1.0], [1.5, 1.0], [1.75, 1.0]]
>>> bool(abs(tube.cap(np.array([[1.0, 0.0]]))[0] - 2.0) < 1e-6)   # 1 + 1/2 + 1/4 + ... = 2
True
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from plansynth.reach.disturbance import Disturbance
from plansynth.reach.geometry import _array_key, _frozen_array

__all__ = ["Tube", "TAIL_NORM", "MAX_EXACT_STEPS", "UnstableFeedback"]

#: terms of the error sets are summed exactly until the power of A_K drops below this (2-norm)
TAIL_NORM = 1e-9
#: most exact terms (a closed loop that needs more is too slow to bound this way)
MAX_EXACT_STEPS = 20_000


class UnstableFeedback(ValueError):
    """A_K = A + B K is not stable enough for its error sets to be bounded."""


@dataclass(frozen=True, eq=False)
class Tube:
    """The error sets E_t of the closed loop ``A_K = A + B K`` under ``W`` (module doc).

    ``A_K``: the closed-loop matrix (n x n); ``K``: the gain (m x n), for the input's
    margins ``h_{K E_t}``; ``W``: the disturbance. :attr:`exact_steps` and :attr:`tail`
    are computed once.
    """

    A_K: np.ndarray
    K: np.ndarray
    W: Disturbance

    def __post_init__(self) -> None:
        object.__setattr__(self, "A_K", _frozen_array(self.A_K))
        object.__setattr__(self, "K", _frozen_array(np.atleast_2d(self.K)))

    @cached_property
    def _powers(self) -> tuple[np.ndarray, int, float]:
        """(A_K^0 .. A_K^(I-1), I, tail): the exact powers and the bound on
        ``sum_{i>=I} |A_K^i|_2``."""
        A = np.asarray(self.A_K, float)
        n = A.shape[0]
        if not np.all(np.isfinite(A)) or (n and float(np.max(np.abs(np.linalg.eigvals(A)))) >= 1.0 - 1e-9):
            raise UnstableFeedback("the closed loop A + B K is not stable (spectral radius >= 1)")
        powers = [np.eye(n)]
        norms = [1.0 if n else 0.0]
        while norms[-1] > TAIL_NORM:
            if len(powers) > MAX_EXACT_STEPS:
                raise UnstableFeedback(
                    f"the closed loop A + B K converges too slowly: |A_K^{MAX_EXACT_STEPS}|_2 > {TAIL_NORM:g}"
                )
            powers.append(powers[-1] @ A)
            norms.append(float(np.linalg.norm(powers[-1], 2)))
        I = len(powers) - 1  # |A_K^I|_2 <= TAIL_NORM: the terms 0..I-1 are summed exactly
        # a power J < I with |A_K^J|_2 < 1 bounds every later one; then the J norms from I on
        J = next((j for j in range(1, I + 1) if norms[j] < 1.0), I) if I else 1
        q = norms[J] if I else 0.0
        P = powers[I]
        tail_terms = []
        for _ in range(J):
            tail_terms.append(float(np.linalg.norm(P, 2)))
            P = P @ A
        tail = sum(tail_terms) / (1.0 - q) if I else 0.0
        stack = np.array(powers[:I]) if I else np.zeros((0, n, n))
        return stack, I, tail * (1.0 + 1e-9)

    @property
    def exact_steps(self) -> int:
        """I: the error sets E_0..E_I are summed exactly; later ones are bounded."""
        return self._powers[1]

    @property
    def tail(self) -> float:
        """The bound on ``sum_{i >= I} |A_K^i|_2`` (module doc)."""
        return self._powers[2]

    @property
    def varies(self) -> bool:
        """Do the error sets change with t (W is not {0})? Then a constraint tightened
        by them is tighter at later steps."""
        return self.W.radius() > 0.0

    def support(self, directions: np.ndarray, steps: int | None = None) -> np.ndarray:
        """``h_{E_t}(c)`` for t = 0..``steps`` (rows) and every row c of ``directions``
        (columns): exact up to :attr:`exact_steps`, the cap after (module doc).
        ``steps`` None: up to ``exact_steps + 1``, whose row is the cap."""
        D = np.atleast_2d(np.asarray(directions, float))
        P, I, tail = self._powers
        steps = I + 1 if steps is None else int(steps)
        terms = self.W.support_batch(np.einsum("kn,inm->ikm", D, P)) if I else np.zeros((0, len(D)))
        exact = np.vstack([np.zeros((1, len(D))), np.cumsum(terms, axis=0)])  # E_0..E_I
        cap = exact[-1] + np.linalg.norm(D, axis=1) * self.W.radius() * tail
        out = np.empty((steps + 1, len(D)))
        k = min(steps, I)
        out[: k + 1] = exact[: k + 1]
        out[k + 1 :] = cap
        # round-off must not make a margin shrink: the sums are monotone in exact arithmetic
        np.maximum.accumulate(out, axis=0, out=out)
        return out

    def cap(self, directions: np.ndarray) -> np.ndarray:
        """``sup_t h_{E_t}(c)``, bounded above (the last row of :meth:`support`)."""
        return self.support(directions)[-1]

    def state_margins(self, steps: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """How much every state bound tightens at t = 0..steps: ``(lo, hi)`` with
        ``lo[t, i] = h_{E_t}(-e_i)`` (the lower bound rises by it) and ``hi[t, i] =
        h_{E_t}(e_i)`` (the upper bound falls by it)."""
        n = self.A_K.shape[0]
        s = self.support(np.vstack([-np.eye(n), np.eye(n)]), steps)
        return s[:, :n], s[:, n:]

    def input_margins(self, steps: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """How much the input bound tightens at t = 0..steps, per input: ``(lo, hi)``
        with ``hi[t, j] = h_{K E_t}(e_j) = h_{E_t}(K_j)`` (the feedback's share of the
        input) and ``lo[t, j] = h_{E_t}(-K_j)``."""
        K = np.asarray(self.K, float)
        m = K.shape[0]
        s = self.support(np.vstack([-K, K]), steps)
        return s[:, :m], s[:, m:]

    def position_margins(self, H: np.ndarray, position: tuple[int, ...], steps: int | None = None) -> np.ndarray:
        """``h_{E_t}`` of the rows of ``H`` (k x d, on the position components
        ``position``), for t = 0..steps: how far each half-space ``H p <= h`` tightens."""
        H = np.atleast_2d(np.asarray(H, float))
        D = np.zeros((len(H), self.A_K.shape[0]))
        D[:, list(position)] = H
        return self.support(D, steps)

    def bounds(
        self, lo: np.ndarray, hi: np.ndarray, input_bound: float, horizon: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The state bounds ``lo``/``hi`` and the input bound tightened at every step of
        a plan of ``horizon`` steps from the start (E_0 at step 0): the states' (horizon
        + 1, n) and the inputs' (horizon, m) lower and upper bounds, for the one-shot
        models (the MILPs) that lay out a whole plan at once."""
        s_lo, s_hi = self.state_margins(horizon)
        u_lo, u_hi = self.input_margins(horizon)
        x_lo = np.asarray(lo, float)[None, :] + s_lo
        x_hi = np.asarray(hi, float)[None, :] - s_hi
        return x_lo, x_hi, -input_bound + u_lo[:horizon], input_bound - u_hi[:horizon]

    def _key(self) -> tuple:
        return (_array_key(self.A_K), _array_key(self.K), self.W)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Tube):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

"""The feedback law around a nominal plan, ``u = v + K (x - x_nom)``: the design of K.

Three designs (a problem's ``robot.disturbance.feedback``):

``lqr`` (default)  the discrete-time LQR gain of ``x' = A x + B u`` with diagonal
                   weights Q (``q``, default the identity) and R (``r``, default the
                   identity): ``K = -(R + B^T X B)^-1 B^T X A`` with X the stabilising
                   solution of the discrete algebraic Riccati equation (DARE)
                   ``X = A^T X A - A^T X B (R + B^T X B)^-1 B^T X A + Q``, solved by the
                   structure-preserving doubling algorithm (Chu, Fan, Lin and Wang, "A
                   structure-preserving doubling algorithm for periodic discrete-time
                   algebraic Riccati equations", 2004: quadratic convergence, numpy
                   only). Why LQR: it exists whenever (A, B) is stabilisable, its closed
                   loop is stable with margin, and it trades the error the tube keeps
                   (how far the obstacles grow) against the input it spends (how much of
                   the input bound the tube takes) by one pair of weights.
``deadbeat``       every closed-loop eigenvalue at 0, so (A + B K)^k = 0 after k steps
                   (k the chain's order): the error sets stop growing after k steps and
                   the tube is exact with no tail. Ackermann's formula
                   ``K = -e_k^T C^-1 A^k`` (C the controllability matrix) per axis of a
                   named integrator chain (A = A1 (x) I, B = B1 (x) I), or on explicit
                   dynamics with one input. It reacts hardest, so it keeps the smallest
                   error and spends the most input.
``gain``           K as given (m x n); it must make A + B K stable.

The design is checked: A + B K must be stable (spectral radius below 1), the Riccati
residual small, a deadbeat loop nilpotent; otherwise :class:`~plansynth.errors.InvalidProblem`
names the field ``robot.disturbance.feedback``. A plan is robust *for this K*: no robust
plan for this design does not mean none for another (the result says so).

>>> from plansynth.reach.dynamics import double_integrator
>>> from plansynth.reach.disturbance import Disturbance
>>> f = design_feedback(double_integrator(1, 0.5), Disturbance(box=(0.02, 0.05)))
>>> f.design, np.round(f.K, 3).tolist(), round(f.spectral_radius, 3)
('lqr', [[-0.651, -1.314]], 0.651)
>>> g = design_feedback(double_integrator(1, 0.5), Disturbance(box=(0.02, 0.05), feedback="deadbeat"))
>>> g.K.tolist(), g.spectral_radius
([[-4.0, -3.0]], 0.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import LinearDynamics, chain_axis_matrices

__all__ = ["Feedback", "design_feedback", "dare", "deadbeat_gain"]

#: the doubling iterations stop when X changes by less than this (relative)
DARE_TOL = 1e-13
DARE_MAX_ITERATIONS = 200
FIELD = "robot.disturbance.feedback"


@dataclass(frozen=True, eq=False)
class Feedback:
    """A designed gain: ``K`` (m x n), the ``design`` that made it, the closed loop
    ``A_K = A + B K`` and its spectral radius, and one line saying how it was made."""

    K: np.ndarray
    design: str
    A_K: np.ndarray
    spectral_radius: float
    how: str


def dare(A: np.ndarray, B: np.ndarray, Q: np.ndarray, R: np.ndarray) -> np.ndarray:
    """The stabilising solution X of the DARE (module doc) by the doubling algorithm:
    ``A_0 = A``, ``G_0 = B R^-1 B^T``, ``H_0 = Q``; ``W = I + G_k H_k``,
    ``A_{k+1} = A_k W^-1 A_k``, ``G_{k+1} = G_k + A_k W^-1 G_k A_k^T``,
    ``H_{k+1} = H_k + A_k^T H_k W^-1 A_k``; H_k converges to X. Raises ValueError
    when it does not converge (A, B not stabilisable) or X is not a solution.

    >>> X = dare(np.array([[1.0]]), np.array([[1.0]]), np.eye(1), np.eye(1))
    >>> round(float(X[0, 0]), 6)    # X^2 - X - 1 = 0: the golden ratio
    1.618034
    """
    A, B, Q, R = (np.asarray(M, float) for M in (A, B, Q, R))
    n = A.shape[0]
    I = np.eye(n)
    Ak, G, H = A.copy(), B @ np.linalg.solve(R, B.T), Q.copy()
    for _ in range(DARE_MAX_ITERATIONS):
        if not (np.all(np.isfinite(H)) and np.abs(H).max() < 1e150):
            raise ValueError("the Riccati iteration diverged: (A, B) is not stabilisable")
        W = I + G @ H
        Wi_A = np.linalg.solve(W, Ak)
        Wi_G = np.linalg.solve(W, G)
        H_next = H + Ak.T @ H @ Wi_A
        G = G + Ak @ Wi_G @ Ak.T
        Ak = Ak @ Wi_A
        if not np.all(np.isfinite(H_next)):
            raise ValueError("the Riccati iteration diverged: (A, B) is not stabilisable")
        done = np.linalg.norm(H_next - H) <= DARE_TOL * max(1.0, np.linalg.norm(H_next))
        H = H_next
        if done:
            break
    else:
        raise ValueError(f"the Riccati iteration did not converge in {DARE_MAX_ITERATIONS} doublings")
    X = (H + H.T) / 2
    with np.errstate(over="ignore", invalid="ignore"):
        S = R + B.T @ X @ B
        residual = A.T @ X @ A - A.T @ X @ B @ np.linalg.solve(S, B.T @ X @ A) + Q - X
        size = float(np.linalg.norm(X))
        miss = float(np.linalg.norm(residual))
    if not (np.isfinite(size) and np.isfinite(miss)) or size > 1e150:
        raise ValueError("the Riccati iteration diverged: (A, B) is not stabilisable")
    if miss > 1e-8 * max(1.0, size):
        raise ValueError(f"the Riccati solution misses the equation by {miss:.2e}")
    K = -np.linalg.solve(S, B.T @ X @ A)
    if float(np.max(np.abs(np.linalg.eigvals(A + B @ K)))) >= 1.0:
        raise ValueError("the Riccati solution does not stabilise: (A, B) is not stabilisable")
    return X


def _ackermann(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The deadbeat gain of a single-input pair (A, b): ``-e_n^T C^-1 A^n``."""
    n = A.shape[0]
    C = np.hstack([np.linalg.matrix_power(A, i) @ b for i in range(n)])
    if np.linalg.matrix_rank(C) < n:
        raise ValueError("(A, B) is not controllable: no deadbeat gain")
    e = np.zeros((1, n))
    e[0, -1] = 1.0
    return -e @ np.linalg.solve(C, np.linalg.matrix_power(A, n))


def deadbeat_gain(dynamics: LinearDynamics) -> np.ndarray:
    """A gain with every eigenvalue of A + B K at 0: per axis of a named integrator
    chain, or for explicit dynamics with one input (ValueError otherwise).

    >>> from plansynth.reach.dynamics import integrator_chain
    >>> K = deadbeat_gain(integrator_chain(3, 2, 1.0))
    >>> dyn = integrator_chain(3, 2, 1.0)
    >>> float(np.abs(np.linalg.matrix_power(dyn.A + dyn.B @ K, 3)).max()) < 1e-9
    True
    """
    A, B = np.asarray(dynamics.A, float), np.asarray(dynamics.B, float)
    if dynamics.model != "explicit":
        d = len(dynamics.position)
        A1, B1 = chain_axis_matrices(dynamics.order or 1, dynamics.dt)  # type: ignore[arg-type]
        return np.kron(_ackermann(A1, B1), np.eye(d))
    if B.shape[1] == 1:
        return _ackermann(A, B)
    raise ValueError(
        "a deadbeat gain is designed for the named integrator models and for explicit dynamics with one "
        "input; use lqr or give the gain"
    )


def design_feedback(dynamics: LinearDynamics, disturbance: Disturbance, source: str | None = None) -> Feedback:
    """The gain the disturbance's design asks for, checked (module doc)."""
    A, B = np.asarray(dynamics.A, float), np.asarray(dynamics.B, float)
    n, m = A.shape[0], B.shape[1]
    design = disturbance.feedback
    try:
        if design == "lqr":
            Q = np.diag(disturbance.q) if disturbance.q is not None else np.eye(n)
            R = np.diag(disturbance.r) if disturbance.r is not None else np.eye(m)
            X = dare(A, B, Q, R)
            K = -np.linalg.solve(R + B.T @ X @ B, B.T @ X @ A)
            weights = (
                "Q = I, R = I"
                if disturbance.q is None and disturbance.r is None
                else f"Q = diag({_list(np.diag(Q))}), R = diag({_list(np.diag(R))})"
            )
            how = f"discrete LQR ({weights}; DARE by the doubling algorithm)"
        elif design == "deadbeat":
            K = deadbeat_gain(dynamics)
            how = "deadbeat (every closed-loop eigenvalue at 0, Ackermann's formula)"
        else:
            K = np.asarray(disturbance.gain, float)
            how = "given in the problem"
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise InvalidProblem(source, FIELD, f"{design}: {exc}") from None
    A_K = A + B @ K
    rho = float(np.max(np.abs(np.linalg.eigvals(A_K)))) if n else 0.0
    if design == "deadbeat":
        P = np.linalg.matrix_power(A_K, n)
        if np.max(np.abs(P)) > 1e-9 * max(1.0, float(np.max(np.abs(A_K)))) ** n:
            raise InvalidProblem(source, FIELD, "deadbeat: the closed loop is not nilpotent (ill-conditioned)")
        rho = 0.0
    if not rho < 1.0 - 1e-9:
        raise InvalidProblem(
            source, FIELD, f"{design}: the closed loop A + B K is not stable (spectral radius {rho:.6g} >= 1)"
        )
    return Feedback(K=K, design=design, A_K=A_K, spectral_radius=rho, how=how)


def _list(v: np.ndarray) -> str:
    return ", ".join(f"{x:g}" for x in v)

"""Exact discretisation of the named robot models (paper, Section II, eq. (1)).

A chain of ``k`` integrators per workspace axis, ``d^k p / dt^k = u``, has the
continuous-time form ``x' = N x + e u`` on one axis with ``N`` the nilpotent shift.
Because ``N^k = 0`` its zero-order-hold discretisation is a finite sum, so the
discrete-time matrices are exact closed forms, not approximations:

    A = sum_{j<k} (dt N)^j / j!          A[i, i+j] = dt^j / j!
    B = sum_{j<k} dt^{j+1} N^j e / (j+1)!   B[i]   = dt^(k-i) / (k-i)!

State order (spec): by derivative, then axis, ``[x, y, vx, vy, ...]``; input ``[ux, uy]``.

>>> dyn = double_integrator(dim=1, dt=0.5)
>>> dyn.A.tolist(), dyn.B.tolist()
([[1.0, 0.5], [0.0, 1.0]], [[0.125], [0.5]])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from plansynth.reach.geometry import _array_key, _frozen_array

__all__ = ["LinearDynamics", "NAMED_MODELS", "MODELS", "integrator_chain", "single_integrator", "double_integrator", "named_model", "chain_axis_matrices"]


NAMED_MODELS = ("single-integrator", "double-integrator", "integrator-chain")
MODELS = NAMED_MODELS + ("explicit",)


@dataclass(frozen=True, eq=False)
class LinearDynamics:
    """Discrete-time linear dynamics ``x' = A x + B u`` (paper, eq. (1)).

    ``position`` names the state components that are the workspace coordinates.
    ``model`` records where the matrices come from ("explicit" for matrices given in a
    file; named models are built by :mod:`plansynth.reach.dynamics`), ``dt`` the time
    step of a named model (None for explicit matrices) and ``order`` the chain order.
    Arrays are read-only copies; equality compares them element-wise.
    """

    A: np.ndarray
    B: np.ndarray
    position: tuple[int, ...]
    dt: float | None = None
    model: str = "explicit"
    order: int | None = None

    def __post_init__(self) -> None:
        A = _frozen_array(self.A)
        B = _frozen_array(self.B)
        if B.ndim == 1:
            B = _frozen_array(B.reshape(-1, 1))
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", B)
        object.__setattr__(self, "position", tuple(int(i) for i in self.position))
        if self.dt is not None:
            object.__setattr__(self, "dt", float(self.dt))
        if self.model not in MODELS:
            raise ValueError(f"unknown dynamics model {self.model!r} (known: {', '.join(MODELS)})")

    @property
    def n_states(self) -> int:
        return int(self.A.shape[0])

    @property
    def n_inputs(self) -> int:
        return int(self.B.shape[1])

    def step(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        """One step ``A x + B u``."""
        return self.A @ np.asarray(x, dtype=float) + self.B @ np.asarray(u, dtype=float)

    def _key(self) -> tuple:
        return (_array_key(self.A), _array_key(self.B), self.position, self.dt, self.model, self.order)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, LinearDynamics):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


def chain_axis_matrices(order: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One axis of an integrator chain of ``order`` >= 1: exact ``(A, B)``, k x k and k x 1.

    >>> A, B = chain_axis_matrices(3, 2.0)
    >>> A.tolist()
    [[1.0, 2.0, 2.0], [0.0, 1.0, 2.0], [0.0, 0.0, 1.0]]
    >>> B.ravel().tolist()
    [1.3333333333333333, 2.0, 2.0]
    """
    if order < 1:
        raise ValueError(f"integrator chain order must be >= 1, got {order}")
    if not dt > 0:
        raise ValueError(f"dt must be positive, got {dt}")
    k = order
    A = np.zeros((k, k))
    for i in range(k):
        for j in range(k - i):
            A[i, i + j] = dt**j / math.factorial(j)
    B = np.array([[dt ** (k - i) / math.factorial(k - i)] for i in range(k)])
    return A, B


def integrator_chain(order: int, dim: int, dt: float) -> LinearDynamics:
    """``order`` integrators per axis in ``dim`` axes, discretised exactly with step ``dt``.

    The state is ``[p (dim), p' (dim), ..., p^(order-1) (dim)]`` and the input is the
    ``order``-th derivative; so ``A = A1 (x) I_dim`` and ``B = B1 (x) I_dim``.

    >>> dyn = integrator_chain(3, 2, 0.5)
    >>> (dyn.n_states, dyn.n_inputs, dyn.position, dyn.model)
    (6, 2, (0, 1), 'integrator-chain')
    """
    A1, B1 = chain_axis_matrices(order, dt)
    eye = np.eye(dim)
    model = {1: "single-integrator", 2: "double-integrator"}.get(order, "integrator-chain")
    return LinearDynamics(
        A=np.kron(A1, eye),
        B=np.kron(B1, eye),
        position=tuple(range(dim)),
        dt=dt,
        model=model,
        order=order,
    )


def single_integrator(dim: int, dt: float) -> LinearDynamics:
    """Velocity-controlled point: ``p' = p + dt u``."""
    return integrator_chain(1, dim, dt)


def double_integrator(dim: int, dt: float) -> LinearDynamics:
    """Acceleration-controlled point mass (the paper's robot in Section VI)."""
    return integrator_chain(2, dim, dt)


def named_model(model: str, dim: int, dt: float, order: int | None = None) -> LinearDynamics:
    """The named model of the spec (``single-integrator``, ``double-integrator``,
    ``integrator-chain`` with ``order``).

    An ``integrator-chain`` of order 1 or 2 is recorded as the single/double integrator
    it equals, so files round-trip to the canonical name.
    """
    if model == "single-integrator":
        return single_integrator(dim, dt)
    if model == "double-integrator":
        return double_integrator(dim, dt)
    if model == "integrator-chain":
        if order is None:
            raise ValueError("integrator-chain needs an order")
        return integrator_chain(order, dim, dt)
    raise ValueError(f"unknown model {model!r}")

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

import functools
import math
from dataclasses import dataclass

import numpy as np

from plansynth.reach.geometry import _array_key, _frozen_array

__all__ = [
    "LinearDynamics",
    "NAMED_MODELS",
    "MODELS",
    "integrator_chain",
    "single_integrator",
    "double_integrator",
    "named_model",
    "chain_axis_matrices",
    "displacement_reach",
    "reach_steps",
]


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


#: the tail of an impulse response is summed until the power of the internal block
#: drops below this (2-norm); what is left is bounded, not dropped (see displacement_reach)
_TAIL_NORM = 1e-10
_MAX_TAIL = 20_000


def displacement_reach(dyn: LinearDynamics, input_bound: float, steps: int) -> np.ndarray | None:
    """``W[k, a]``: no trajectory that starts at rest moves its position along axis ``a``
    by more than ``W[k, a]`` (either way) in any ``k`` consecutive steps, k = 0..steps;
    None when the dynamics are not of the form below.

    For dynamics whose positions integrate internal states that do not depend on them,
    ``A = [[I, C], [0, F]]`` (positions first, after reordering) with F stable (some
    power of F has 2-norm below 1), such as the random robots of
    :func:`plansynth.reach.families.random_dynamics`. With ``Psi_j = P A^j B`` the
    position's impulse response (``Psi_0 = B_p``, ``Psi_j = B_p + C sum_{i<j} F^i G``),
    a trajectory from rest has ``p_{t+k} - p_t = sum_{j<k} Psi_j u_{t+k-1-j} +
    sum_{i<t} (Psi_{i+k} - Psi_i) u_{t-1-i}``, so with ``|u| <= input_bound`` per
    component (the l-infinity to l-infinity gain of that map, at the worst t):

        W[k, a] = input_bound (sum_{j<k} |Psi_j[a]|_1 + sum_{i>=0} |Psi_{i+k}[a] - Psi_i[a]|_1).

    The second sum converges (``Psi_{i+k} - Psi_i = C F^i S_k``, ``S_k = sum_{j<k} F^j
    G``) and is summed while ``|F^i|_2`` is above 1e-10; the rest is bounded by
    ``sqrt(m) |C[a]|_2 |S_k|_2 sum_{i>=I} |F^i|_2`` with the geometric series of
    ``|F^J|_2 < 1``, so W is an upper bound, never an estimate. State bounds are ignored
    (a relaxation: the bound holds with them). A stable internal block makes the robot's
    speed bounded by its inputs alone, where the one-step bound of
    :func:`plansynth.reach.lazy.bounds.step_reach` must let every internal state sit at
    its bound (n = 50 random dynamics: 16 m per step there, 0.75 m per step in the long
    run here). An integrator chain (F is not stable) gets None.

    >>> from plansynth.reach.families import random_dynamics
    >>> W = displacement_reach(random_dynamics(1, 10, seed=0).dynamics, 1.0, 200)
    >>> bool(W[1, 0] > 0), bool(np.all(np.diff(W[:, 0]) >= -1e-9))
    (True, True)
    >>> bool(abs(W[200, 0] / 200 - 0.75) < 0.05)   # long run: the steady-state speed, 1.5 m/s x 0.5 s
    True
    >>> displacement_reach(integrator_chain(2, 2, 0.5), 1.0, 10) is None
    True
    """
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    n, m = A.shape[0], B.shape[1]
    pos = list(dyn.position)
    internal = [i for i in range(n) if i not in set(pos)]
    d = len(pos)
    if not internal or not np.array_equal(A[np.ix_(pos, pos)], np.eye(d)) or np.any(A[np.ix_(internal, pos)] != 0):
        return None
    F = A[np.ix_(internal, internal)]
    if not np.all(np.isfinite(F)) or float(np.max(np.abs(np.linalg.eigvals(F)))) >= 1.0 - 1e-6:
        return None  # not stable (an integrator chain): no bound of this kind
    C = A[np.ix_(pos, internal)]
    G = B[internal]
    Bp = B[pos]
    # |F^i|_2 until below _TAIL_NORM: the terms summed exactly; the last J powers bound the rest
    norms = [1.0]
    P = np.eye(len(internal))
    while norms[-1] > _TAIL_NORM:
        if len(norms) > _MAX_TAIL:
            return None  # not stable enough to bound this way
        P = P @ F
        norms.append(float(np.linalg.norm(P, 2)))
    I = len(norms) - 1  # |F^I|_2 <= _TAIL_NORM
    # a power J with |F^J|_2 < 1: submultiplicativity bounds every later power
    J = next((j for j in range(1, I + 1) if norms[j] < 1.0), I)
    q = norms[J]
    # sum_{i >= I} |F^i|_2 <= sum_{r < J} |F^{I+r}|_2 / (1 - q) <= J |F^I|_2 max_{r<J}|F^r|_2 / (1 - q)
    tail_f = J * norms[I] * max(norms[: J + 1]) / (1.0 - q)
    # impulse responses Psi_0 .. Psi_{I + steps}
    total = I + steps + 1
    Psi = np.empty((total, d, m))
    Psi[0] = Bp
    acc = np.zeros((len(internal), m))  # sum_{i<j} F^i G
    Fi_G = G.copy()
    S = [np.zeros((len(internal), m))]  # S_k = sum_{j<k} F^j G, k = 0..steps
    for j in range(1, total):
        acc = acc + Fi_G
        Fi_G = F @ Fi_G
        Psi[j] = Bp + C @ acc
        if j <= steps:
            S.append(acc.copy())
    fresh = np.concatenate([np.zeros((1, d)), np.cumsum(np.abs(Psi[:steps]).sum(axis=2), axis=0)])
    W = np.empty((steps + 1, d))
    c_norm = np.linalg.norm(C, axis=1)
    for k in range(steps + 1):
        old = np.abs(Psi[k : k + I] - Psi[:I]).sum(axis=2).sum(axis=0)
        tail = math.sqrt(m) * c_norm * float(np.linalg.norm(S[k], 2)) * tail_f
        W[k] = fresh[k] + old + tail
    out = input_bound * W * (1.0 + 1e-9) + 1e-12
    out.setflags(write=False)
    return out


#: one table per robot (the transit layer and the horizon bound both ask)
displacement_reach = functools.lru_cache(maxsize=32)(displacement_reach)


def reach_steps(W: np.ndarray, dist: float, axis: int) -> int:
    """The fewest k with ``W[k, axis] >= dist`` (``len(W)`` when none in the table:
    more steps than it covers); a lower bound on the steps of a move by ``dist``."""
    if dist <= 0:
        return 0
    hit = np.nonzero(W[:, axis] >= dist * (1 - 1e-9) - 1e-9)[0]
    return int(hit[0]) if hit.size else len(W)

"""Exact discretisation of integrator chains, checked against independent routes:
a numerical matrix exponential of the continuous system (scaling and squaring of a
Taylor series of the augmented matrix), the double integrator's textbook closed form,
and a fine Runge-Kutta simulation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.dynamics import (
    chain_axis_matrices,
    double_integrator,
    integrator_chain,
    named_model,
    single_integrator,
)


def expm(M: np.ndarray) -> np.ndarray:
    """Matrix exponential by scaling and squaring a 30-term Taylor series."""
    norm = np.linalg.norm(M, 1)
    s = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0 else 0
    X = M / 2**s
    E = np.eye(len(M))
    term = np.eye(len(M))
    for k in range(1, 30):
        term = term @ X / k
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def continuous_chain(order: int, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """x' = Ac x + Bc u for the state [p, p', ..., p^(order-1)] (derivative-major)."""
    n = order * dim
    Ac = np.zeros((n, n))
    for k in range(order - 1):
        for a in range(dim):
            Ac[k * dim + a, (k + 1) * dim + a] = 1.0
    Bc = np.zeros((n, dim))
    for a in range(dim):
        Bc[(order - 1) * dim + a, a] = 1.0
    return Ac, Bc


def zoh(Ac: np.ndarray, Bc: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    n, m = Bc.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = Ac
    M[:n, n:] = Bc
    E = expm(M * dt)
    return E[:n, :n], E[:n, n:]


@settings(max_examples=60)
@given(order=st.integers(1, 8), dim=st.integers(1, 3), dt=st.floats(0.01, 2.0))
def test_matches_matrix_exponential(order: int, dim: int, dt: float) -> None:
    dyn = integrator_chain(order, dim, dt)
    A, B = zoh(*continuous_chain(order, dim), dt)
    assert dyn.A.shape == A.shape and dyn.B.shape == B.shape
    np.testing.assert_allclose(dyn.A, A, rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(dyn.B, B, rtol=1e-12, atol=1e-13)
    assert dyn.position == tuple(range(dim)) and dyn.dt == dt and dyn.order == order


@pytest.mark.parametrize("dt", [0.5, 0.1, 1.0, 2.0])
def test_double_integrator_closed_form(dt: float) -> None:
    dyn = double_integrator(2, dt)
    A = np.array([[1, 0, dt, 0], [0, 1, 0, dt], [0, 0, 1, 0], [0, 0, 0, 1]])
    B = np.array([[dt**2 / 2, 0], [0, dt**2 / 2], [dt, 0], [0, dt]])
    assert np.array_equal(dyn.A, A) and np.array_equal(dyn.B, B)
    assert dyn.model == "double-integrator" and (dyn.n_states, dyn.n_inputs) == (4, 2)


def test_single_integrator_and_names() -> None:
    dyn = single_integrator(3, 0.25)
    assert np.array_equal(dyn.A, np.eye(3)) and np.array_equal(dyn.B, 0.25 * np.eye(3))
    assert named_model("integrator-chain", 2, 0.5, 2) == double_integrator(2, 0.5)
    assert named_model("single-integrator", 2, 0.5).model == "single-integrator"
    assert integrator_chain(4, 2, 0.5).model == "integrator-chain"


def test_matches_rk4_simulation_with_constant_input() -> None:
    order, dim, dt = 5, 2, 0.7
    Ac, Bc = continuous_chain(order, dim)
    dyn = integrator_chain(order, dim, dt)
    rng = np.random.default_rng(0)
    x = rng.normal(size=order * dim)
    u = rng.normal(size=dim)
    y = x.copy()
    steps = 200
    h = dt / steps
    f = lambda z: Ac @ z + Bc @ u  # noqa: E731
    for _ in range(steps):
        k1 = f(y)
        k2 = f(y + h / 2 * k1)
        k3 = f(y + h / 2 * k2)
        k4 = f(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    np.testing.assert_allclose(dyn.step(x, u), y, rtol=1e-10, atol=1e-10)


def test_chain_is_nilpotent_exact_powers() -> None:
    # A = exp(dt N): A(dt1) A(dt2) = A(dt1 + dt2) exactly in exact arithmetic
    A1, _ = chain_axis_matrices(6, 0.5)
    A2, _ = chain_axis_matrices(6, 0.25)
    A3, _ = chain_axis_matrices(6, 0.75)
    np.testing.assert_allclose(A1 @ A2, A3, rtol=1e-14)


@pytest.mark.parametrize("order, dt", [(0, 0.5), (2, 0.0), (2, -1.0)])
def test_bad_arguments(order: int, dt: float) -> None:
    with pytest.raises(ValueError):
        chain_axis_matrices(order, dt)


def test_matrices_are_read_only() -> None:
    dyn = integrator_chain(3, 2, 0.5)
    with pytest.raises(ValueError):
        dyn.A[0, 0] = 2.0

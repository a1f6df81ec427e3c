"""The mazes of Shoukry et al. (CDC 2016, Section VI) with seeded random controllable
(A, B) pairs of n states: the paper's Figure 4 setting (random A and B at n = 50).
"""

from __future__ import annotations

import math

import numpy as np

from plansynth.reach.dynamics import LinearDynamics
from plansynth.reach.families.paper_maze import MAZE_SIZE, maze
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["random_dynamics", "RANDOM_DYNAMICS_MAX_HORIZON"]

#: ``max_horizon`` of every :func:`random_dynamics` instance (its docstring says why)
RANDOM_DYNAMICS_MAX_HORIZON = 400


def random_dynamics(n_passages: int, n_states: int, seed: int = 0, *, dt: float = 0.5) -> ReachProblem:
    """The maze with ``n_passages`` walls and a seeded random robot of ``n_states`` states.

    The state is x = (p, z): the position p in the plane (state components 0 and 1, the
    outputs) and k = n - 2 internal states; continuous time p' = C z, z' = F z + G u,
    discretised exactly with step dt = 0.5 s (matrix exponential). Drawn from
    ``numpy.random.default_rng(seed)``: F = S D S^-1 with S a random orthogonal matrix
    and D block-diagonal with 2 x 2 blocks [[a, -b], [b, a]], a ~ U[-1, -0.2], b ~
    U[0, 1] (one 1 x 1 block a when k is odd), so the internal modes are stable and
    their discrete eigenvalues exp((a +- ib) dt) have modulus in [0.61, 0.90]; the
    discrete A has spectral radius exactly 1 (the two position integrators); C is
    Gaussian with each row scaled to unit 1-norm; G is Gaussian, then right-multiplied so
    that the steady-state gain from u to p' is 1.5 I (a constant input |u| <= 1 moves
    the robot at up to 1.5 m/s per axis). Bounds: |u| <= 1, the position within the
    workspace, each internal state within twice the largest steady-state magnitude it
    takes under the four corner inputs (and at least 1). The pair (A, B) is controllable
    (the PBH test at every eigenvalue, relative tolerance 1e-9); a draw that fails, or
    whose steady-state gain -C F^-1 G is singular (|det| < 1e-6), is redrawn from the
    same generator. Start (1, 1) at rest (z = 0), goal as in :func:`maze`. The internal
    bounds bind: bang-bang inputs can drive an internal state past them (the l1 norm of
    its impulse response exceeds its bound up to 11x at n = 50, seed 0), so they are
    constraints, not decoration; the position moves at most 0.75 m per step in the long
    run but up to 4.3 m in one step (:func:`plansynth.reach.dynamics.displacement_reach`).
    A is dense (n = 50: 2,402 nonzeros). Plans are checked by the validator against
    these exact A, B (dynamics residual at most 1e-6 max(1, |x|); CON-PLAN re-solves a
    plan whose residual is above 1e-8). ``max_horizon`` is
    :data:`RANDOM_DYNAMICS_MAX_HORIZON` = 400 for every instance, twice the default of
    :class:`~plansynth.reach.problem.ReachProblem`: at the long-run speed of 0.75 m per step
    per axis, maze-4's horizontal travel alone (x from 1 to 27, then four times across
    between 3 and 27: 122 m) takes about 163 steps, before the turns at its gaps; at 200
    its plans at n = 4 and 20 sat at the very top and n = 50 found none.

    >>> p = random_dynamics(1, 8, seed=3)
    >>> p.dynamics.n_states, p.dynamics.position, p.starts_at_rest
    (8, (0, 1), True)
    >>> bool(abs(max(abs(np.linalg.eigvals(p.dynamics.A))) - 1.0) < 1e-9)
    True
    """
    if n_states < 4:
        raise ValueError(f"n_states must be >= 4, got {n_states}")
    rng = np.random.default_rng(seed)
    k = n_states - 2
    for _ in range(100):
        S, _r = np.linalg.qr(rng.standard_normal((k, k)))
        D = np.zeros((k, k))
        i = 0
        while i < k:
            a = rng.uniform(-1.0, -0.2)
            if i + 1 < k:
                b = rng.uniform(0.0, 1.0)
                D[i : i + 2, i : i + 2] = [[a, -b], [b, a]]
                i += 2
            else:
                D[i, i] = a
                i += 1
        F = S @ D @ S.T
        C = rng.standard_normal((2, k))
        C /= np.abs(C).sum(axis=1, keepdims=True)
        G = rng.standard_normal((k, 2))
        gain = -C @ np.linalg.solve(F, G)  # steady state: p' = gain u
        if abs(np.linalg.det(gain)) < 1e-6:
            continue
        G = G @ np.linalg.inv(gain) * 1.5
        Ac = np.zeros((n_states, n_states))
        Ac[:2, 2:] = C
        Ac[2:, 2:] = F
        Bc = np.zeros((n_states, 2))
        Bc[2:] = G
        A, B = _discretise(Ac, Bc, dt)
        if _controllable(A, B):
            break
    else:  # pragma: no cover - a controllable pair is drawn at once in practice
        raise RuntimeError("no controllable random pair drawn in 100 tries")
    zss = np.array([-np.linalg.solve(F, G @ np.array(u)) for u in ((1, 1), (1, -1), (-1, 1), (-1, -1))])
    zb = np.maximum(2.0 * np.abs(zss).max(axis=0), 1.0)
    base = maze(n_passages)
    dyn = LinearDynamics(A=A, B=B, position=(0, 1), dt=dt, model="explicit")
    start = np.zeros(n_states)
    start[:2] = (1.0, 1.0)
    S_ = MAZE_SIZE
    return ReachProblem(
        workspace=base.workspace,
        obstacles=base.obstacles,
        goal=base.goal,
        dynamics=dyn,
        start=start,
        input_bound=1.0,
        state_bounds=Box(tuple([0.0, 0.0] + list(-zb)), tuple([S_, S_] + list(zb))),
        name=f"random-dynamics-{n_passages}-n{n_states}-s{seed}",
        max_horizon=RANDOM_DYNAMICS_MAX_HORIZON,
    )


def _expm(M: np.ndarray) -> np.ndarray:
    """Matrix exponential: scaling and squaring with a degree-18 Taylor polynomial."""
    norm = float(np.abs(M).sum(axis=1).max())
    s = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0.5 else 0
    X = M / (2.0**s)
    E = np.eye(M.shape[0])
    term = np.eye(M.shape[0])
    for j in range(1, 19):
        term = term @ X / j
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def _discretise(Ac: np.ndarray, Bc: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact zero-order-hold discretisation: expm([[Ac, Bc], [0, 0]] dt) = [[A, B], [0, I]]."""
    n, m = Bc.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n] = Ac
    M[:n, n:] = Bc
    E = _expm(M * dt)
    return E[:n, :n], E[:n, n:]


def _controllable(A: np.ndarray, B: np.ndarray, tol: float = 1e-9) -> bool:
    """PBH test: rank [A - lambda I, B] = n at every eigenvalue lambda of A."""
    n = A.shape[0]
    scale = max(1.0, float(np.abs(A).max()), float(np.abs(B).max()))
    for lam in np.linalg.eigvals(A):
        sv = np.linalg.svd(np.hstack([A - lam * np.eye(n), B]), compute_uv=False)
        if sv[-1] <= tol * scale:
            return False
    return True

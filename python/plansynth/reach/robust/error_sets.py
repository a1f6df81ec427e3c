"""The error sets of the independent robust validator (:mod:`plansynth.reach.robust.check`,
whose docstring defines them): under ``u_t = v_t + K (x_t - x_nom_t)`` the error ranges
exactly over ``E_t = sum_{i<t} A_K^i W``; its support functions by iterating the
direction (every step exactly), the limit set's bounded above for a lasso, and the
position part of E_t as an exact convex polygon. Like the validator, it shares nothing
with the planner (neither the tube of :mod:`plansynth.reach.tube` nor the tightened
problem).
"""

from __future__ import annotations

import numpy as np

from plansynth.reach.problem import ReachProblem

__all__ = ["error_supports", "limit_polygon", "limit_supports", "tube_polygons"]

#: the limit set's sum stops when every term is below this (2-norm of the direction)
LIMIT_TERM = 1e-12
MAX_LIMIT_TERMS = 100_000


def _closed_loop(problem: ReachProblem, K: np.ndarray) -> np.ndarray:
    A, B = np.asarray(problem.dynamics.A, float), np.asarray(problem.dynamics.B, float)
    return A + B @ np.asarray(K, float)


def _support_W(problem: ReachProblem, C: np.ndarray) -> np.ndarray:
    """``h_W`` of the rows of C, from the problem's W (a box or vertices)."""
    w = problem.disturbance
    assert w is not None
    if w.box is not None:
        return np.abs(C) @ np.array(w.box, float)
    return np.max(C @ np.asarray(w.vertices, float).T, axis=1)


def error_supports(problem: ReachProblem, K: np.ndarray, directions: np.ndarray, steps: int) -> np.ndarray:
    """``h_{E_t}(c)`` for t = 0..steps (rows) and the rows c of ``directions``: the sum
    of ``h_W(c_i)`` with ``c_{i+1} = A_K^T c_i``, every term.

    >>> from dataclasses import replace
    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.disturbance import Disturbance
    >>> p = replace(maze(1), disturbance=Disturbance(box=(0.1, 0.1, 0.0, 0.0)))
    >>> error_supports(p, np.zeros((2, 4)), np.array([[1.0, 0, 0, 0]]), 3).ravel().tolist()  # K = 0: p' = p + dt v
    [0.0, 0.1, 0.2, 0.30000000000000004]
    """
    AK = _closed_loop(problem, K)
    C = np.atleast_2d(np.asarray(directions, float)).copy()
    out = np.zeros((steps + 1, len(C)))
    for i in range(steps):
        out[i + 1] = out[i] + _support_W(problem, C)
        C = C @ AK
    return out


def limit_supports(problem: ReachProblem, K: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """An upper bound of ``sup_t h_{E_t}(c)`` per row c: the sum until every term's
    direction is below :data:`LIMIT_TERM`, then ``r_W sum_{i>=I} |A_K^i|_2 |c|_2`` bounded
    by ``sum_{j<J} |A_K^{I+j}|_2 / (1 - |A_K^J|_2)`` for the first J with
    ``|A_K^J|_2 < 1``; inf when A_K is not stable."""
    AK = _closed_loop(problem, K)
    n = AK.shape[0]
    C = np.atleast_2d(np.asarray(directions, float)).copy()
    if n and float(np.max(np.abs(np.linalg.eigvals(AK)))) >= 1.0:
        return np.full(len(C), np.inf)
    total = np.zeros(len(C))
    P = np.eye(n)
    for _ in range(MAX_LIMIT_TERMS):
        total += _support_W(problem, C)
        C = C @ AK
        P = P @ AK
        if float(np.max(np.linalg.norm(C, axis=1), initial=0.0)) <= LIMIT_TERM * max(
            1.0, float(np.max(np.linalg.norm(directions, axis=1)))
        ):
            break
    else:
        return np.full(len(C), np.inf)
    w = problem.disturbance
    r_w = float(np.linalg.norm(w.box)) if w.box is not None else float(np.max(np.linalg.norm(w.vertices, axis=1)))
    Q, J, q = AK.copy(), 1, float(np.linalg.norm(AK, 2))
    while q >= 1.0 and J < MAX_LIMIT_TERMS:  # the first power of norm below 1
        Q, J = Q @ AK, J + 1
        q = float(np.linalg.norm(Q, 2))
    if q >= 1.0:
        return np.full(len(C), np.inf)
    rest, R = 0.0, P.copy()
    for _ in range(J):
        rest += float(np.linalg.norm(R, 2))
        R = R @ AK
    return total + r_w * rest / (1.0 - q) * np.linalg.norm(directions, axis=1) * (1 + 1e-9)


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2-D points, counter-clockwise (Andrew's monotone chain);
    fewer than 3 points when they are collinear or one."""
    pts = np.unique(np.round(points, 15), axis=0)
    if len(pts) <= 2:
        return pts

    def half(ps: np.ndarray) -> list[np.ndarray]:
        out: list[np.ndarray] = []
        for p in ps:
            while len(out) >= 2:
                a, b = out[-2], out[-1]
                if (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) <= 0:
                    out.pop()
                else:
                    break
            out.append(p)
        return out

    lower = half(pts)
    upper = half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _zonotope(G: np.ndarray) -> np.ndarray:
    """The vertices of the 2-D zonotope ``{G xi : |xi|_inf <= 1}`` (columns of G are its
    generators): the generators turned into the upper half-plane, parallel ones added
    up, sorted by angle and walked from the lowest corner."""
    G = G[:, np.any(G != 0.0, axis=0)]
    if G.shape[1] == 0:
        return np.zeros((1, 2))
    flip = (G[1] < 0) | ((G[1] == 0) & (G[0] < 0))
    G = np.where(flip, -G, G)
    angle = np.arctan2(G[1], G[0])
    order = np.argsort(angle, kind="stable")
    G, angle = G[:, order], angle[order]
    # parallel generators (equal angles, to round-off) are one longer generator
    group = np.concatenate([[0], np.cumsum(np.diff(angle) > 1e-13)])
    G = np.stack([np.bincount(group, weights=G[0]), np.bincount(group, weights=G[1])])
    start = -G.sum(axis=1)
    steps = np.concatenate([2 * G.T, -2 * G.T])
    return start + np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)[:-1]])


def tube_polygons(problem: ReachProblem, K: np.ndarray, steps: int) -> list[np.ndarray]:
    """The position parts of E_0..E_steps as vertex arrays (exact convex polygons,
    possibly a point or a segment).

    >>> from dataclasses import replace
    >>> from plansynth.reach.families import maze
    >>> from plansynth.reach.disturbance import Disturbance
    >>> p = replace(maze(1), disturbance=Disturbance(box=(0.1, 0.2, 0.0, 0.0)))
    >>> [sorted(map(tuple, v.round(6).tolist())) for v in tube_polygons(p, np.zeros((2, 4)), 1)]
    [[(0.0, 0.0)], [(-0.1, -0.2), (-0.1, 0.2), (0.1, -0.2), (0.1, 0.2)]]
    """
    AK = _closed_loop(problem, K)
    pos = list(problem.dynamics.position)
    w = problem.disturbance
    assert w is not None
    out = [np.zeros((1, 2))]
    M = np.eye(AK.shape[0])  # A_K^i
    if w.box is not None:
        gens = []
        for _ in range(steps):
            gens.append(M[pos] * np.array(w.box, float)[None, :])
            out.append(_zonotope(np.hstack(gens)))
            M = AK @ M
        return out
    V = np.asarray(w.vertices, float)
    current = np.zeros((1, 2))
    for _ in range(steps):
        term = _hull((M[pos] @ V.T).T)
        current = _hull((current[:, None, :] + term[None, :, :]).reshape(-1, 2))
        out.append(current)
        M = AK @ M
    return out


def limit_polygon(problem: ReachProblem, K: np.ndarray) -> np.ndarray:
    """The box of the limit supports along the workspace axes: it contains the
    positions of every E_t (inf corners when the closed loop is not stable)."""
    n = problem.dynamics.n_states
    pos = list(problem.dynamics.position)
    D = np.zeros((4, n))
    D[0, pos[0]], D[1, pos[0]], D[2, pos[1]], D[3, pos[1]] = 1.0, -1.0, 1.0, -1.0
    s = limit_supports(problem, K, D)
    if not np.all(np.isfinite(s)):
        return np.array([[np.inf, np.inf]])
    return np.array([[-s[1], -s[3]], [s[0], -s[3]], [s[0], s[2]], [-s[1], s[2]]])

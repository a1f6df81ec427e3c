"""Pieces the reach property tests share: their random workspaces, and the independent
oracle LP's last step (sparse rows into HiGHS), written apart from the package's own LP
assembly (plansynth.reach.highs) so that the oracle does not share what it checks."""

from __future__ import annotations

import highspy
import numpy as np
from hypothesis import strategies as st

from plansynth.reach.families import random_workspace
from plansynth.reach.problem import ReachProblem

#: One row: {column: coefficient}, lower bound, upper bound.
Row = tuple[dict[int, float], float, float]


@st.composite
def problems(draw, max_obstacles: int = 5) -> ReachProblem:
    """Small random workspaces: 2-D or 3-D, single or double integrators."""
    seed = draw(st.integers(0, 10**6))
    dim = draw(st.sampled_from([2, 2, 2, 3]))
    order = draw(st.sampled_from([1, 2]))
    n_obstacles = draw(st.integers(1, max_obstacles))
    try:
        return random_workspace(seed, n_obstacles, dim=dim, order=order, dt=1.0 if order == 1 else 0.5)
    except RuntimeError:  # no free point for start or goal: a different seed next time
        return random_workspace(seed % 97, 2, dim=dim, order=order)


@st.composite
def disturbed(draw, max_obstacles: int = 4, scales: tuple[float, float] = (0.002, 0.05)) -> ReachProblem:
    """A random 2-D room (single or double integrator) under a random disturbance
    (``robot.disturbance``) of size within ``scales``: a box (some half-widths zero) or
    a polytope around 0."""
    from dataclasses import replace

    from plansynth.reach.disturbance import Disturbance

    seed = draw(st.integers(0, 10**6))
    order = draw(st.sampled_from([1, 2]))
    dt = 1.0 if order == 1 else 0.5
    try:
        p = random_workspace(seed, draw(st.integers(1, max_obstacles)), order=order, dt=dt)
    except RuntimeError:
        p = random_workspace(seed % 97, 2, order=order, dt=dt)
    n = p.dynamics.n_states
    scale = draw(st.floats(*scales))
    if draw(st.booleans()):
        w = Disturbance(box=tuple(scale * draw(st.sampled_from([0.0, 0.5, 1.0])) for _ in range(n)))
    else:
        rng = np.random.default_rng(seed)
        V = rng.normal(size=(draw(st.integers(2, 5)), n))
        V = np.vstack([V, -V.sum(axis=0, keepdims=True)])  # the vertices add up to 0: 0 is inside
        w = Disturbance(vertices=scale * V / np.abs(V).max())
    return replace(p, disturbance=w)


def tube_margins(problem: ReachProblem, directions: np.ndarray, steps: int) -> np.ndarray:
    """``h_{E_t}(c)`` for t = 0..steps and the rows c of ``directions``, for the tube a
    tightened problem carries (``problem.tube``), summed term by term here from its
    closed loop and its W: the oracle's own, not the planner's."""
    tube = problem.tube
    A_K, w = np.asarray(tube.A_K, float), tube.W
    out = np.zeros((steps + 1, len(directions)))
    C = np.asarray(directions, float).copy()
    for t in range(steps):
        term = np.abs(C) @ np.asarray(w.box) if w.box is not None else np.max(C @ np.asarray(w.vertices).T, axis=1)
        out[t + 1] = out[t] + term
        C = C @ A_K
    return out


def add_rows(h: highspy.Highs, rows: list[Row]) -> None:
    """Add sparse ``rows`` (coefficients by column, lower, upper) to ``h`` in one call."""
    starts, index, value = [], [], []
    for coef, _, _ in rows:
        starts.append(len(index))
        index.extend(coef)
        value.extend(coef.values())
    h.addRows(
        len(rows),
        np.array([r[1] for r in rows]),
        np.array([r[2] for r in rows]),
        len(index),
        np.array(starts, dtype=np.int32),
        np.array(index, dtype=np.int32),
        np.array(value, dtype=float),
    )


def feasible(h: highspy.Highs, rows: list[Row]) -> bool:
    """Add ``rows`` to ``h`` (its columns already added), solve, and say whether the LP
    is feasible (an optimum exists: the objective is zero)."""
    add_rows(h, rows)
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kOptimal


# ------------------------------------------------------------------------------------
# The independent exact oracle: a big-M MILP over the spec's
# semantics (shared/spec/reach-problem.md), written from the problem's data only (its
# obstacles, dynamics, bounds and goal), sharing nothing with the planners (no
# decomposition, no region, no plansynth LP code).


def _faces(shape) -> list[tuple[np.ndarray, float]]:
    """The faces of a convex obstacle as (n, c): its interior is {p : n.p < c for every
    face}, so p is outside the interior iff n.p >= c for some face (Box or convex
    polygon; a non-convex polygon is refused: the oracle is for convex obstacles)."""
    from plansynth.reach.geometry import Box

    if isinstance(shape, Box):
        lo, hi = np.asarray(shape.lo, float), np.asarray(shape.hi, float)
        out = []
        for a in range(len(lo)):
            e = np.zeros(len(lo))
            e[a] = 1.0
            out += [(e, float(hi[a])), (-e, float(-lo[a]))]
        return out
    v = np.asarray(shape.vertices, float)
    area = 0.5 * sum(v[i, 0] * v[(i + 1) % len(v), 1] - v[(i + 1) % len(v), 0] * v[i, 1] for i in range(len(v)))
    if area < 0:
        v = v[::-1]
    out = []
    for i in range(len(v)):
        a, b = v[i], v[(i + 1) % len(v)]
        n = np.array([b[1] - a[1], a[0] - b[0]])  # outward for a CCW polygon
        norm = float(np.hypot(*n))
        if norm == 0.0:
            continue
        n = n / norm
        c = float(n @ a)
        if any(n @ w > c + 1e-9 for w in v):
            raise ValueError("the oracle takes convex obstacles only")
        out.append((n, c))
    return out


def oracle_feasible(
    problem: ReachProblem, horizon: int, *, segments: bool, seconds: float = 60.0, witness: list | None = None
) -> bool | None:
    """Is there a trajectory of exactly ``horizon`` steps (the spec's Definition 2.3)?
    A big-M MILP solved by HiGHS: True, False, or None (HiGHS's time limit).

    Columns x_0..x_N, u_0..u_{N-1} (N = ``horizon``) and binaries. Rows: x_0 = start,
    x_{t+1} = A x_t + B u_t, |u_t|_inf <= input_bound, state bounds, positions in the
    workspace, the final position in the goal (a box or convex polygon), and for every
    convex obstacle and every sample a choice of face whose closed outer half-space
    holds the sample: ``n.p_t >= c - M (1 - z)``, ``sum z >= 1`` (M: the largest
    violation over the workspace box). This is *exact* for samples (``segments=False``):
    a point is outside the interior of a convex obstacle iff some face's half-space
    holds it.

    Zero-width slits are not free: a face flush with (or beyond) the workspace's
    boundary offers no room (a position on it, between the obstacle and the boundary,
    is outside the obstacle's interior as the spec words it, but has no free
    neighbourhood: maze-1's wall ends at x = 0, and "passing" it along x = 0 would save
    a step). Seams between two touching obstacles are not caught here (a test world
    lets its obstacles overlap instead).

    ``segments=True``: both end points of every segment outside the *same* face of
    each convex obstacle (one binary choice per segment, obstacle and face). This is
    *sufficient* for the segment to miss the obstacle's interior (a half-space is
    convex) but not necessary: a segment that cuts diagonally past a corner, its end
    points beyond two different faces, misses the obstacle too. The planner's
    segment-safe semantics (consecutive samples in one convex region of its
    decomposition) is stricter than this one in a world of axis-aligned boxes (a free
    box and an obstacle box are separated by a face of the obstacle) and is neither
    stricter nor looser in general; neither is the exact segment semantics. So: a
    segment-safe plan that the planner proves impossible for the problem is impossible
    here too, and in a box world a planner's segment-safe plan is a solution here.
    """
    from plansynth.reach.geometry import Box

    rs = getattr(problem, "robot_shape", None)
    if rs is not None and not rs.is_point:
        raise ValueError("the oracle takes point robots only")
    dyn = problem.dynamics
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    n, m, pos = A.shape[0], B.shape[1], list(dyn.position)
    N = int(horizon)
    ws_lo, ws_hi = np.asarray(problem.workspace.lo, float), np.asarray(problem.workspace.hi, float)
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    if problem.state_bounds is not None:
        lo, hi = np.asarray(problem.state_bounds.lo, float).copy(), np.asarray(problem.state_bounds.hi, float).copy()
    lo[pos], hi[pos] = np.maximum(lo[pos], ws_lo), np.minimum(hi[pos], ws_hi)
    x = lambda t, i: t * n + i  # noqa: E731
    u = lambda t, j: (N + 1) * n + t * m + j  # noqa: E731
    n_cont = (N + 1) * n + N * m
    col_lo = np.concatenate([np.tile(lo, N + 1), np.full(N * m, -problem.input_bound)])
    col_hi = np.concatenate([np.tile(hi, N + 1), np.full(N * m, problem.input_bound)])
    col_lo[:n] = col_hi[:n] = np.asarray(problem.start, float)
    rows: list[Row] = []
    for t in range(N):
        for i in range(n):
            coef = {x(t + 1, i): 1.0}
            for k in range(n):
                if A[i, k] != 0.0:
                    coef[x(t, k)] = coef.get(x(t, k), 0.0) - A[i, k]
            for j in range(m):
                if B[i, j] != 0.0:
                    coef[u(t, j)] = -B[i, j]
            rows.append((coef, 0.0, 0.0))
    goal = problem.goal
    if isinstance(goal, Box):
        for a, i in enumerate(pos):
            rows.append(({x(N, i): 1.0}, float(goal.lo[a]), float(goal.hi[a])))
    else:
        for nrm, c in _faces(goal):  # inside a convex goal: n.p <= c for every face
            rows.append(({x(N, pos[a]): float(nrm[a]) for a in range(len(pos)) if nrm[a] != 0.0}, -np.inf, c))
    n_bin = 0
    groups = [(t, t + 1) for t in range(N)] if segments else [(t,) for t in range(N + 1)]
    if segments and N == 0:
        groups = [(0,)]
    for shape in problem.obstacles:
        faces = _faces(shape)
        for times in groups:
            zs = []
            for nrm, c in faces:
                M = c - float(np.sum(np.minimum(nrm * ws_lo, nrm * ws_hi)))  # c - min over the workspace of n.p
                if M <= 0:  # the workspace lies beyond this face: always outside
                    zs = None
                    break
                if c >= float(np.sum(np.maximum(nrm * ws_lo, nrm * ws_hi))) - 1e-12:
                    continue  # beyond this face lies at most the workspace's boundary: a slit
                z = n_cont + n_bin
                n_bin += 1
                zs.append(z)
                for t in times:  # n.p_t - M z >= c - M
                    coef = {x(t, pos[a]): float(nrm[a]) for a in range(len(pos)) if nrm[a] != 0.0}
                    coef[z] = -M
                    rows.append((coef, c - M, np.inf))
            if zs is not None:
                rows.append(({z: 1.0 for z in zs}, 1.0, np.inf))
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("time_limit", float(seconds))
    h.setOptionValue("threads", 1)
    total = n_cont + n_bin
    h.addVars(total, np.concatenate([col_lo, np.zeros(n_bin)]), np.concatenate([col_hi, np.ones(n_bin)]))
    if n_bin:
        h.changeColsIntegrality(
            n_bin, np.arange(n_cont, total, dtype=np.int32), np.full(n_bin, highspy.HighsVarType.kInteger)
        )
    add_rows(h, rows)
    h.run()
    status = h.getModelStatus()
    if status == highspy.HighsModelStatus.kOptimal:
        if witness is not None:  # the states x_0..x_N, for a look at the solution
            col = np.asarray(h.getSolution().col_value)
            witness.append(col[: (N + 1) * n].reshape(N + 1, n))
        return True
    if status in (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnboundedOrInfeasible):
        return False
    return None


def oracle_minimum(problem: ReachProblem, top: int, *, segments: bool, seconds: float = 60.0) -> int | None:
    """The smallest horizon <= ``top`` with a trajectory per :func:`oracle_feasible`
    (None: none up to ``top``). Raises RuntimeError when HiGHS times out."""
    for N in range(top + 1):
        ok = oracle_feasible(problem, N, segments=segments, seconds=seconds)
        if ok is None:
            raise RuntimeError(f"the oracle MILP timed out at horizon {N}")
        if ok:
            return N
    return None

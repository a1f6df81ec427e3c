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
    points beyond two different faces, misses the obstacle too (the *face oracle*;
    :func:`oracle_exact` decides the spec's segment semantics). So a segment-safe
    horizon refuted for the problem is refuted here too, and a solution here is a
    segment-safe trajectory.
    """
    N = int(horizon)
    # groups of points that must lie beyond one common face of each obstacle
    if segments and N > 0:
        points = [((t, 0.0), (t + 1, 0.0)) for t in range(N)]
    else:
        points = [((t, 0.0),) for t in range(N + 1)]
    col = _milp(problem, N, points, seconds)
    if col is None or isinstance(col, str):
        return None if col == "timeout" else False
    if witness is not None:  # the states x_0..x_N, for a look at the solution
        witness.append(_states(problem, N, col))
    return True


#: Points per segment the exact oracle keeps free from the start (then more where a
#: segment of a solution still meets an obstacle's interior).
EXACT_START_POINTS = 3
#: Depth below which a segment's incursion into an obstacle counts as touching: the
#: validator's default tolerance, a tenth of it.
EXACT_TOL = 1e-7
EXACT_ROUNDS = 40


def oracle_exact(
    problem: ReachProblem,
    horizon: int,
    *,
    seconds: float = 60.0,
    witness: list | None = None,
    start: bool = True,
    goal: bool = True,
    claims: tuple = (),
) -> bool | None:
    """Is there a *segment-safe* trajectory of exactly ``horizon`` steps (the spec: every
    segment between consecutive positions avoids every obstacle's interior)? Exact up
    to :data:`EXACT_TOL`, by refinement of a necessary condition:

    * the MILP of :func:`oracle_feasible` with, per segment, the samples and points at
      fixed fractions of the segment each outside every convex obstacle's interior (a
      point p_t + s (p_{t+1} - p_t) is linear in the states): every segment-safe
      trajectory is a solution, so an infeasible MILP is a proof (False);
    * a solution is checked exactly: for each segment and convex obstacle the deepest
      point of the segment inside the obstacle (the largest, over s in [0, 1], of the
      least face slack, a concave piecewise-linear function of s: its breakpoints
      decide it); when every segment's depth is at most :data:`EXACT_TOL` the solution
      is segment-safe (True);
    * otherwise each offending segment gets its deepest point as one more point kept
      free, and the MILP is solved again (at most :data:`EXACT_ROUNDS` rounds; then
      None, as on HiGHS's time limit).

    The face MILP (``oracle_feasible(segments=True)``, sufficient) is asked first: its
    solutions are segment-safe. Faces flush with the workspace's boundary give no room
    here either (see :func:`oracle_feasible`): the depth of a point counts only the
    other faces.

    ``start``/``goal`` False: x_0 free / no goal at x_N; ``claims``: more rows, (t, s,
    H, h) meaning ``H (p_t + s (p_{t+1} - p_t)) <= h`` (a clause's literals, to check
    that no segment-safe trajectory realises them)."""
    import time

    deadline = time.perf_counter() + seconds
    N = int(horizon)
    kw = dict(start=start, goal=goal, claims=claims)
    col = _milp(problem, N, [((t, 0.0), (t + 1, 0.0)) for t in range(N)] or [((0, 0.0),)], seconds, **kw)
    if col is not None and not isinstance(col, str):  # the face MILP: a segment-safe solution
        if witness is not None:
            witness.append(_states(problem, N, col))
        return True
    if N == 0:
        return None if isinstance(col, str) else False
    fractions = [[j / (EXACT_START_POINTS + 1) for j in range(1, EXACT_START_POINTS + 1)] for _ in range(N)]
    shapes = [_interior_faces(problem, o) for o in problem.obstacles]
    for _ in range(EXACT_ROUNDS):
        points = [((t, 0.0),) for t in range(N + 1)]
        points += [((t, s),) for t in range(N) for s in fractions[t]]
        left = deadline - time.perf_counter()
        if left <= 0:
            return None
        col = _milp(problem, N, points, left, **kw)
        if col is None:
            return False
        if isinstance(col, str):
            return None
        X = _states(problem, N, col)
        P = X[:, list(problem.dynamics.position)]
        deep = False
        for t in range(N):
            worst, at = 0.0, None
            for faces in shapes:
                d, s = segment_depth(P[t], P[t + 1], faces)
                if d > worst:
                    worst, at = d, s
            if worst > EXACT_TOL:
                deep = True
                fractions[t].append(at)
        if not deep:
            if witness is not None:
                witness.append(X)
            return True
        # sufficient: each piece between consecutive points of a segment beyond one face
        left = deadline - time.perf_counter()
        if left <= 0:
            return None
        pieces = []
        for t in range(N):
            cuts = [0.0, *sorted(fractions[t]), 1.0]
            pieces += [((t, a), (t, b)) for a, b in zip(cuts, cuts[1:])]
        col = _milp(problem, N, pieces, left, **kw)
        if col is not None and not isinstance(col, str):
            if witness is not None:
                witness.append(_states(problem, N, col))
            return True
    return None


def segment_depth(p: np.ndarray, q: np.ndarray, faces: list[tuple[np.ndarray, float]]) -> tuple[float, float]:
    """How deep the segment [p, q] goes into the convex set {x : n.x < c for every face}
    (``faces``: (n, c) pairs with unit normals): the largest over s in [0, 1] of
    min_f (c_f - n_f.(p + s (q - p))), and the s where it is reached; depth <= 0 when the
    segment avoids the interior. Exact: the function is concave and piecewise linear,
    so its maximum is at s = 0, s = 1 or where two faces' slacks cross.

    >>> sq = [(np.array([1.0, 0]), 1.0), (np.array([-1.0, 0]), 0.0), (np.array([0, 1.0]), 1.0), (np.array([0, -1.0]), 0.0)]
    >>> segment_depth(np.array([-1.0, 0.5]), np.array([2.0, 0.5]), sq)
    (0.5, 0.5)
    >>> segment_depth(np.array([-0.5, 0.7]), np.array([0.4, 1.6]), sq)[0] <= 0   # past the corner (0, 1)
    True
    """
    if not faces:
        return -np.inf, 0.0
    d = q - p
    a = np.array([c - n @ p for n, c in faces])  # slack at s = 0
    b = np.array([-(n @ d) for n, _ in faces])  # its slope in s
    cands = [0.0, 1.0]
    for i in range(len(faces)):
        for j in range(i + 1, len(faces)):
            if b[i] != b[j]:
                s = (a[j] - a[i]) / (b[i] - b[j])
                if 0.0 < s < 1.0:
                    cands.append(float(s))
    best, at = -np.inf, 0.0
    for s in cands:
        v = float(np.min(a + b * s))
        if v > best:
            best, at = v, s
    return best, at


def _interior_faces(problem: ReachProblem, shape) -> list[tuple[np.ndarray, float]]:
    """The faces of a convex obstacle that leave room beyond them inside the workspace
    (a face flush with or beyond the workspace's boundary leaves a zero-width slit at
    most: see :func:`oracle_feasible`)."""
    ws_lo, ws_hi = np.asarray(problem.workspace.lo, float), np.asarray(problem.workspace.hi, float)
    return [(n, c) for n, c in _faces(shape) if c < float(np.sum(np.maximum(n * ws_lo, n * ws_hi))) - 1e-12]


def _states(problem: ReachProblem, N: int, col: np.ndarray) -> np.ndarray:
    n = problem.dynamics.n_states
    return np.asarray(col[: (N + 1) * n]).reshape(N + 1, n)


def _milp(
    problem: ReachProblem,
    N: int,
    groups: list[tuple[tuple[int, float], ...]],
    seconds: float,
    *,
    start: bool = True,
    goal: bool = True,
    claims: tuple = (),
):
    """The oracle MILP of horizon N: the trajectory's rows and, for every group of points
    (t, s), meaning p_t + s (p_{t+1} - p_t), and every convex obstacle, one face whose
    closed outer half-space holds every point of the group. The solution's columns, None
    (infeasible) or "timeout". ``start``/``goal``/``claims``: see :func:`oracle_exact`."""
    from plansynth.reach.geometry import Box

    rs = getattr(problem, "robot_shape", None)
    if rs is not None and not rs.is_point:
        raise ValueError("the oracle takes point robots only")
    dyn = problem.dynamics
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    n, m, pos = A.shape[0], B.shape[1], list(dyn.position)
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
    if start:
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
    target = problem.goal
    if not goal:
        pass
    elif isinstance(target, Box):
        for a, i in enumerate(pos):
            rows.append(({x(N, i): 1.0}, float(target.lo[a]), float(target.hi[a])))
    else:
        for nrm, c in _faces(target):  # inside a convex goal: n.p <= c for every face
            rows.append(({x(N, pos[a]): float(nrm[a]) for a in range(len(pos)) if nrm[a] != 0.0}, -np.inf, c))

    def point(t: int, s: float, nrm: np.ndarray) -> dict[int, float]:
        """n . (p_t + s (p_{t+1} - p_t)) as coefficients."""
        coef: dict[int, float] = {}
        for a in range(len(pos)):
            if nrm[a] == 0.0:
                continue
            if s < 1.0:
                coef[x(t, pos[a])] = (1.0 - s) * float(nrm[a])
            if s > 0.0:
                coef[x(t + 1, pos[a])] = coef.get(x(t + 1, pos[a]), 0.0) + s * float(nrm[a])
        return coef

    for t, s, H, h in claims:  # H p(t, s) <= h
        for row, b in zip(np.atleast_2d(H), np.atleast_1d(h)):
            rows.append((point(t, s, np.asarray(row, float)), -np.inf, float(b)))
    n_bin = 0
    for shape in problem.obstacles:
        faces = _faces(shape)
        for group in groups:
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
                for t, s in group:  # n.p - M z >= c - M
                    coef = point(t, s, nrm)
                    coef[z] = -M
                    rows.append((coef, c - M, np.inf))
            if zs is not None:
                rows.append(({z: 1.0 for z in zs}, 1.0, np.inf))
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("time_limit", float(max(seconds, 1e-3)))
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
        return np.asarray(h.getSolution().col_value)
    if status in (highspy.HighsModelStatus.kInfeasible, highspy.HighsModelStatus.kUnboundedOrInfeasible):
        return None
    return "timeout"


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

"""Benchmark families and the example problems (paper, Section VI; project spec
"Benchmark families from the papers").

* :func:`maze` -- the n-passage maze of Section VI (Table I) with the double integrator,
  or with an integrator chain of any order (the scalability study, Figure 4).
* :func:`cluttered` -- non-convex polygon obstacles (an example beyond the paper).
* :func:`dubins_example` -- Section VI-A: a unicycle through its feedback-linearised
  form, a double integrator on (x, y) (see :mod:`plansynth.reach.dubins`).
* :func:`random_workspace` -- small random workspaces for property tests.
* :func:`random_dynamics` -- the mazes with seeded random controllable (A, B) pairs of
  n states (the paper's Figure 4 setting: random A and B at n = 50).
* :func:`gcs_maze` -- the n x n mazes of the GCS paper (Marcucci et al., Science
  Robotics 2023), generated as its code does.

``python -m plansynth.reach.families DIR`` (re)writes the example files of
``examples/reach``.

>>> p = maze(2)
>>> len(p.obstacles), p.goal, p.start.tolist()
(4, Box(lo=(27.0, 27.0), hi=(29.0, 29.0)), [1.0, 1.0, 0.0, 0.0])
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

import numpy as np
import shapely
import yaml

from plansynth.io import write_output
from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.fileformat import reach_problem_to_dict
from plansynth.reach.geometry import Box, Polygon, Shape, shape_to_shapely
from plansynth.reach.problem import ReachProblem

__all__ = [
    "maze",
    "gcs_maze",
    "cluttered",
    "dubins_example",
    "random_workspace",
    "random_dynamics",
    "examples",
    "write_examples",
]

MAZE_SIZE = 30.0
WALL_THICKNESS = 1.0
RIGHT_GAP = (27.0, 29.0)
LEFT_GAP = (1.0, 3.0)
DERIVATIVE_BOUND = 2.0
#: ``max_horizon`` of every :func:`random_dynamics` instance (its docstring says why)
RANDOM_DYNAMICS_MAX_HORIZON = 400


def maze(n_passages: int, order: int = 2, *, dt: float = 0.5, input_bound: float = 1.0) -> ReachProblem:
    """The maze with ``n_passages`` walls (Section VI, Table I).

    Workspace [0,30]^2; wall i (1 m thick) centred at y = 30 i / (n+1), spanning the
    width except a 2 m gap, alternately at x in [27, 29] (first) and [1, 3]. Start
    (1, 1) at rest; goal the 2 x 2 box at y in [27, 29] at the end opposite the last
    gap. Robot: ``order`` integrators per axis (2: the paper's double integrator),
    dt = 0.5, |u| <= 1, every derivative bounded by 2, position by the workspace.

    >>> maze(1).obstacles
    (Box(lo=(0.0, 14.5), hi=(27.0, 15.5)), Box(lo=(29.0, 14.5), hi=(30.0, 15.5)))
    >>> maze(3, order=4).dynamics.n_states
    8
    """
    if n_passages < 0:
        raise ValueError(f"n_passages must be >= 0, got {n_passages}")
    if order < 1:
        raise ValueError(f"order must be >= 1, got {order}")
    S = MAZE_SIZE
    walls: list[Shape] = []
    for i in range(1, n_passages + 1):
        y = S * i / (n_passages + 1)
        y0, y1 = y - WALL_THICKNESS / 2, y + WALL_THICKNESS / 2
        g0, g1 = RIGHT_GAP if i % 2 == 1 else LEFT_GAP
        walls.append(Box((0.0, y0), (g0, y1)))
        walls.append(Box((g1, y0), (S, y1)))
    last_gap_right = n_passages % 2 == 1
    gx = LEFT_GAP if (last_gap_right or n_passages == 0) else RIGHT_GAP
    goal = Box((gx[0], 27.0), (gx[1], 29.0))
    dyn = integrator_chain(order, 2, dt)
    start = np.zeros(dyn.n_states)
    start[:2] = (1.0, 1.0)
    lo = [0.0, 0.0] + [-DERIVATIVE_BOUND] * (2 * (order - 1))
    hi = [S, S] + [DERIVATIVE_BOUND] * (2 * (order - 1))
    name = f"maze-{n_passages}" if order == 2 else f"chain{order}-maze-{n_passages}"
    return ReachProblem(
        workspace=Box((0.0, 0.0), (S, S)),
        obstacles=tuple(walls),
        goal=goal,
        dynamics=dyn,
        start=start,
        input_bound=input_bound,
        state_bounds=Box(tuple(lo), tuple(hi)),
        name=name,
    )


GCS_MAZE_WALL = 0.1
# the knock-downs of the GCS paper's notebook after make_maze, by maze size (only its
# 50 x 50 maze is in the paper; the smaller ones keep the plain perfect maze)
GCS_MAZE_KNOCK_DOWNS = {50: 100}


def gcs_maze(n: int, *, seed: int = 4, knock_downs: int | None = None) -> ReachProblem:
    """The ``n`` x ``n`` maze of the GCS paper (Marcucci, Petersen, von Wrangel, Tedrake,
    "Motion planning around obstacles with convex optimization", Science Robotics 2023,
    Section "Maze"), generated as in github.com/RobotLocomotion/gcs-science-robotics,
    ``models/maze.py`` and ``reproduction/maze_example.ipynb``: Python's
    ``random.seed(seed)`` (4 there), the recursive-backtracker ``Maze(n, n).make_maze()``
    from cell (0, 0) (neighbours tried in the order W, E, S, N, one taken by
    ``random.choice``), then ``knock_downs`` extra walls knocked down, each at
    ``cell_at(randint(1, n - 2), randint(1, n - 2))`` with ``choice`` among its standing
    walls (100 at n = 50, the notebook's maze; none by default at other sizes).

    The walls are those ``Maze.plot`` draws: every cell's south wall except at cell
    (0, 0) (the entrance), every west wall, the north border from x = 0 to n - 1 (the
    exit above cell (n-1, n-1)) and the east border, each a box 0.1 thick around its
    line (neighbouring walls overlap at corners; the border ones reach 0.05 past the
    workspace [0, n]^2, which closes the entrance and exit). Obstacles are sorted.
    Robot: the spec's double integrator (dt = 0.5 s, |u| <= 1 per axis), |v| <= 1 per
    axis (the notebook's velocity limits), position within the workspace; from the
    centre of cell (0, 0) at rest to the goal box of side 0.4 at the centre of cell
    (n-1, n-1) (the notebook's start and goal are the entrance and exit points on the
    border; ours stay inside); ``max_horizon`` 200 up to n = 10 (the claims file's), 40 n
    steps beyond (20 s per cell of the side). For n = 10 this is ``examples/reach/claims/gcs-maze-10.yaml``.

    >>> p = gcs_maze(10)
    >>> len(p.obstacles), p.goal, p.start.tolist()
    (102, Box(lo=(9.3, 9.3), hi=(9.7, 9.7)), [0.5, 0.5, 0.0, 0.0])
    """
    if n < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    knock = GCS_MAZE_KNOCK_DOWNS.get(n, 0) if knock_downs is None else knock_downs
    if knock and n < 3:
        raise ValueError("knock-downs need n >= 3 (they pick interior cells)")
    rnd = random.Random(seed)
    walls = {(x, y): {"N": True, "S": True, "E": True, "W": True} for x in range(n) for y in range(n)}
    step = {"N": (0, 1), "S": (0, -1), "E": (1, 0), "W": (-1, 0)}
    opposite = {"N": "S", "S": "N", "E": "W", "W": "E"}

    def knock_down(cell: tuple[int, int], wall: str) -> None:
        walls[cell][wall] = False
        walls[(cell[0] + step[wall][0], cell[1] + step[wall][1])][opposite[wall]] = False

    stack: list[tuple[int, int]] = []
    cur, visited = (0, 0), 1
    while visited < n * n:
        options = []
        for d in ("W", "E", "S", "N"):
            nxt = (cur[0] + step[d][0], cur[1] + step[d][1])
            if 0 <= nxt[0] < n and 0 <= nxt[1] < n and all(walls[nxt].values()):
                options.append((d, nxt))
        if not options:
            cur = stack.pop()
            continue
        d, nxt = rnd.choice(options)
        knock_down(cur, d)
        stack.append(cur)
        cur, visited = nxt, visited + 1
    while knock > 0:
        cell = (rnd.randint(1, n - 2), rnd.randint(1, n - 2))
        standing = [w for w, up in walls[cell].items() if up]
        if standing:
            knock_down(cell, rnd.choice(standing))
            knock -= 1
    h = GCS_MAZE_WALL / 2
    segs: list[tuple[tuple[float, float], tuple[float, float]]] = []
    for x in range(n):
        for y in range(n):
            if walls[(x, y)]["S"] and (x, y) != (0, 0):
                segs.append(((x - h, y - h), (x + 1 + h, y + h)))
            if walls[(x, y)]["W"]:
                segs.append(((x - h, y - h), (x + h, y + 1 + h)))
    segs.append(((-h, n - h), (n - 1 + h, n + h)))
    segs.append(((n - h, -h), (n + h, n + h)))
    obstacles = tuple(
        Box(tuple(round(v, 9) for v in lo), tuple(round(v, 9) for v in hi))
        for lo, hi in sorted((tuple(round(v, 9) for v in lo), tuple(round(v, 9) for v in hi)) for lo, hi in segs)
    )
    dyn = integrator_chain(2, 2, 0.5)
    c = n - 0.5
    return ReachProblem(
        workspace=Box((0.0, 0.0), (float(n), float(n))),
        obstacles=obstacles,
        goal=Box((round(c - 0.2, 9), round(c - 0.2, 9)), (round(c + 0.2, 9), round(c + 0.2, 9))),
        dynamics=dyn,
        start=np.array([0.5, 0.5, 0.0, 0.0]),
        input_bound=1.0,
        state_bounds=Box((0.0, 0.0, -1.0, -1.0), (float(n), float(n), 1.0, 1.0)),
        name=f"gcs-maze-{n}",
        max_horizon=200 if n <= 10 else 40 * n,
    )


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
    from plansynth.reach.dynamics import LinearDynamics

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


def cluttered() -> ReachProblem:
    """A 20 x 20 m room with several non-convex polygon obstacles (an L, a U, a
    star, a zig-zag wall, a triangle) and the paper's double integrator.

    >>> p = cluttered()
    >>> sum(isinstance(o, Polygon) for o in p.obstacles)
    5
    """
    L = Polygon(((3, 3), (8, 3), (8, 5), (5, 5), (5, 9), (3, 9)))
    U = Polygon(((11, 2), (17, 2), (17, 8), (15, 8), (15, 4), (13, 4), (13, 8), (11, 8)))
    star = Polygon(
        tuple(
            (
                round(6 + (2.6 if k % 2 == 0 else 1.1) * math.cos(math.pi / 2 + k * math.pi / 5), 3),
                round(14 + (2.6 if k % 2 == 0 else 1.1) * math.sin(math.pi / 2 + k * math.pi / 5), 3),
            )
            for k in range(10)
        )
    )
    zigzag = Polygon(((9, 10), (12, 13), (14, 11), (17, 14), (17, 15.5), (14, 12.5), (12, 14.5), (9, 11.5)))
    tri = Polygon(((12, 17), (15, 19), (10, 19.5)))
    dyn = integrator_chain(2, 2, 0.5)
    return ReachProblem(
        workspace=Box((0.0, 0.0), (20.0, 20.0)),
        obstacles=(L, U, star, zigzag, tri),
        goal=Box((17.0, 17.0), (19.0, 19.0)),
        dynamics=dyn,
        start=np.array([1.0, 1.0, 0.0, 0.0]),
        input_bound=1.0,
        state_bounds=Box((0.0, 0.0, -2.0, -2.0), (20.0, 20.0, 2.0, 2.0)),
        name="cluttered",
    )


def dubins_example() -> ReachProblem:
    """Section VI-A: a Dubins-like car (unicycle with speed as a state) planned through
    its feedback-linearised form, a double integrator on (x, y).

    The car starts moving east at 1 m/s (speed 0 is where the linearisation is
    singular, see :mod:`plansynth.reach.dubins`) and must reach the far corner of a
    15 x 15 m yard with two offset walls.

    >>> dubins_example().start.tolist()
    [1.0, 2.0, 1.0, 0.0]
    """
    dyn = integrator_chain(2, 2, 0.5)
    return ReachProblem(
        workspace=Box((0.0, 0.0), (15.0, 15.0)),
        obstacles=(Box((0.0, 5.0), (10.0, 6.0)), Box((5.0, 9.5), (15.0, 10.5)), Polygon(((11, 1), (13, 1), (12, 3)))),
        goal=Box((1.0, 12.0), (3.0, 14.0)),
        dynamics=dyn,
        start=np.array([1.0, 2.0, 1.0, 0.0]),
        input_bound=1.0,
        state_bounds=Box((0.0, 0.0, -2.0, -2.0), (15.0, 15.0, 2.0, 2.0)),
        name="dubins",
    )


def random_workspace(
    seed: int,
    n_obstacles: int = 5,
    *,
    dim: int = 2,
    size: float = 10.0,
    polygons: bool = True,
    order: int = 1,
    dt: float = 1.0,
    input_bound: float = 1.0,
) -> ReachProblem:
    """A small random problem: ``n_obstacles`` random boxes (and, in 2-D with
    ``polygons``, random star-shaped non-convex polygons) in ``[0, size]^dim``; start
    and goal drawn in free space (the goal is a small box around a free point).

    Deterministic in ``seed``.

    >>> p = random_workspace(3, 4)
    >>> len(p.obstacles), p.dim
    (4, 2)
    """
    if dim not in (2, 3):
        raise ValueError("dim must be 2 or 3")
    rng = np.random.default_rng(seed)
    obstacles: list[Shape] = []
    for _ in range(n_obstacles):
        if dim == 2 and polygons and rng.random() < 0.5:
            obstacles.append(_random_star(rng, size))
        else:
            lo = rng.uniform(0, size * 0.85, dim)
            ext = rng.uniform(size * 0.05, size * 0.35, dim)
            obstacles.append(Box(tuple(np.round(lo, 3)), tuple(np.round(np.minimum(lo + ext, size * 1.05), 3))))
    ws = Box((0.0,) * dim, (size,) * dim)
    free_pt = _free_point_sampler(rng, ws, obstacles)
    start_pos = free_pt()
    goal_pos = free_pt()
    half = size * 0.04
    goal = Box(tuple(goal_pos - half), tuple(goal_pos + half))
    dyn = integrator_chain(order, dim, dt)
    start = np.zeros(dyn.n_states)
    start[:dim] = start_pos
    return ReachProblem(
        workspace=ws,
        obstacles=tuple(obstacles),
        goal=goal,
        dynamics=dyn,
        start=start,
        input_bound=input_bound,
        name=f"random-{dim}d-{seed}",
    )


def _random_star(rng: np.random.Generator, size: float) -> Polygon:
    k = int(rng.integers(3, 9))
    c = rng.uniform(size * 0.1, size * 0.9, 2)
    angles = np.sort(rng.uniform(0, 2 * math.pi, k))
    # keep angular gaps below pi so the centre stays inside: star-shaped, simple
    while np.max(np.diff(np.concatenate([angles, [angles[0] + 2 * math.pi]]))) >= math.pi * 0.9:
        angles = np.sort(rng.uniform(0, 2 * math.pi, k))
    radii = rng.uniform(size * 0.04, size * 0.2, k)
    vs = tuple(
        (round(float(c[0] + r * math.cos(a)), 3), round(float(c[1] + r * math.sin(a)), 3))
        for a, r in zip(angles, radii)
    )
    return Polygon(vs)


def _free_point_sampler(rng: np.random.Generator, ws: Box, obstacles: list[Shape]):
    d = ws.dim
    geom = None
    if d == 2 and obstacles:
        geom = shapely.union_all([shape_to_shapely(o) for o in obstacles])

    def inside(p: np.ndarray) -> bool:
        if d == 2:
            return (
                geom is not None
                and geom.distance(shapely.Point(p)) < ws.hi[0] * 0.005
                or (geom is not None and geom.contains(shapely.Point(p)))
            )
        return any(all(o.lo[k] - 0.05 <= p[k] <= o.hi[k] + 0.05 for k in range(d)) for o in obstacles)  # type: ignore[union-attr]

    def sample() -> np.ndarray:
        for _ in range(10_000):
            p = np.round(rng.uniform(np.array(ws.lo) + 0.5, np.array(ws.hi) - 0.5), 3)
            if not inside(p):
                return p
        raise RuntimeError("no free point found; too many obstacles for the workspace")

    return sample


def examples() -> dict[str, ReachProblem]:
    """The example problems written to ``examples/reach`` (file stem -> problem)."""
    out = {f"maze-{n}": maze(n) for n in range(1, 5)}
    chain = maze(2, order=3)
    out["chain-maze-2"] = ReachProblem(**{**_fields(chain), "name": "chain-maze-2"})
    out["dubins"] = dubins_example()
    out["cluttered"] = cluttered()
    return out


def _fields(p: ReachProblem) -> dict:
    return {k: getattr(p, k) for k in p.__dataclass_fields__}


_HEADERS = {
    "maze": "Maze with {n} passage(s): Shoukry et al., CDC 2016, Section VI (Table I).\nDouble integrator, dt = 0.5 s, |u| <= 1 m/s^2, |v| <= 2 m/s per axis.",
    "chain-maze-2": "Maze with 2 passages and a chain of 3 integrators per axis (jerk input):\nthe scalability study of Shoukry et al., CDC 2016, Figure 4.",
    "dubins": "Dubins-like car (unicycle with speed as a state) through its feedback-linearised\nform: a double integrator on (x, y) (Shoukry et al., CDC 2016, Section VI-A).\nplansynth.reach.dubins maps the planned trajectory back to speed, heading and turn rate.",
    "cluttered": "A room with five non-convex polygon obstacles, double-integrator robot.",
}


class _ExampleDumper(yaml.SafeDumper):
    """Writes a polygon (a list of [x, y] pairs) on one line."""


def _represent_list(dumper: yaml.SafeDumper, data: list) -> yaml.Node:
    flow = all(isinstance(v, list) and all(isinstance(c, (int, float)) for c in v) for v in data) and bool(data)
    return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=True if flow else None)


_ExampleDumper.add_representer(list, _represent_list)


def write_examples(directory: str | Path) -> list[Path]:
    """(Re)write every example problem as ``<directory>/<name>.yaml``; return the paths."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    paths = []
    for stem, p in examples().items():
        key = "maze" if stem.startswith("maze-") else stem
        header = _HEADERS[key].format(n=stem.split("-")[-1])
        comment = "".join(f"# {line}\n" for line in header.splitlines())
        comment += "# Generated by `python -m plansynth.reach.families examples/reach`.\n"
        doc = reach_problem_to_dict(p)
        text = comment + yaml.dump(doc, Dumper=_ExampleDumper, sort_keys=False, default_flow_style=None, width=100)
        path = d / f"{stem}.yaml"
        write_output(path, text)
        paths.append(path)
    return paths


def main(argv: list[str] | None = None) -> None:
    args = sys.argv[1:] if argv is None else argv
    directory = args[0] if args else "examples/reach"
    for path in write_examples(directory):
        print(path)


if __name__ == "__main__":
    main()

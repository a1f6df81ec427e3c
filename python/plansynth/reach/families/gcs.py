"""The n x n mazes of the GCS paper (Marcucci, Petersen, von Wrangel, Tedrake, "Motion
planning around obstacles with convex optimization", Science Robotics 2023), generated
as its code does: the scale family beside Shoukry et al.'s (CDC 2016, Section VI) mazes.
"""

from __future__ import annotations

import random

import numpy as np

from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["gcs_maze", "GCS_MAZE_WALL", "GCS_MAZE_KNOCK_DOWNS"]


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

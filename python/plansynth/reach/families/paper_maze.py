"""The n-passage maze of Shoukry et al. (CDC 2016, Section VI, Table I) with the
double integrator, or with an integrator chain of any order (the scalability study,
Figure 4).
"""

from __future__ import annotations

import numpy as np

from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.geometry import Box, Shape
from plansynth.reach.problem import ReachProblem

__all__ = ["maze", "MAZE_SIZE", "WALL_THICKNESS", "RIGHT_GAP", "LEFT_GAP", "DERIVATIVE_BOUND"]

MAZE_SIZE = 30.0
WALL_THICKNESS = 1.0
RIGHT_GAP = (27.0, 29.0)
LEFT_GAP = (1.0, 3.0)
DERIVATIVE_BOUND = 2.0


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

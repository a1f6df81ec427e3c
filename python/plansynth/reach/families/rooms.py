"""Two hand-made rooms beside the mazes: :func:`cluttered`, non-convex polygon
obstacles (an example beyond Shoukry et al., CDC 2016), and :func:`dubins_example`,
Section VI-A's car through its feedback-linearised form (see :mod:`plansynth.reach.dubins`).
"""

from __future__ import annotations

import math

import numpy as np

from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.problem import ReachProblem

__all__ = ["cluttered", "dubins_example"]


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

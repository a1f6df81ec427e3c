"""The goal regions of the abstraction (Shoukry et al., CDC 2016, Section III): the
regions whose closure meets the goal (a face or a point is enough: a plan may end
there, where the goal's interior beside it is obstacle).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction.regions import Region
from plansynth.reach.geometry import Box, shape_to_shapely
from plansynth.reach.problem import ReachProblem

__all__ = ["regions_meeting_goal"]


def regions_meeting_goal(problem: ReachProblem, regions: Sequence[Region]) -> tuple[int, ...]:
    goal = problem.goal
    out = []
    if problem.dim == 2:
        g = shape_to_shapely(goal)
        gb = g.bounds
        for r in regions:
            v = r.vertices
            if v[:, 0].max() < gb[0] or v[:, 0].min() > gb[2] or v[:, 1].max() < gb[1] or v[:, 1].min() > gb[3]:
                continue
            if ShPolygon(v).intersects(g):  # closed sets: touching counts
                out.append(r.index)
        return tuple(out)
    assert isinstance(goal, Box)
    for r in regions:
        lo, hi = r.vertices.min(axis=0), r.vertices.max(axis=0)
        if np.all(np.minimum(hi, goal.hi) - np.maximum(lo, goal.lo) >= 0):  # (3-D regions are boxes)
            out.append(r.index)
    return tuple(out)

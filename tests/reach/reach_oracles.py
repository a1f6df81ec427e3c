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


def feasible(h: highspy.Highs, rows: list[Row]) -> bool:
    """Add ``rows`` to ``h`` (its columns already added), solve, and say whether the LP
    is feasible (an optimum exists: the objective is zero)."""
    starts, index, value = [], [], []
    for coef, _, _ in rows:
        starts.append(len(index))
        index.extend(coef)
        value.extend(coef.values())
    h.addRows(len(rows), np.array([r[1] for r in rows]), np.array([r[2] for r in rows]), len(index),
              np.array(starts, dtype=np.int32), np.array(index, dtype=np.int32), np.array(value, dtype=float))
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kOptimal

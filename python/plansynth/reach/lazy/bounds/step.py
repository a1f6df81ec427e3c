"""How far the robot can move in one step, and the horizon bound that follows with the
obstacles ignored (beyond Shoukry et al., CDC 2016; every bound is sound): the first
relaxation of CON-PLAN (Section V) that the time windows, the proved bound, the separator
chains and the transit layer build on.

* :func:`step_reach`: the largest position change per step along each axis, one small
  LP per axis and direction (computed once per problem);
* :func:`physical_lower_bound`: the distance from the start to the goal divided by it;
* :func:`box_steps`: the fewest steps between two boxes at those speeds (and, from rest,
  by the multi-step table of :func:`~plansynth.reach.dynamics.displacement_reach`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import highspy
import numpy as np

from plansynth.reach.dynamics import displacement_reach, reach_steps
from plansynth.reach.geometry import Box
from plansynth.reach.highs import new_highs
from plansynth.reach.problem import ReachProblem

__all__ = ["step_reach", "physical_lower_bound", "shape_box", "box_of", "box_steps", "MULTISTEP_TABLE"]


def step_reach(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
    """(down, up): the largest position change per step along each workspace axis in
    the negative and the positive direction that dynamics, input bounds, state bounds
    and the workspace allow (inf when unbounded). One LP per axis and direction:
    maximise ``+-(p_{t+1} - p_t)_a`` over ``x_t, u_t`` with ``x_t`` and ``A x_t + B u_t``
    within the bounds.
    """
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    pos = list(dyn.position)
    A, B = np.asarray(dyn.A), np.asarray(dyn.B)
    lo, hi = problem.state_box
    # variables [x (n), u (m)]; rows: A x + B u within [lo, hi]
    M = np.hstack([A, B])
    lp = highspy.HighsLp()
    lp.num_col_ = n + m
    lp.num_row_ = n
    lp.col_lower_ = np.concatenate([lo, np.full(m, -problem.input_bound)])
    lp.col_upper_ = np.concatenate([hi, np.full(m, problem.input_bound)])
    lp.row_lower_ = lo
    lp.row_upper_ = hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kRowwise
    nz = np.nonzero(M)
    lp.a_matrix_.start_ = np.concatenate([[0], np.cumsum(np.bincount(nz[0], minlength=n))]).astype(np.int32)
    lp.a_matrix_.index_ = nz[1].astype(np.int32)
    lp.a_matrix_.value_ = M[nz]
    h = new_highs()
    down, up = np.zeros(len(pos)), np.zeros(len(pos))
    for a, i in enumerate(pos):
        for sign, out in ((1.0, up), (-1.0, down)):
            cost = sign * (M[i] - np.eye(n + m)[i])  # (A x + B u)_i - x_i
            lp.col_cost_ = -cost  # HiGHS minimises
            h.passModel(lp)
            h.run()
            status = h.getModelStatus()
            if status == highspy.HighsModelStatus.kOptimal:
                out[a] = max(0.0, -h.getInfo().objective_function_value)
            else:
                out[a] = math.inf
    return down, up


def _once_per_problem(f):  # (problems are immutable values with identity hashes)
    import functools
    import weakref

    memo: weakref.WeakKeyDictionary[ReachProblem, tuple[np.ndarray, np.ndarray]] = weakref.WeakKeyDictionary()

    @functools.wraps(f)
    def cached(problem: ReachProblem) -> tuple[np.ndarray, np.ndarray]:
        if problem not in memo:
            memo[problem] = f(problem)
        down, up = memo[problem]
        return down.copy(), up.copy()

    return cached


#: computed once per problem (four callers per plan: the bounds, the windows, the
#: proved bound and the transit layer; eight LPs each time)
step_reach = _once_per_problem(step_reach)


#: steps covered by the multi-step displacement table (the random dynamics family)
MULTISTEP_TABLE = 1000


def physical_lower_bound(problem: ReachProblem) -> int:
    """A horizon below which no trajectory reaches the goal, obstacles ignored: along
    every axis, the distance from the start to the goal's bounding box divided by the
    largest displacement per step (see :func:`step_reach`).

    >>> from plansynth.reach.families import maze
    >>> physical_lower_bound(maze(1))   # 26 m up at most 1 m (2 m/s x 0.5 s) per step
    26
    """
    down, up = step_reach(problem)
    s = np.asarray(problem.start_position, dtype=float)
    table = (
        displacement_reach(problem.dynamics, problem.input_bound, MULTISTEP_TABLE) if problem.starts_at_rest else None
    )
    return box_steps((s, s), shape_box(problem.goal), down, up, table)


def shape_box(shape: Any) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box (lo, hi) of a :class:`Box` or a polygon."""
    if isinstance(shape, Box):
        return np.asarray(shape.lo, dtype=float), np.asarray(shape.hi, dtype=float)
    return box_of(np.asarray(shape.vertices))


def box_steps(
    a: tuple[np.ndarray, np.ndarray],
    b: tuple[np.ndarray, np.ndarray],
    down: Sequence[float],
    up: Sequence[float],
    table: np.ndarray | None = None,
) -> int:
    """The fewest steps from a position in box ``a`` to one in box ``b`` when a step moves
    at most ``down[i]``/``up[i]`` along axis i (1 << 30: some axis cannot move that way),
    and (``table``, :func:`plansynth.reach.dynamics.displacement_reach`) k steps move at
    most ``table[k, i]`` either way.

    >>> box_steps((np.zeros(2), np.zeros(2)), (np.array([3.0, -1.0]), np.array([4.0, 1.0])), [1, 1], [1.5, 1])
    2
    """
    (alo, ahi), (blo, bhi) = a, b
    need = 0
    for ax in range(len(alo)):
        for dist, reach in ((blo[ax] - ahi[ax], up[ax]), (alo[ax] - bhi[ax], down[ax])):
            if dist > 0:
                if not reach > 0:
                    return 1 << 30  # cannot move that way at all
                if math.isfinite(reach):
                    # shave the LP's tolerance off before rounding up
                    need = max(need, math.ceil(dist / reach * (1 - 1e-9) - 1e-9))
                if table is not None:
                    need = max(need, reach_steps(table, dist, ax))
    return need


def box_of(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bounding box (lo, hi) of a set of points (a region's vertices)."""
    v = np.asarray(vertices, dtype=float)
    return v.min(axis=0), v.max(axis=0)

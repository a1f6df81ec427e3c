"""The polytopes the mission MILP (:mod:`plansynth.reach.mission.milp`, Wolff, Topcu and
Murray, ICRA 2014, Section IV, "mixed-integer encoding of polyhedra") states on the
continuous positions: the obstacles' convex pieces, each label's literals at its margin
(:mod:`plansynth.reach.offsets`), and the boxes of positions the robot can reach in t
steps that make every big-M tight.
"""

from __future__ import annotations

from dataclasses import dataclass

import highspy
import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.geometry import convex_pieces, halfspaces, is_convex
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.offsets import grown, shrunk
from plansynth.reach.problem import ReachProblem

__all__ = ["MilpGeometry", "ReachBoxes", "Rows_"]

Rows_ = tuple[np.ndarray, np.ndarray]  # (H, h) of a convex piece: {p : H p <= h}


# --------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class _LabelPieces:
    """A label's literals as polytopes: ``a`` holds in one of ``inside`` (convex pieces;
    empty when no point is deep enough); ``!a`` holds beyond one edge of ``outside`` (a
    convex label grown by its margin) or, for a non-convex label, in one of
    ``complement`` (convex pieces of the workspace outside it)."""

    inside: tuple[Rows_, ...]
    outside: Rows_ | None
    complement: tuple[Rows_, ...]


@dataclass(frozen=True)
class MilpGeometry:
    """The polytopes the model states: the planning problem's obstacles (convex pieces:
    grown by the obstacle margin, in a sized robot's configuration space) and each
    label's literals at its margin."""

    obstacles: tuple[Rows_, ...]
    labels: dict[str, _LabelPieces]

    @classmethod
    def of(cls, problem: ReachProblem, planning: ReachProblem) -> MilpGeometry:
        obstacles = tuple(piece for o in planning.obstacles for piece in convex_pieces(o))
        labels = {}
        ws = planning.workspace
        for name, shape in problem.mission_labels.items():
            r = problem.label_margin(name)
            if is_convex(shape):
                inner = shrunk(shape, r)
                labels[name] = _LabelPieces(
                    () if inner is None else (halfspaces(inner),), halfspaces(grown(shape, r)), ()
                )
            else:  # margin 0 (the door refuses a margin on a non-convex label)
                labels[name] = _LabelPieces(tuple(convex_pieces(shape)), None, _complement(shape, ws))
        return cls(obstacles, labels)


def _complement(shape, ws) -> tuple[Rows_, ...]:
    """Convex pieces (triangles) of the workspace box outside the polygon ``shape``."""
    import shapely

    from plansynth.reach.geometry import Polygon, shape_to_shapely

    rest = shape_to_shapely(ws).difference(shape_to_shapely(shape))
    out = []
    for tri in shapely.get_parts(shapely.constrained_delaunay_triangles(rest)):
        coords = list(tri.exterior.coords)[:-1]
        out.append(halfspaces(Polygon(tuple((float(x), float(y)) for x, y in coords))))
    return tuple(out)


class ReachBoxes:
    """The box of positions the robot can reach from the start in exactly t steps
    (dynamics, input and state bounds, workspace; obstacles ignored): for each step an LP
    per axis and direction, computed on demand and kept. A sound relaxation, so the model
    may bound its positions by it."""

    def __init__(self, planning: ReachProblem) -> None:
        self.problem = planning
        self.boxes: list[tuple[np.ndarray, np.ndarray]] = []
        self.lp_calls = 0

    def __call__(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        while len(self.boxes) <= t:
            checkpoint()
            self.boxes.append(self._box(len(self.boxes)))
        return self.boxes[t]

    def _box(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        p = self.problem
        pos = list(p.dynamics.position)
        start = np.asarray(p.start, float)
        if t == 0:
            return start[pos].copy(), start[pos].copy()
        lo_s, hi_s = p.state_box
        dyn = p.dynamics
        n, m = dyn.n_states, dyn.n_inputs
        A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        nx = (t + 1) * n
        ncol = nx + t * m
        R, C, V = [], [], []
        for s in range(t):
            for i in range(n):
                row = s * n + i
                R.append(row), C.append((s + 1) * n + i), V.append(1.0)
                for j in np.nonzero(A[i])[0]:
                    R.append(row), C.append(s * n + j), V.append(-A[i, j])
                for j in np.nonzero(B[i])[0]:
                    R.append(row), C.append(nx + s * m + j), V.append(-B[i, j])
        col_lo = np.concatenate([np.tile(lo_s, t + 1), np.full(t * m, -p.input_bound)])
        col_hi = np.concatenate([np.tile(hi_s, t + 1), np.full(t * m, p.input_bound)])
        col_lo[:n] = col_hi[:n] = start
        lp = csc_lp(
            ncol,
            t * n,
            np.array(R, np.int64),
            np.array(C, np.int64),
            np.array(V, float),
            np.zeros(ncol),
            col_lo,
            col_hi,
            np.zeros(t * n),
            np.zeros(t * n),
        )
        h = new_highs()
        h.passModel(lp)
        lo, hi = np.zeros(len(pos)), np.zeros(len(pos))
        for a, i in enumerate(pos):
            for sign, out in ((1.0, hi), (-1.0, lo)):
                cost = np.zeros(ncol)
                cost[t * n + i] = -sign  # HiGHS minimises: maximise sign * p_t[a]
                h.changeColsCost(ncol, np.arange(ncol, dtype=np.int32), cost)
                h.run()
                self.lp_calls += 1
                if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
                    out[a] = (p.workspace.hi if sign > 0 else p.workspace.lo)[a]  # no answer: the workspace
                    continue
                out[a] = sign * -h.getInfo().objective_function_value
        # rounding outwards (the LP's tolerance): never cut a reachable position off
        slack = 1e-7 * (1.0 + np.abs(np.concatenate([lo, hi])).max())
        ws_lo, ws_hi = np.asarray(p.workspace.lo, float), np.asarray(p.workspace.hi, float)
        return np.maximum(lo - slack, ws_lo), np.minimum(hi + slack, ws_hi)

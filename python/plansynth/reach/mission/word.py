"""The word of a trajectory for the independent mission checker
(:mod:`plansynth.reach.mission.check`, whose docstring defines the margins, the readings
and the word): each label's geometry, each literal's margin at each step (at the sample,
or least along the segment), and the letters of the literals that may hold there.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.geometry import Box, halfspaces, is_convex
from plansynth.reach.mission.ltl import Formula, Not, Prop, children, subformulas
from plansynth.reach.problem import ReachProblem

__all__ = ["NEG", "Label", "literal_form", "trajectory_word"]

NEG = "!"  # letters hold "a" (a may hold) and "!a" (not a may hold)


# --------------------------------------------------------------------------- the labels' margins


class Label:
    """One label's geometry: its half-planes when convex, shapely's polygon otherwise."""

    def __init__(self, shape) -> None:
        self.convex = is_convex(shape)
        if self.convex:
            self.H, self.h = halfspaces(shape)
        if isinstance(shape, Box):
            self.geom = shapely.box(shape.lo[0], shape.lo[1], shape.hi[0], shape.hi[1])
        else:
            self.geom = ShPolygon(shape.vertices)
        shapely.prepare(self.geom)

    def at_points(self, P: np.ndarray) -> np.ndarray:
        """The margin of ``a`` at each point (that of ``!a`` is its negative)."""
        if self.convex:
            return np.min(self.h[None, :] - P @ self.H.T, axis=1)
        pts = shapely.points(P)
        d = shapely.distance(self.geom.boundary, pts)
        inside = shapely.contains(self.geom, pts)
        return np.where(inside, d, -d)

    def along(self, p: np.ndarray, q: np.ndarray) -> tuple[float, float]:
        """(the least margin of ``a``, the least margin of ``!a``) along [p, q]."""
        if np.array_equal(p, q):
            v = float(self.at_points(p[None, :])[0])
            return v, -v
        if self.convex:
            a = float(min(np.min(self.h - self.H @ p), np.min(self.h - self.H @ q)))
            return a, _min_of_max(self.H @ p - self.h, self.H @ (q - p))
        seg = LineString([tuple(p), tuple(q)])
        P = np.array([p, q])
        ends = self.at_points(P)
        inside, boundary = self.geom.covers(seg), self.geom.boundary
        if inside:
            a = float(shapely.distance(boundary, seg))
        else:  # leaves the label: the farthest of the endpoints and of the parts outside
            out = seg.difference(self.geom)
            pts = np.array([c for part in shapely.get_parts(out) for c in part.coords] or [p])
            a = -max(float(np.max(-self.at_points(pts))), 1e-300)
        if not shapely.relate_pattern(self.geom, seg, "T********"):
            na = float(shapely.distance(self.geom, seg))
        else:  # enters its interior: the deepest of the endpoints and of the parts inside
            part_in = seg.intersection(self.geom)
            pts = np.array([c for part in shapely.get_parts(part_in) for c in getattr(part, "coords", [])] or [p])
            mids = (pts[:-1] + pts[1:]) / 2 if len(pts) > 1 else pts
            na = -max(float(np.max(self.at_points(np.vstack([pts, mids])))), float(np.max(ends)), 1e-300)
        return a, na


def _min_of_max(c: np.ndarray, d: np.ndarray) -> float:
    """min over s in [0, 1] of max_i (c_i + d_i s): a convex piecewise-linear function,
    least at an end or where two of its lines cross."""
    cand = [0.0, 1.0]
    for i in range(len(c)):
        for j in range(i + 1, len(c)):
            if d[i] != d[j]:
                s = (c[j] - c[i]) / (d[i] - d[j])
                if 0.0 < s < 1.0:
                    cand.append(float(s))
    S = np.array(cand)
    return float(np.min(np.max(c[None, :] + d[None, :] * S[:, None], axis=1)))


def _step_margins(
    problem: ReachProblem, P: np.ndarray, loop_start: int | None, reading: str, labels: dict[str, Label]
) -> list[dict[str, float]]:
    """Per step of the word, each literal's margin (``"a"`` and ``"!a"``)."""
    N = len(P) - 1
    last = N - 1 if loop_start is not None else N
    out: list[dict[str, float]] = [{} for _ in range(last + 1)]
    for n, lab in labels.items():
        if reading == "sample":
            depth = lab.at_points(P[: last + 1])
            for t in range(last + 1):
                out[t][n], out[t][NEG + n] = float(depth[t]), float(-depth[t])
            continue
        for t in range(last + 1):
            if t < N:
                a, na = lab.along(P[t], P[t + 1])
            else:
                d = float(lab.at_points(P[t][None, :])[0])
                a, na = d, -d
            out[t][n], out[t][NEG + n] = a, na
    return out


def trajectory_word(
    problem: ReachProblem,
    positions: np.ndarray,
    loop_start: int | None,
    tol: float = 1e-6,
    *,
    reading: str | None = None,
    labels: dict | None = None,
) -> tuple[list[frozenset[str]], list[dict[str, float]]]:
    """The letters (sets of "may hold" literals: ``a`` when its margin is >= the label's
    margin - tol, ``!a`` likewise) of the trajectory's word in the reading (default: the
    problem's), and each step's margins. A lasso's word has N letters (position N is
    position k again). ``labels``: the labels' geometry (name -> ``Label``), if the
    caller has built it."""
    reading = problem.reading if reading is None else reading
    if labels is None:
        labels = {n: Label(s) for n, s in problem.mission_labels.items()}
    P = np.asarray(positions, float)[:, :2]
    values = _step_margins(problem, P, loop_start, reading, labels)
    letters = []
    for v in values:
        letter = set()
        for n in labels:
            r = problem.label_margin(n)
            if v[n] >= r - tol:
                letter.add(n)
            if v[NEG + n] >= r - tol:
                letter.add(NEG + n)
        letters.append(frozenset(letter))
    return letters, values


def literal_form(f: Formula) -> Formula:
    """NNF with ``!a`` turned into the proposition "!a" (read off the letters); iterative."""
    done: dict[Formula, Formula] = {}
    for g in subformulas(f):
        if isinstance(g, Not):
            done[g] = Prop(NEG + g.arg.name)
        elif not children(g):
            done[g] = g
        else:
            kids = [done[c] for c in children(g)]
            fields = [getattr(g, k) for k in ("lo", "hi") if hasattr(g, k)]
            done[g] = type(g)(*fields, *kids)
    return done[f]


# --------------------------------------------------------------------------- the check

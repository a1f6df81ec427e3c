"""The independent trajectory validator (paper, Definition 2.3; spec, "Semantics").

Every trajectory a planner reports is checked here before it is called ``found``. The
validator knows only the problem and the trajectory: it uses neither the convex
decomposition nor any planner code, and it re-does the geometry itself (boxes exactly
by slab clipping; polygons with shapely's exact predicates), so a bug in the planner's
encoding cannot hide behind the same bug here.

Checks, each reported as a :class:`Violation` of a named ``kind``:

``shape``       the arrays have the wrong sizes (nothing else is checked then);
``start``       x_0 differs from the problem's start;
``dynamics``    ``|x_{t+1} - (A x_t + B u_t)|_inf > tol * max(1, |x_{t+1}|_inf)``;
``input``       ``|u_t|_inf > input_bound + tol``;
``state-bound`` a state component outside ``state_bounds`` by more than tol;
``workspace``   a position outside the workspace by more than tol;
``obstacle``    a position inside an obstacle deeper than tol (boundary is allowed);
``goal``        the final position outside the goal by more than tol;
``segment``     the straight segment between consecutive positions enters an obstacle
                deeper than tol (only an error when ``require_segment_safe``).

>>> from plansynth.reach.problem import Box, ReachProblem
>>> from plansynth.reach.dynamics import single_integrator
>>> from plansynth.reach.trajectory import Trajectory
>>> p = ReachProblem(workspace=Box((0, 0), (4, 4)), obstacles=(Box((1, 1), (3, 3)),),
...                  goal=Box((3, 3), (4, 4)), dynamics=single_integrator(2, 1.0),
...                  start=[0, 0], input_bound=4.0)
>>> t = Trajectory(states=[[0, 0], [3.5, 3.5]], inputs=[[3.5, 3.5]])
>>> r = validate(p, t)
>>> r.ok, r.segment_safe, [v.kind for v in r.violations]
(True, False, [])
>>> validate(p, t, require_segment_safe=True).violations[0].kind
'segment'
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.problem import Box, ReachProblem, Shape, halfspaces
from plansynth.reach.trajectory import Trajectory

__all__ = ["Violation", "ValidationReport", "validate", "VIOLATION_KINDS"]

VIOLATION_KINDS = ("shape", "start", "dynamics", "input", "state-bound", "workspace", "obstacle", "goal", "segment")


@dataclass(frozen=True)
class Violation:
    """One failed check: its ``kind`` (see module doc), the step (None: whole trajectory)."""

    kind: str
    step: int | None
    detail: str

    def __str__(self) -> str:
        at = "" if self.step is None else f" at step {self.step}"
        return f"{self.kind}{at}: {self.detail}"


@dataclass(frozen=True)
class ValidationReport:
    """The validator's verdict.

    ``ok``: the trajectory satisfies Definition 2.3 (and is segment-safe when that was
    required). ``segment_safe`` is always computed. ``max_dynamics_error`` and
    ``max_input`` are the largest residual and input magnitude seen (inf-norms).
    """

    ok: bool
    segment_safe: bool
    violations: tuple[Violation, ...]
    max_dynamics_error: float
    max_input: float
    horizon: int
    tol: float
    require_segment_safe: bool
    counts: dict[str, int] = field(default_factory=dict)

    def __bool__(self) -> bool:
        raise TypeError("a ValidationReport has no truth value; read .ok or .segment_safe")

    def summary(self) -> str:
        """One line: verdict and violation counts."""
        verdict = "valid" if self.ok else "INVALID"
        seg = "segment-safe" if self.segment_safe else "not segment-safe"
        counts = ", ".join(f"{k} x{n}" for k, n in self.counts.items())
        return f"{verdict}, {seg}, horizon {self.horizon}, max dynamics error {self.max_dynamics_error:.2e}" + (
            f"; violations: {counts}" if counts else ""
        )

    def to_json_dict(self) -> dict:
        return {
            "ok": self.ok,
            "segment_safe": self.segment_safe,
            "max_dynamics_error": self.max_dynamics_error,
            "max_input": self.max_input,
            "horizon": self.horizon,
            "tol": self.tol,
            "violations": [{"kind": v.kind, "step": v.step, "detail": v.detail} for v in self.violations],
        }


# ------------------------------------------------------------------ geometry kernel


def _segment_enters_open_box(p: np.ndarray, q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> bool:
    """Does the closed segment p-q meet the open box (lo, hi)? (Liang-Barsky, strict.)"""
    if np.any(lo >= hi):
        return False
    t0, t1 = -np.inf, np.inf
    d = q - p
    for k in range(len(p)):
        if d[k] == 0.0:
            if not lo[k] < p[k] < hi[k]:
                return False
            continue
        a, b = (lo[k] - p[k]) / d[k], (hi[k] - p[k]) / d[k]
        if a > b:
            a, b = b, a
        t0, t1 = max(t0, a), min(t1, b)
    return t0 < t1 and t0 < 1.0 and t1 > 0.0


class _Obstacle:
    """One obstacle shrunk by ``tol``: "inside deeper than tol" = meets the open shrunk set."""

    def __init__(self, shape: Shape, tol: float) -> None:
        self.shape = shape
        if isinstance(shape, Box):
            self.lo = np.array(shape.lo) + tol
            self.hi = np.array(shape.hi) - tol
            self.geom = None
        else:
            poly = ShPolygon(shape.vertices)
            self.geom = poly.buffer(-tol, join_style="mitre") if tol > 0 else poly
            shapely.prepare(self.geom)

    def hits(self, p: np.ndarray, q: np.ndarray | None = None) -> bool:
        if q is None:
            q = p
        if self.geom is None:
            return _segment_enters_open_box(p, q, self.lo, self.hi)
        if self.geom.is_empty:
            return False
        g = Point(p[0], p[1]) if np.array_equal(p, q) else LineString([p[:2], q[:2]])
        # interiors meet: DE-9IM "T********"
        return bool(shapely.relate_pattern(self.geom, g, "T********"))


def _in_shape(shape: Shape, p: np.ndarray, tol: float) -> bool:
    if isinstance(shape, Box):
        return bool(np.all(p >= np.array(shape.lo) - tol) and np.all(p <= np.array(shape.hi) + tol))
    H, h = halfspaces(shape)
    return bool(np.all(H @ p <= h + tol))


# ------------------------------------------------------------------ the validator


MAX_TOL_FRACTION = 1e-3  # the largest tolerance: this fraction of the workspace's smallest side


def tolerance_problem(problem: ReachProblem, tol: float) -> str | None:
    """Why ``tol`` cannot be a validation tolerance for ``problem``, or None: it must be
    a finite number >= 0 and at most :data:`MAX_TOL_FRACTION` of the workspace's
    smallest side, or 1e-6 (``inf`` would call a trajectory that leaves the workspace
    valid).

    >>> from plansynth.reach.families import maze
    >>> tolerance_problem(maze(1), float("inf"))
    'must be a finite number >= 0, got inf'
    >>> tolerance_problem(maze(1), 0.5)
    'must be at most 0.03 (1e-03 of the workspace side 30), got 0.5'
    """
    if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not np.isfinite(tol) or tol < 0:
        return f"must be a finite number >= 0, got {tol!r}"
    side = float(np.min(np.array(problem.workspace.hi) - np.array(problem.workspace.lo)))
    top = max(MAX_TOL_FRACTION * side, 1e-6)  # the default tolerance is always allowed
    if tol > top:
        return f"must be at most {top:g} ({MAX_TOL_FRACTION:.0e} of the workspace side {side:g}), got {tol!r}"
    return None


def validate(
    problem: ReachProblem,
    trajectory: Trajectory,
    *,
    require_segment_safe: bool = False,
    tol: float = 1e-6,
) -> ValidationReport:
    """Check ``trajectory`` against ``problem`` (Definition 2.3) and report every violation.

    ``tol`` must pass :func:`tolerance_problem` (ValueError otherwise)."""
    why = tolerance_problem(problem, tol)
    if why is not None:
        raise ValueError(f"validation tolerance {why}")
    dyn = problem.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    X, U = trajectory.states, trajectory.inputs
    N = trajectory.horizon
    viol: list[Violation] = []

    def report(ok_flag: bool, segment_safe: bool, max_err: float, max_u: float) -> ValidationReport:
        counts: dict[str, int] = {}
        for v in viol:
            counts[v.kind] = counts.get(v.kind, 0) + 1
        return ValidationReport(
            ok=ok_flag,
            segment_safe=segment_safe,
            violations=tuple(viol),
            max_dynamics_error=max_err,
            max_input=max_u,
            horizon=N,
            tol=tol,
            require_segment_safe=require_segment_safe,
            counts=counts,
        )

    if X.shape[1] != n or (N > 0 and U.shape[1] != m):
        viol.append(Violation("shape", None, f"expected states with {n} and inputs with {m} components, got {X.shape[1]} and {U.shape[1]}"))
        return report(False, False, float("inf"), float("inf"))
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(U))):
        viol.append(Violation("shape", None, "states or inputs contain NaN or infinity"))
        return report(False, False, float("inf"), float("inf"))

    # x_0 = start
    err0 = float(np.max(np.abs(X[0] - problem.start)))
    if err0 > tol * max(1.0, float(np.max(np.abs(problem.start)))):
        viol.append(Violation("start", 0, f"x_0 differs from the start by {err0:.3g}"))

    # dynamics and inputs
    max_err = 0.0
    max_u = 0.0
    for t in range(N):
        pred = dyn.A @ X[t] + dyn.B @ U[t]
        err = float(np.max(np.abs(X[t + 1] - pred)))
        max_err = max(max_err, err)
        if err > tol * max(1.0, float(np.max(np.abs(X[t + 1])))):
            viol.append(Violation("dynamics", t, f"|x_{t + 1} - (A x_{t} + B u_{t})|_inf = {err:.3g}"))
        un = float(np.max(np.abs(U[t]))) if m else 0.0
        max_u = max(max_u, un)
        if un > problem.input_bound + tol:
            viol.append(Violation("input", t, f"|u_{t}|_inf = {un:.6g} exceeds the bound {problem.input_bound:g}"))

    # state bounds
    if problem.state_bounds is not None:
        lo, hi = np.array(problem.state_bounds.lo), np.array(problem.state_bounds.hi)
        for t in range(N + 1):
            bad = np.nonzero((X[t] < lo - tol) | (X[t] > hi + tol))[0]
            if bad.size:
                k = int(bad[0])
                viol.append(Violation("state-bound", t, f"x_{t}[{k}] = {X[t, k]:.6g} outside [{lo[k]:g}, {hi[k]:g}]"))

    # positions: workspace, obstacles, goal
    P = X[:, list(dyn.position)]
    ws_lo, ws_hi = np.array(problem.workspace.lo), np.array(problem.workspace.hi)
    obstacles = [_Obstacle(o, tol) for o in problem.obstacles]
    for t in range(N + 1):
        p = P[t]
        if np.any(p < ws_lo - tol) or np.any(p > ws_hi + tol):
            viol.append(Violation("workspace", t, f"position {_fmt(p)} outside the workspace"))
        for i, ob in enumerate(obstacles):
            if ob.hits(p):
                viol.append(Violation("obstacle", t, f"position {_fmt(p)} inside obstacles[{i}]"))
    if not _in_shape(problem.goal, P[N], tol):
        viol.append(Violation("goal", N, f"final position {_fmt(P[N])} is not in the goal"))

    # segments
    segment_safe = True
    for t in range(N):
        for i, ob in enumerate(obstacles):
            if ob.hits(P[t], P[t + 1]):
                segment_safe = False
                if require_segment_safe:
                    viol.append(Violation("segment", t, f"segment {_fmt(P[t])} -> {_fmt(P[t + 1])} crosses obstacles[{i}]"))
    return report(not viol, segment_safe, max_err, max_u)


def _fmt(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in p) + ")"

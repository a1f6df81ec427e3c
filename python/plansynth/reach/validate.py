"""The independent trajectory validator (paper, Definition 2.3; spec, "Semantics").

Every trajectory a planner reports is checked here before it is called ``found``. The
validator knows only the problem and the trajectory: it uses neither the convex
decomposition nor any planner code, and it re-does the geometry itself (boxes exactly
by slab clipping; polygons with shapely's exact predicates), so a bug in the planner's
encoding cannot hide behind the same bug here.

Checks, each reported as a :class:`Violation` of a named ``kind``:

``shape``       the arrays have the wrong sizes (nothing else is checked then);
``start``       a component of x_0 differs from the start's by more than
                ``tol * max(1, |start_i|)``;
``dynamics``    a row of the residual, ``|(x_{t+1} - A x_t - B u_t)_i|``, exceeds
                ``tol * max(1, sum_j |A_ij x_t,j| + sum_j |B_ij u_t,j|)``: each row is held
                to the size of its own terms (a velocity row is not excused by a position
                of 1e6);
``input``       ``|u_t|_inf > input_bound + tol``;
``state-bound`` a state component outside ``state_bounds`` by more than tol;
``workspace``   a position outside the workspace by more than tol;
``obstacle``    a position inside an obstacle deeper than tol (boundary is allowed);
                with a sized robot (``robot.radius`` / ``robot.half_extent``): a disc
                robot's position closer than R - tol to an obstacle (Euclidean distance,
                shapely), a box robot's box meeting an obstacle's interior (box obstacles:
                exact slab test on the grown box; polygons: shapely); the workspace check
                then keeps the robot's whole extent inside;
``goal``        the final position outside the goal by more than tol;
``segment``     the straight segment between consecutive positions enters an obstacle
                deeper than tol (only an error when ``require_segment_safe``); with a
                sized robot: the segment's distance below R - tol, or the area the box
                sweeps along it meeting an obstacle's interior;
``derivative``  (``dynamics="curve"`` with sample ``times``, named integrator models
                only) a derivative changes faster between two samples than the bound
                of the next derivative allows: ``|d_i(t') - d_i(t)|_inf > b_{i+1} (t' - t)
                + tol`` (``b`` from the state bounds, the input bound for the last), or
                moves away from what the next derivative's samples say, by more than
                ``b_{i+2} (t' - t)^2 / 2 + tol`` (a position that jumps while its velocity
                samples stand still).

``dynamics="exact"`` (the default) is Definition 2.3. ``dynamics="curve"`` is for the
samples of a continuous-time curve (the ``gcs`` planner, guarantee ``"curve"``): the
exact discrete dynamics are *not* required (the residual is still measured and
reported as ``max_dynamics_error``), every other check is made, and with ``times`` the
derivative check above, which a curve with |a| <= input_bound passes and a velocity
jump fails.

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

from plansynth.reach.collisions import hits_table, in_shape, obstacle_checks
from plansynth.reach.collisions import segment_enters_open_box as _segment_enters_open_box  # noqa: F401 - tests
from plansynth.reach.collisions import segments_enter_open_box as _segments_enter_open_box  # noqa: F401 - tests
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["Violation", "ValidationReport", "validate", "VIOLATION_KINDS"]

VIOLATION_KINDS = (
    "shape",
    "start",
    "dynamics",
    "input",
    "state-bound",
    "workspace",
    "obstacle",
    "goal",
    "segment",
    "derivative",
)
DYNAMICS_MODES = ("exact", "curve")


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
    dynamics: str = "exact"

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
            "dynamics": self.dynamics,
            "violations": [{"kind": v.kind, "step": v.step, "detail": v.detail} for v in self.violations],
        }


def row_tolerance(A: np.ndarray, B: np.ndarray, x: np.ndarray, u: np.ndarray, tol: float) -> np.ndarray:
    """The allowed residual of each row of x' = A x + B u: ``tol`` times the size of the
    row's own terms, at least 1 (so a velocity row is not excused by a position of 1e6)."""
    return tol * np.maximum(1.0, np.abs(A) @ np.abs(x) + np.abs(B) @ np.abs(u))


def component_tolerance(ref: np.ndarray, tol: float) -> np.ndarray:
    """The allowed difference of each component from ``ref`` (a start, a loop's closure)."""
    return tol * np.maximum(1.0, np.abs(ref))


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
    dynamics: str = "exact",
    times: np.ndarray | None = None,
) -> ValidationReport:
    """Check ``trajectory`` against ``problem`` (Definition 2.3) and report every violation.

    ``dynamics``: ``"exact"`` or ``"curve"`` (see the module doc); ``times``: the sample
    times in seconds (curve mode only), for the derivative check.
    ``tol`` must pass :func:`tolerance_problem` (ValueError otherwise)."""
    if dynamics not in DYNAMICS_MODES:
        raise ValueError(f"unknown dynamics mode {dynamics!r} (known: {', '.join(DYNAMICS_MODES)})")
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
            dynamics=dynamics,
        )

    if X.shape[1] != n or (N > 0 and U.shape[1] != m):
        viol.append(
            Violation(
                "shape",
                None,
                f"expected states with {n} and inputs with {m} components, got {X.shape[1]} and {U.shape[1]}",
            )
        )
        return report(False, False, float("inf"), float("inf"))
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(U))):
        viol.append(Violation("shape", None, "states or inputs contain NaN or infinity"))
        return report(False, False, float("inf"), float("inf"))

    # x_0 = start
    start = np.asarray(problem.start, float)
    off = np.abs(X[0] - start)
    err0 = float(np.max(off))
    if np.any(off > component_tolerance(start, tol)):
        viol.append(Violation("start", 0, f"x_0 differs from the start by {err0:.3g}"))

    # dynamics and inputs
    max_err = 0.0
    max_u = 0.0
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    for t in range(N):
        pred = A @ X[t] + B @ U[t]
        row = np.abs(X[t + 1] - pred)
        err = float(np.max(row))
        max_err = max(max_err, err)
        if dynamics == "exact" and np.any(row > row_tolerance(A, B, X[t], U[t], tol)):
            viol.append(Violation("dynamics", t, f"|x_{t + 1} - (A x_{t} + B u_{t})|_inf = {err:.3g}"))
        un = float(np.max(np.abs(U[t]))) if m else 0.0
        max_u = max(max_u, un)
        if un > problem.input_bound + tol:
            viol.append(Violation("input", t, f"|u_{t}|_inf = {un:.6g} exceeds the bound {problem.input_bound:g}"))

    if dynamics == "curve" and times is not None:
        _derivative_check(problem, X, np.asarray(times, dtype=float), tol, viol)

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
    if problem.robot_shape is not None:  # the robot's extent stays in the workspace
        margin = np.array(problem.robot_shape.margins(problem.dim))
        ws_lo, ws_hi = ws_lo + margin, ws_hi - margin
    obstacles = obstacle_checks(problem, tol)
    # (obstacle, time) tables; only the times with a violation are visited, in the order
    # of the plain double loop over times and obstacles
    inside = hits_table(obstacles, P)
    outside = np.any(P < ws_lo - tol, axis=1) | np.any(P > ws_hi + tol, axis=1)
    for t in np.flatnonzero(outside | inside.any(axis=0)).tolist():
        p = P[t]
        if outside[t]:
            viol.append(Violation("workspace", t, f"position {_fmt(p)} outside the workspace"))
        for i in np.flatnonzero(inside[:, t]).tolist():
            viol.append(Violation("obstacle", t, f"position {_fmt(p)} inside obstacles[{i}]"))
    if not in_shape(problem.goal, P[N], tol):
        viol.append(Violation("goal", N, f"final position {_fmt(P[N])} is not in the goal"))

    # segments
    crosses = hits_table(obstacles, P[:-1], P[1:])
    segment_safe = not crosses.any()
    if require_segment_safe:
        for t in np.flatnonzero(crosses.any(axis=0)).tolist():
            for i in np.flatnonzero(crosses[:, t]).tolist():
                viol.append(Violation("segment", t, f"segment {_fmt(P[t])} -> {_fmt(P[t + 1])} crosses obstacles[{i}]"))
    return report(not viol, segment_safe, max_err, max_u)


def _derivative_check(
    problem: ReachProblem, X: np.ndarray, times: np.ndarray, tol: float, viol: list[Violation]
) -> None:
    """Curve mode: between two samples, each derivative block of a named integrator
    model moves by at most the bound of the next derivative times the time between them."""
    dyn = problem.dynamics
    order = {"single-integrator": 1, "double-integrator": 2}.get(
        dyn.model, dyn.order if dyn.model == "integrator-chain" else None
    )
    d = problem.dim
    if order is None or X.shape[0] != times.shape[0]:
        if X.shape[0] != times.shape[0]:
            viol.append(Violation("shape", None, f"{times.shape[0]} sample times for {X.shape[0]} states"))
        return
    bounds: list[float | None] = []
    for i in range(1, order + 1):
        if i == order:
            bounds.append(problem.input_bound)
        elif problem.state_bounds is not None:
            lo = np.abs(np.array(problem.state_bounds.lo[i * d : (i + 1) * d]))
            hi = np.abs(np.array(problem.state_bounds.hi[i * d : (i + 1) * d]))
            bounds.append(float(max(lo.max(), hi.max())))
        else:
            bounds.append(None)
    gaps = np.diff(times)
    for i in range(order):
        b = bounds[i]
        if b is None:
            continue
        block = X[:, i * d : (i + 1) * d]
        moved = np.max(np.abs(np.diff(block, axis=0)), axis=1)
        bad = np.nonzero(moved > b * gaps + tol * max(1.0, b))[0]
        for t in bad[:5]:
            what = "position" if i == 0 else f"derivative {i}"
            viol.append(
                Violation(
                    "derivative",
                    int(t),
                    f"{what} moves by {moved[t]:.4g} in {gaps[t]:.4g} s, more than the bound {b:g} allows",
                )
            )
    if order >= 2:
        # each block against the next one's samples: with |d_{i+2}| <= b, d_i(t') - d_i(t)
        # differs from d_{i+1}(t) (t' - t) by at most b (t' - t)^2 / 2, and likewise with
        # d_{i+1}(t') (Taylor with the remainder bounded): a position that jumps while the
        # sampled velocity says it stands still fails
        for i in range(order - 1):
            b = bounds[i + 1]
            if b is None:
                continue
            block, rate = X[:, i * d : (i + 1) * d], X[:, (i + 1) * d : (i + 2) * d]
            step = np.diff(block, axis=0)
            slack = b * gaps**2 / 2 + tol * max(1.0, b)
            off = np.maximum(
                np.max(np.abs(step - rate[:-1] * gaps[:, None]), axis=1),
                np.max(np.abs(step - rate[1:] * gaps[:, None]), axis=1),
            )
            what = "position" if i == 0 else f"derivative {i}"
            for t in np.nonzero(off > slack)[0][:5]:
                viol.append(
                    Violation(
                        "derivative",
                        int(t),
                        f"{what} moves by {np.max(np.abs(step[t])):.4g} in "
                        f"{gaps[t]:.4g} s, {off[t]:.4g} away from what derivative {i + 1} allows",
                    )
                )


def _fmt(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in p) + ")"

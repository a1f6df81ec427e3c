"""Piecewise Bezier curves, the answers of the convex-optimisation baselines (``gcs``:
Marcucci et al., Science Robotics 2023; ``fpp``: Marcucci, Nobel, Tedrake and Boyd,
IEEE T-RO 2024), turned into what the validator checks.

A curve is a sequence of Bezier pieces, each given by its control points and its time
interval. Its derivative is again one (the differences of the control points, scaled by
order / duration), and by the convex-hull property every value of a piece lies in the
hull of its control points: the per-axis extremes of the control points bound the curve,
its velocity and its acceleration over the whole piece (:meth:`PiecewiseBezier.extremes`).

:func:`sampled_curve` re-times a curve to a whole number of time steps ``N dt`` (a
uniform stretch by a factor >= 1, which keeps every bound of the velocity and
acceleration and a start at rest) and samples it twice: at ``t_k = k dt`` (the states
(position, velocity) and inputs (the acceleration) the validator reads as a trajectory)
and densely (:data:`CURVE_SUBSTEPS` per dt, plus every piece's ends), as
:class:`~plansynth.reach.result.ReachResult` carries them (``trajectory``, ``curve``,
``curve_times``).

>>> c = PiecewiseBezier((np.array([[0.0], [0.0], [1.0]]),), np.array([0.0, 2.0]))
>>> c(np.array([0.0, 1.0, 2.0])).ravel().tolist()
[0.0, 0.25, 1.0]
>>> c.derivative().derivative()(np.array([1.0])).ravel().tolist()
[0.5]
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from plansynth.errors import SolverUnavailable
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "PiecewiseBezier",
    "CurveRun",
    "sampled_curve",
    "CURVE_SUBSTEPS",
    "integrator_order",
    "derivative_bounds",
    "position_box",
]

#: Dense samples per time step of the curve returned beside the samples at dt.
CURVE_SUBSTEPS = 10


@dataclass(frozen=True)
class PiecewiseBezier:
    """Bezier pieces: ``points[i]`` (order + 1 rows, one column per axis) on the time
    interval ``breaks[i]..breaks[i + 1]`` (seconds)."""

    points: tuple[np.ndarray, ...]
    breaks: np.ndarray

    def __post_init__(self) -> None:
        if len(self.breaks) != len(self.points) + 1 or not len(self.points):
            raise ValueError("a curve needs at least one piece and one more break than pieces")
        if np.any(np.diff(self.breaks) <= 0):
            raise ValueError("the pieces' time intervals must have positive lengths")

    @property
    def duration(self) -> float:
        return float(self.breaks[-1] - self.breaks[0])

    @property
    def dim(self) -> int:
        return int(self.points[0].shape[1])

    def derivative(self) -> PiecewiseBezier:
        """The curve's time derivative (pieces of order 0 have derivative 0)."""
        out = []
        for P, a, b in zip(self.points, self.breaks[:-1], self.breaks[1:]):
            k = P.shape[0] - 1
            out.append(np.diff(P, axis=0) * (k / (b - a)) if k > 0 else np.zeros((1, P.shape[1])))
        return PiecewiseBezier(tuple(out), self.breaks)

    def stretched(self, factor: float) -> PiecewiseBezier:
        """The same path traversed ``factor`` times slower, from the same start time."""
        t0 = self.breaks[0]
        return PiecewiseBezier(self.points, t0 + (self.breaks - t0) * float(factor))

    def extremes(self) -> tuple[np.ndarray, np.ndarray]:
        """Per-axis bounds of the curve over its whole duration: the extremes of the
        control points (convex-hull property)."""
        allp = np.vstack(self.points)
        return allp.min(axis=0), allp.max(axis=0)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """Values at the times ``t`` (clipped to the curve's interval): (len(t), dim)."""
        t = np.clip(np.asarray(t, float), self.breaks[0], self.breaks[-1])
        which = np.clip(np.searchsorted(self.breaks, t, side="right") - 1, 0, len(self.points) - 1)
        out = np.zeros((len(t), self.dim))
        for i in np.unique(which):
            sel = which == i
            P = self.points[i]
            k = P.shape[0] - 1
            s = (t[sel] - self.breaks[i]) / (self.breaks[i + 1] - self.breaks[i])
            basis = np.array([math.comb(k, j) * s**j * (1 - s) ** (k - j) for j in range(k + 1)])
            out[sel] = basis.T @ P
        return out


def sampled_curve(
    problem: ReachProblem, curve: PiecewiseBezier, order: int
) -> tuple[Trajectory, Trajectory, tuple[float, ...], int, float]:
    """The curve (positions, starting at the problem's start) re-timed to ``N dt`` with
    ``N = ceil(duration / dt)`` and sampled (see the module doc), for a robot of
    ``order`` 1 (the input is the velocity) or 2 (the state holds the velocity, the input
    is the acceleration): (samples at dt, dense samples, their times, N, stretch)."""
    dt = float(problem.dynamics.dt)  # type: ignore[arg-type]
    duration = curve.duration
    N = max(1, math.ceil(duration / dt - 1e-9))
    stretch = N * dt / duration if duration > 0 else 1.0  # >= 1: keeps every bound
    c = curve.stretched(stretch)
    v = c.derivative()
    acc = v.derivative()
    d = problem.dim
    pos = list(problem.dynamics.position)
    t0 = float(c.breaks[0])

    def states_inputs(times: np.ndarray) -> Trajectory:
        tau = t0 + times
        X = np.zeros((len(times), problem.dynamics.n_states))
        X[:, pos] = c(tau)
        if order == 2:
            X[:, d : 2 * d] = v(tau)
            U = acc(tau)[:-1]
        else:
            U = v(tau)[:-1]
        X[0] = problem.start  # the curve starts exactly there; drop round-off
        return Trajectory(states=X, inputs=U)

    times = np.arange(N + 1) * dt
    breaks = np.asarray(c.breaks, float) - t0
    dense = np.union1d(np.linspace(0.0, N * dt, N * CURVE_SUBSTEPS + 1), np.clip(breaks, 0.0, N * dt))
    return states_inputs(times), states_inputs(dense), tuple(float(t) for t in dense), N, float(stretch)


def integrator_order(problem: ReachProblem, planner: str) -> int:
    """The derivative order of the robot (1: single, 2: double integrator); other
    dynamics are :class:`~plansynth.errors.SolverUnavailable` for ``planner``, whose
    curves have no other dynamics."""
    dyn = problem.dynamics
    order = {"single-integrator": 1, "double-integrator": 2}.get(
        dyn.model, dyn.order if dyn.model == "integrator-chain" else None
    )
    if order not in (1, 2) or dyn.dt is None:
        raise SolverUnavailable(
            planner,
            f"{planner} plans for single- and double-integrator robots only (named models of order 1 or 2); "
            f"this problem's dynamics are {dyn.model}"
            + (f" of order {dyn.order}" if dyn.order else "")
            + ": use lazy-smt",
        )
    return int(order)


def derivative_bounds(problem: ReachProblem, k: int) -> tuple[np.ndarray, np.ndarray] | None:
    """Per-axis bounds of the k-th derivative block of a named integrator model (state
    ordered by derivative, then axis), from the state bounds; None when unbounded."""
    if problem.state_bounds is None:
        return None
    d = problem.dim
    lo = np.array(problem.state_bounds.lo[k * d : (k + 1) * d])
    hi = np.array(problem.state_bounds.hi[k * d : (k + 1) * d])
    if lo.size != d:
        return None
    return lo, hi


def position_box(problem: ReachProblem) -> Box:
    """The workspace intersected with the state bounds of the position components."""
    lo, hi = np.array(problem.workspace.lo), np.array(problem.workspace.hi)
    if problem.state_bounds is not None:
        pos = list(problem.dynamics.position)
        lo = np.maximum(lo, np.array(problem.state_bounds.lo)[pos])
        hi = np.minimum(hi, np.array(problem.state_bounds.hi)[pos])
    return Box(tuple(lo), tuple(hi))


@dataclass
class CurveRun:
    """What a curve planner records while it runs (its name, start time, counters,
    timings, options) and the two results it ends with: :meth:`unknown` and :meth:`found`
    (``guarantee="curve"``). Its ``seconds`` are the wall time since ``t0`` less
    ``timings["isolation"]`` (a child process's start and imports, when the planner runs
    its library in one)."""

    solver: str
    t0: float = field(default_factory=time.perf_counter)
    counters: dict[str, Any] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)

    def _seconds(self) -> float:
        self.timings["total"] = time.perf_counter() - self.t0
        return self.timings["total"] - self.timings.get("isolation", 0.0)

    def unknown(self, message: str) -> ReachResult:
        return ReachResult(
            status=ReachStatus.UNKNOWN,
            solver=self.solver,
            seconds=self._seconds(),
            counters=self.counters,
            timings=self.timings,
            options=self.options,
            message=message,
            guarantee="curve",
        )

    def found(
        self,
        sampled: tuple[Trajectory, Trajectory, tuple[float, ...], int, float],
        message: str,
        regions: tuple[int, ...] | None = None,
    ) -> ReachResult:
        """``found`` with the samples of :func:`sampled_curve` (``message``: the guarantee)."""
        traj, dense, times, N, _ = sampled
        return ReachResult(
            status=ReachStatus.FOUND,
            solver=self.solver,
            seconds=self._seconds(),
            trajectory=traj,
            regions=regions,
            horizon=N,
            counters=self.counters,
            timings=self.timings,
            options=self.options,
            guarantee="curve",
            message=message,
            curve=dense,
            curve_times=times,
        )

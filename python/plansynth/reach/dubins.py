"""Dubins-like vehicles through feedback linearisation (paper, Section VI-A).

The planner handles linear dynamics only. A unicycle with its speed made a state (the
*dynamic extension*),

    x' = s cos(theta),  y' = s sin(theta),  theta' = omega,  s' = a,

has the flat output (x, y): differentiating twice gives

    [x'', y'']^T = [[cos(theta), -s sin(theta)], [sin(theta), s cos(theta)]] [a, omega]^T,

so with the state feedback ``(a, omega) = M(theta, s)^{-1} (ux, uy)`` the closed loop is
exactly the double integrator ``p'' = u`` on (x, y), with ``s = |p'|`` and
``theta = atan2(y', x')``. The matrix has determinant ``s``: the linearisation is
singular where the speed is zero, and the heading is then undefined.

:func:`unicycle_controls` maps a planned double-integrator trajectory back to the car's
speed, heading, acceleration and turn rate, and lists the singular samples;
:func:`simulate_unicycle` drives the nonlinear car with that feedback (RK4) and returns
its states, so one can check that it follows the plan.

>>> import numpy as np
>>> from plansynth.reach.families import dubins_example
>>> from plansynth.reach.trajectory import Trajectory
>>> p = dubins_example()
>>> x1 = p.dynamics.step(p.start, [0.0, 1.0])
>>> c = unicycle_controls(p, Trajectory([p.start, x1], [[0.0, 1.0]]))
>>> [float(v) for v in (c.speed[0], c.heading[0], c.acceleration[0], c.turn_rate[0])], c.singular
([1.0, 0.0, 0.0, 1.0], ())
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = ["UnicycleControls", "unicycle_controls", "linearising_feedback", "simulate_unicycle"]

SINGULAR_SPEED = 1e-6


@dataclass(frozen=True, eq=False)
class UnicycleControls:
    """The car's view of a double-integrator trajectory, sampled at t_k = k dt.

    ``speed``, ``heading`` (rad) at every sample (N+1); ``acceleration`` and
    ``turn_rate`` (rad/s) at the start of every step (N), from the feedback law.
    ``singular``: samples with speed below ``SINGULAR_SPEED`` -- there the heading is
    carried over from the previous sample (or taken along the first input) and the turn
    rate is NaN: the car must stop and turn in place, which a Dubins car cannot.
    ``singular_steps``: steps during which the speed ``|v_k + u_k tau|`` comes below
    ``SINGULAR_SPEED`` for some ``tau`` in ``[0, dt]`` (the velocity passes near zero
    between samples); ``step_min_speed`` gives that minimum for every step.
    """

    times: np.ndarray
    speed: np.ndarray
    heading: np.ndarray
    acceleration: np.ndarray
    turn_rate: np.ndarray
    singular: tuple[int, ...]
    singular_steps: tuple[int, ...] = ()
    step_min_speed: np.ndarray | None = None

    @property
    def min_speed(self) -> float:
        return float(self.speed.min())

    @property
    def max_turn_rate(self) -> float:
        """Largest |turn rate| over the non-singular steps (0 for none)."""
        w = self.turn_rate[np.isfinite(self.turn_rate)]
        return float(np.max(np.abs(w))) if w.size else 0.0


def linearising_feedback(speed: float, heading: float, u: np.ndarray) -> tuple[float, float]:
    """``(a, omega)`` with ``M(heading, speed) (a, omega) = u``; needs ``speed != 0``.

    >>> a, w = linearising_feedback(2.0, math.pi / 2, np.array([1.0, 0.0]))  # heading north, push east
    >>> round(a, 12), w
    (0.0, -0.5)
    """
    c, s = math.cos(heading), math.sin(heading)
    a = c * u[0] + s * u[1]
    omega = (c * u[1] - s * u[0]) / speed
    return float(a), float(omega)


def _check(problem: ReachProblem) -> tuple[int, int, int, int]:
    dyn = problem.dynamics
    if dyn.model != "double-integrator" or problem.dim != 2:
        raise ValueError(
            f"the unicycle mapping needs a 2-D double integrator, got a {problem.dim}-D {dyn.model!r} model"
        )
    return dyn.position[0], dyn.position[1], 2, 3


def unicycle_controls(problem: ReachProblem, trajectory: Trajectory) -> UnicycleControls:
    """Speed, heading, acceleration and turn rate of the car that follows ``trajectory``."""
    _, _, ivx, ivy = _check(problem)
    dt = float(problem.dynamics.dt)  # type: ignore[arg-type]
    X, U = trajectory.states, trajectory.inputs
    speed = np.hypot(X[:, ivx], X[:, ivy])
    heading = np.empty(len(X))
    singular = []
    for k in range(len(X)):
        if speed[k] >= SINGULAR_SPEED:
            heading[k] = math.atan2(X[k, ivy], X[k, ivx])
        else:
            singular.append(k)
            if k > 0:
                heading[k] = heading[k - 1]
            elif len(U) and np.any(U[0] != 0):
                heading[k] = math.atan2(U[0][1], U[0][0])
            else:
                heading[k] = 0.0
    acc = np.empty(len(U))
    turn = np.empty(len(U))
    for k in range(len(U)):
        if speed[k] >= SINGULAR_SPEED:
            acc[k], turn[k] = linearising_feedback(speed[k], heading[k], U[k])
        else:
            acc[k] = math.cos(heading[k]) * U[k][0] + math.sin(heading[k]) * U[k][1]
            turn[k] = math.nan
    step_min = np.empty(len(U))
    for k in range(len(U)):
        v = X[k, [ivx, ivy]]
        uu = np.asarray(U[k], dtype=float)
        uu2 = float(uu @ uu)
        tau = 0.0 if uu2 == 0.0 else min(max(-float(v @ uu) / uu2, 0.0), dt)
        step_min[k] = float(np.hypot(*(v + uu * tau)))
    return UnicycleControls(
        times=np.arange(len(X)) * dt,
        speed=speed,
        heading=heading,
        acceleration=acc,
        turn_rate=turn,
        singular=tuple(singular),
        singular_steps=tuple(int(k) for k in np.nonzero(step_min < SINGULAR_SPEED)[0]),
        step_min_speed=step_min,
    )


def simulate_unicycle(problem: ReachProblem, trajectory: Trajectory, substeps: int = 40) -> np.ndarray:
    """Drive the car ``[x, y, heading, speed]`` with the linearising feedback of the
    trajectory's inputs (RK4, ``substeps`` per step); return its state at every sample.

    Raises ValueError when the speed comes near zero at a sample or within a step.
    """
    ix, iy, ivx, ivy = _check(problem)
    c = unicycle_controls(problem, trajectory)
    if c.singular or c.singular_steps:
        raise ValueError(
            "the feedback linearisation is singular (speed ~ 0) at samples "
            f"{list(c.singular)} and during steps {list(c.singular_steps)}"
        )
    dt = float(problem.dynamics.dt)  # type: ignore[arg-type]
    X, U = trajectory.states, trajectory.inputs
    z = np.array([X[0, ix], X[0, iy], c.heading[0], c.speed[0]])
    out = [z.copy()]
    h = dt / substeps

    def f(state: np.ndarray, u: np.ndarray) -> np.ndarray:
        _, _, th, s = state
        a, w = linearising_feedback(s, th, u)
        return np.array([s * math.cos(th), s * math.sin(th), w, a])

    for k in range(len(U)):
        for _ in range(substeps):
            k1 = f(z, U[k])
            k2 = f(z + h / 2 * k1, U[k])
            k3 = f(z + h / 2 * k2, U[k])
            k4 = f(z + h * k3, U[k])
            z = z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(z.copy())
    return np.array(out)

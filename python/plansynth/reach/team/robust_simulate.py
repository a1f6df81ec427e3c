"""Every robot's closed loop under sampled disturbance sequences: each robot r runs
``u_t = v_t + K_r (x_t - x_nom_t)`` on ``x_{t+1} = A_r x_t + B_r u_t + w_{r,t}`` from its
start, with its own sequence (independent of the other robots'), and every run of the
team is checked by the independent team validator
(:func:`~plansynth.reach.team.validate.validate_team` with ``dynamics="curve"``: the
disturbed runs need not satisfy ``x' = A x + B u``; bounds, goals, static obstacles,
segments, the separation between every two robots and from every moving obstacle are
required). A violation names the robots and the step.

The sequences are those of the single robot (:func:`plansynth.reach.robust.simulate.sample_disturbances`:
``random`` uniform in W_r, ``vertex`` a vertex of W_r at every step); a robot without a
disturbance runs its nominal plan. A simulation can only show a violation; the worst case
of :mod:`plansynth.reach.team.robust_check` proves there is none. A nominal team plan run
under the same sequences shows what robustness buys.

>>> from plansynth.reach import solve
>>> from plansynth.reach.team.families import windy_swap
>>> from plansynth.reach.team.robust_check import team_gains
>>> p = windy_swap()
>>> r = solve(p)
>>> simulate_team(p, r.trajectories, team_gains(p, r.robust), sequences=20).violated
0
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from plansynth.reach.robust.simulate import KINDS, Failure, SimulationReport, closed_loop, sample_disturbances
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.team.validate import validate_team
from plansynth.reach.trajectory import Trajectory

__all__ = ["simulate_team"]


def simulate_team(
    problem: TeamProblem,
    trajectories: Sequence[Trajectory],
    gains: Sequence[np.ndarray | None],
    *,
    sequences: int = 1000,
    seed: int = 0,
    kinds: tuple[str, ...] = KINDS,
    tol: float = 1e-6,
) -> SimulationReport:
    """Run ``sequences`` team runs of each kind (the same for the same ``seed``) and
    check each with the team validator (module doc)."""
    rng = np.random.default_rng(seed)
    N = trajectories[0].horizon
    runs: dict[str, int] = {}
    bad: dict[str, int] = {}
    kinds_seen: dict[str, int] = {}
    first: Failure | None = None
    for kind in kinds:
        loops = []
        for r, traj in enumerate(trajectories):
            own = problem.robot_problems[r]
            K = gains[r]
            if own.disturbance is None or K is None:
                X = np.broadcast_to(np.asarray(traj.states, float), (sequences, *np.shape(traj.states)))
                U = np.broadcast_to(np.asarray(traj.inputs, float), (sequences, *np.shape(traj.inputs)))
                loops.append((X, U))
                continue
            W = sample_disturbances(own, kind, sequences, N, rng)
            loops.append(closed_loop(own, traj, K, W))
        runs[kind], bad[kind] = sequences, 0
        for i in range(sequences):
            team = [Trajectory(states=X[i], inputs=U[i]) for X, U in loops]
            report = validate_team(problem, team, tol=tol, dynamics="curve")
            if report.ok:
                continue
            bad[kind] += 1
            for k in report.counts:
                kinds_seen[k] = kinds_seen.get(k, 0) + 1
            if first is None:
                first = Failure(kind, i, str(report.violations[0]))
    return SimulationReport(runs, bad, seed, first, kinds_seen)

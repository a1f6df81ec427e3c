"""What ``plansynth reach solve``, ``validate`` and ``plot`` do with a team problem (the
CLI, :mod:`plansynth.reach.cli`, stays a thin shell: it calls these when the problem
file has ``robots``, ``separation`` or ``moving_obstacles``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from plansynth.reach.team.problem import TeamProblem

__all__ = ["write_outputs", "validate_file", "plot_file"]


def write_outputs(
    problem: TeamProblem, result: Any, out: Path | None, plot: Path | None, animate: Path | None
) -> list[str]:
    """The result JSON, picture and GIF of ``reach solve`` on a team; the lines to print."""
    lines = []
    if out is not None:
        result.write(out)
        lines.append(f"result written to {out}")
    if plot is None and animate is None:
        return lines
    if result.trajectories is None:
        return lines + ["no trajectory to draw"]
    from plansynth.reach.team.plot import animate_team, plot_team

    if plot is not None:
        plot_team(
            problem,
            result.trajectories,
            path=plot,
            title=f"{problem.name}: {result.solver}, {problem.n_robots} robots, horizon {result.horizon}",
        )
        lines.append(f"picture written to {plot}")
    if animate is not None:
        animate_team(problem, result.trajectories, animate)
        lines.append(f"animation written to {animate}")
    return lines


def validate_file(
    problem: TeamProblem,
    doc: Any,
    source: str,
    *,
    tol: float,
    disturbances: int = 0,
    seed: int = 0,
    nominal: bool = False,
) -> tuple[bool, list[str]]:
    """``reach validate`` on a team result document: the verdict and the lines to print
    (the team validator's summary and its violations, each naming robots and steps).
    A team under disturbances (:mod:`plansynth.reach.team.robust`): also the worst case
    with each robot's gain (the result's, else its design), ``disturbances`` sampled
    runs of each kind, and with ``nominal`` a nominal team plan under the same runs."""
    from plansynth.reach.team.result import team_trajectories_from_dict
    from plansynth.reach.team.validate import validate_team

    trajectories, _ = team_trajectories_from_dict(doc, source, [r.name for r in problem.robots])
    report = validate_team(problem, trajectories, tol=tol)
    lines = [f"{'valid' if report.ok else 'INVALID'}: {report.summary()}"]
    lines += [f"  {v}" for v in report.violations[:50]]
    if len(report.violations) > 50:
        lines.append(f"  ... and {len(report.violations) - 50} more")
    ok = report.ok
    if any(r.disturbance is not None for r in problem.robots):
        robust_ok, more = _robust_lines(problem, trajectories, doc, tol, disturbances, seed, nominal)
        ok, lines = ok and robust_ok, lines + more
    return ok, lines


def _robust_lines(
    problem: TeamProblem, trajectories: Any, doc: Any, tol: float, disturbances: int, seed: int, nominal: bool
) -> tuple[bool, list[str]]:
    """The worst case, the sampled runs and the nominal plan's runs of a robust team."""
    from plansynth.reach.team.robust_check import check_robust_team, team_gains
    from plansynth.reach.team.robust_simulate import simulate_team

    robust = doc.get("robust") if isinstance(doc.get("robust"), dict) else None
    gains = team_gains(problem, robust)
    source = "the result's" if robust and robust.get("robots") else "the problem's designs"
    lines = []
    for robot, K in zip(problem.robots, gains):
        if K is not None:
            gain = "; ".join(", ".join(f"{v + 0.0:.4g}" for v in row) for row in np.asarray(K))
            lines.append(f"feedback of robot {robot.name}: u = v + K (x - x_nom), K = [{gain}] ({source})")
    report = check_robust_team(problem, trajectories, gains, tol=tol)
    lines.append(f"worst case: {report.summary()}")
    lines += [f"  {v}" for v in report.violations[:20]]
    ok = report.ok
    if disturbances:
        runs = simulate_team(problem, trajectories, gains, sequences=disturbances, seed=seed, tol=tol)
        lines.append(f"simulated: {runs.summary()}")
        ok = ok and runs.violated == 0
        if nominal:
            lines.append(_nominal_runs(problem, gains, disturbances, seed, tol))
    return ok, lines


def _nominal_runs(problem: TeamProblem, gains: Any, disturbances: int, seed: int, tol: float) -> str:
    """A nominal team plan (lazy-smt-team, the disturbances ignored) under the same sequences."""
    from plansynth.budget import Budget
    from plansynth.reach.team.lazy import plan_team_lazy
    from plansynth.reach.team.robust import without_disturbances
    from plansynth.reach.team.robust_simulate import simulate_team
    from plansynth.reach.team.solve import validate_team_result

    plain = without_disturbances(problem)
    result = validate_team_result(plain, plan_team_lazy(plain, Budget(seconds=60.0)))
    if result.trajectories is None:
        return f"nominal plan: none ({result.message})"
    runs = simulate_team(problem, result.trajectories, gains, sequences=disturbances, seed=seed, tol=tol)
    kinds = ", ".join(f"{k} in {v}" for k, v in runs.kinds_violated.items())
    return (
        f"nominal plan (horizon {result.horizon}, the disturbances ignored), same gains and sequences: "
        f"{runs.summary()}" + (f"; runs with each violation: {kinds}" if kinds else "")
    )


def plot_file(problem: TeamProblem, doc: Any | None, source: str | None, output: Path) -> None:
    """``reach plot`` on a team (with a result document: the robots' trajectories)."""
    from plansynth.reach.team.plot import plot_team
    from plansynth.reach.team.result import team_trajectories_from_dict

    trajectories = None
    if doc is not None:
        trajectories, _ = team_trajectories_from_dict(doc, source, [r.name for r in problem.robots])
    plot_team(problem, trajectories, path=output)

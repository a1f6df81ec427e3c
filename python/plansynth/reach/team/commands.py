"""What ``plansynth reach solve``, ``validate`` and ``plot`` do with a team problem (the
CLI, :mod:`plansynth.reach.cli`, stays a thin shell: it calls these when the problem
file has ``robots``, ``separation`` or ``moving_obstacles``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

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


def validate_file(problem: TeamProblem, doc: Any, source: str, *, tol: float) -> tuple[bool, list[str]]:
    """``reach validate`` on a team result document: the verdict and the lines to print
    (the team validator's summary and its violations, each naming robots and steps)."""
    from plansynth.reach.team.result import team_trajectories_from_dict
    from plansynth.reach.team.validate import validate_team

    trajectories, _ = team_trajectories_from_dict(doc, source, [r.name for r in problem.robots])
    report = validate_team(problem, trajectories, tol=tol)
    lines = [f"{'valid' if report.ok else 'INVALID'}: {report.summary()}"]
    lines += [f"  {v}" for v in report.violations[:50]]
    if len(report.violations) > 50:
        lines.append(f"  ... and {len(report.violations) - 50} more")
    return report.ok, lines


def plot_file(problem: TeamProblem, doc: Any | None, source: str | None, output: Path) -> None:
    """``reach plot`` on a team (with a result document: the robots' trajectories)."""
    from plansynth.reach.team.plot import plot_team
    from plansynth.reach.team.result import team_trajectories_from_dict

    trajectories = None
    if doc is not None:
        trajectories, _ = team_trajectories_from_dict(doc, source, [r.name for r in problem.robots])
    plot_team(problem, trajectories, path=output)

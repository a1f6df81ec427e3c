"""``plansynth reach plot``: draw the workspace, the regions the planners see and (with
a result) the trajectory."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.markup import escape

from plansynth.cli_support import EXIT_BAD_INPUT, fail
from plansynth.errors import InvalidProblem, PlansynthError
from plansynth.io import check_output_path
from plansynth.reach.commands.common import read_result

PLOT_EPILOG = """\
Examples:

  plansynth reach plot examples/reach/cluttered.yaml -o regions.png

  plansynth reach plot examples/reach/maze-3.yaml traj.json -o traj.png
"""


def configuration_space_of(problem: Any) -> Any:
    """The point-robot problem of ``problem`` (:func:`plansynth.reach.robot.configuration_space`)."""
    from plansynth.reach.robot import configuration_space

    return configuration_space(problem)


def plot_command(
    file: Path = typer.Argument(..., help="Reach problem file."),
    result_file: Path | None = typer.Argument(None, help="Optional result JSON (trajectory and regions)."),
    output: Path = typer.Option(..., "--output", "-o", help="PNG file to write."),
) -> None:
    """Draw the workspace, the convex regions and (with a result) the trajectory."""
    from plansynth.reach.planner_regions import planner_abstraction
    from plansynth.reach.plot import plot_problem
    from plansynth.reach.team.fileformat import load_problem
    from plansynth.reach.trajectory import trajectory_from_dict

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    try:
        check_output_path(output)
        problem = load_problem(file)
        if getattr(problem, "robots", None) is not None:  # a team: one colour per robot
            from plansynth.reach.team.commands import plot_file

            doc = None if result_file is None else read_result(result_file)
            plot_file(problem, doc, None if result_file is None else str(result_file), output)
            console.print(f"picture written to {escape(str(output))}", highlight=False)
            return
        trajectory, regions = None, None
        if result_file is not None:
            doc = read_result(result_file)
            trajectory = trajectory_from_dict(doc, str(result_file))
            raw = doc.get("regions")
            if raw is not None:
                if not isinstance(raw, list) or not all(isinstance(r, int) and not isinstance(r, bool) for r in raw):
                    raise InvalidProblem(str(result_file), "regions", "expected a list of region indices")
                regions = tuple(raw)
    except PlansynthError as exc:
        raise fail(err, exc) from None
    abstraction = planner_abstraction(problem)
    if regions is not None and any(not 0 <= r < abstraction.n_regions for r in regions):
        err.print(
            f"[bold red]error:[/bold red] {escape(str(result_file))}: regions: indices outside 0..{abstraction.n_regions - 1}"
        )
        raise typer.Exit(EXIT_BAD_INPUT)
    try:
        plot_problem(problem, abstraction, regions, trajectory, path=output)
    except PlansynthError as exc:
        raise fail(err, exc) from None
    console.print(f"picture written to {escape(str(output))}", highlight=False)

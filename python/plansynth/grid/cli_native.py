"""`plansynth grid explain` and `plansynth grid minimize`: the native engine's own commands.

Registered on the `plansynth grid` app by :mod:`plansynth.grid.cli`. Thin shells over
:func:`plansynth.grid.native.explain.explain` and :func:`plansynth.grid.solve.solve`
with the native backend's ``minimize`` option.
"""

from __future__ import annotations

from pathlib import Path

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from plansynth.budget import Budget
from plansynth.cli_support import EXIT_BAD_INPUT, EXIT_NO, EXIT_UNKNOWN, EXIT_YES, positive_seconds
from plansynth.errors import PlansynthError
from plansynth.grid.problem import MAX_STEPS
from plansynth.io import check_output_path

EXIT_REALIZABLE, EXIT_UNREALIZABLE = EXIT_YES, EXIT_NO


def explain_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON)."),
    steps: int | None = typer.Option(
        None, "--steps", min=1, max=MAX_STEPS, help="Path length l to explain (default: the file's steps)."
    ),
    timeout: float = typer.Option(60.0, "--timeout", callback=positive_seconds, help="Wall-clock budget in seconds."),
    gif: Path | None = typer.Option(None, "--gif", help="Animate the obstacles' winning play into this GIF."),
) -> None:
    """Explain why no controller exists at path length l.

    Prints the obstacles' strategy that defeats every controller, played against the robot's most stubborn try (a witness of unrealizability, replayed with the spec's semantics), or says that controllers seeing the time would win but none seeing only positions does.

    Example: plansynth grid explain examples/grid/crossing.yaml --steps 7 --gif why.gif
    """
    from plansynth.grid.native.explain import check_witness_play, explain, relevant_summary
    from plansynth.grid.problem import load_grid_problem

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    try:
        problem = load_grid_problem(file)
        l = steps if steps is not None else problem.steps
        if l is None and problem.objective.bounded:
            raise typer.BadParameter("the file gives no steps: pass --steps", param_hint="--steps")
        if l is not None and not problem.objective.bounded:
            raise typer.BadParameter(f"objective {problem.objective.value} has no path length", param_hint="--steps")
        if gif is not None:
            check_output_path(gif)
        e = explain(problem, l, Budget(seconds=timeout))
    except PlansynthError as exc:
        err.print(f"[bold red]error:[/bold red] {escape(str(exc))}", highlight=False)
        raise typer.Exit(EXIT_BAD_INPUT) from None
    if problem.paper_model:
        console.print(f"l = {l}: {escape(relevant_summary(problem, l))}", highlight=False)
    else:
        console.print(f"objective {problem.objective.value}" + (f", l = {l}" if l is not None else ""), highlight=False)
    if e.kind == "realizable":
        console.print(f"[green]realizable[/green]: {escape(e.summary)}", highlight=False)
        raise typer.Exit(EXIT_REALIZABLE)
    if e.kind == "unknown":
        console.print(f"[yellow]unknown[/yellow]: {escape(e.summary)}", highlight=False)
        raise typer.Exit(EXIT_UNKNOWN)
    console.print(f"[red]unrealizable[/red]: {escape(e.summary)}", highlight=False)
    if e.kind == "game":
        names = [m.name for m in problem.robot.moves]
        table = Table(title="the obstacles' winning play against the robot's best try")
        for col in ("t", "robot", "obstacles", "robot move", "obstacle moves"):
            table.add_column(col)
        for turn in e.play:
            obs = " ".join(f"{c}" for c in turn.state.obstacles)
            omv = " ".join(problem.obstacles[i].moves[j].name for i, j in enumerate(turn.obstacle_moves))
            table.add_row(str(turn.t), str(turn.state.robot), obs, names[turn.robot_move], omv)
        console.print(table)
        console.print(escape(e.play[-1].reason), highlight=False)
        if problem.paper_model:
            ok = check_witness_play(problem, e.play, l)
        else:
            from plansynth.grid.native.product.witness import check_product_play

            ok = check_product_play(problem, e.play, e.loop, l)
        console.print(f"witness replayed with the spec's semantics: {'the robot loses' if ok else 'FAILED'}")
        if gif is not None:
            _animate(problem, e, gif, console)
    raise typer.Exit(EXIT_UNREALIZABLE)


def _animate(problem, e, gif: Path, console: Console) -> None:
    from plansynth.grid.native.animation import animate_play

    try:
        animate_play(problem, e, gif)
    except PlansynthError as exc:
        Console(stderr=True, soft_wrap=True).print(f"[bold red]error:[/bold red] {escape(str(exc))}", highlight=False)
        raise typer.Exit(EXIT_BAD_INPUT) from None
    console.print(f"animation written to {escape(str(gif))}", highlight=False)


def minimize_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON)."),
    steps: int | None = typer.Option(None, "--steps", min=1, max=MAX_STEPS, help="Solve for exactly this path length."),
    timeout: float | None = typer.Option(
        None, "--timeout", callback=positive_seconds, help="Wall-clock budget in seconds."
    ),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write the result JSON here."),
) -> None:
    """Synthesize a controller of smallest depth, proved minimal.

    Program depths 1, 4, 5, ... are tried in order over every winning strategy (the native engine with its minimize option, also available as: plansynth grid solve FILE -O minimize=true); the depth is reported minimal when every smaller depth was refuted with a complete enumeration of conditions.

    Example: plansynth grid minimize examples/grid/figure1.yaml
    """
    from dataclasses import replace

    from plansynth.grid.problem import load_grid_problem
    from plansynth.grid.programs import to_python
    from plansynth.grid.result import GridStatus
    from plansynth.grid.solve import solve

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    try:
        problem = load_grid_problem(file)
        if steps is not None:
            problem = replace(problem, steps=steps)
        if out is not None:
            check_output_path(out)
        result = solve(problem, "native", Budget(seconds=timeout), minimize=True)
    except PlansynthError as exc:
        err.print(f"[bold red]error:[/bold red] {escape(str(exc))}", highlight=False)
        raise typer.Exit(EXIT_BAD_INPUT) from None
    console.print(f"{result.status.value} ({result.seconds:.2f} s)", highlight=False)
    if result.status is GridStatus.REALIZABLE and result.program is not None:
        last = result.attempts[-1]
        proved = last.counters.get("minimal_depth_proved")
        console.print(
            f"l = {result.steps}, depth {result.depth} ({'proved minimal' if proved else 'not proved minimal'}), verified: {result.verified}"
        )
        console.print(f"  {escape(str(result.program))}", highlight=False)
        console.print(escape(to_python(result.program, problem.variables)).rstrip(), highlight=False)
    elif result.message:
        console.print(escape(result.message), highlight=False)
    if out is not None:
        try:
            result.write(out)
        except PlansynthError as exc:
            err.print(f"[bold red]error:[/bold red] {escape(str(exc))}", highlight=False)
            raise typer.Exit(EXIT_BAD_INPUT) from None
    code = {GridStatus.REALIZABLE: EXIT_REALIZABLE, GridStatus.UNREALIZABLE: EXIT_UNREALIZABLE}
    raise typer.Exit(code.get(result.status, EXIT_UNKNOWN))


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app``."""
    app.command("explain")(explain_command)
    app.command("minimize")(minimize_command)

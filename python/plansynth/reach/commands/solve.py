"""``plansynth reach solve``: plan with a planner under a budget, print the result
table, write the result file, picture and animation (STYLE.md, point 12)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.markup import escape

from plansynth.budget import Budget
from plansynth.cli_support import EXIT_NO as EXIT_INFEASIBLE
from plansynth.cli_support import EXIT_UNKNOWN, fail, positive_seconds, seconds_since_start
from plansynth.cli_support import EXIT_YES as EXIT_FOUND
from plansynth.errors import PlansynthError
from plansynth.io import check_output_path
from plansynth.reach.commands.common import MAX_HORIZON_OPTION
from plansynth.reach.commands.readings import given, mission_readings
from plansynth.reach.commands.results import result_table

#: seconds kept from --timeout for printing the result and exiting (as grid solve keeps)
EXIT_RESERVE = 0.5

SOLVE_EXAMPLES = """\
Examples:

  plansynth reach solve examples/reach/maze-3.yaml --out traj.json --plot traj.png

  plansynth reach solve examples/reach/maze-1.yaml --animate run.gif

  plansynth reach solve examples/reach/maze-2.yaml -O counterexample=trivial -O generalize=false --timeout 60

  plansynth reach solve examples/reach/cluttered.yaml --planner milp --max-horizon 60

  plansynth reach solve examples/reach/mission-patrol.yaml -O semantics=lasso

  plansynth reach solve examples/reach/mission-visit.yaml --reading sample --margin 0.2 --end free

  plansynth reach solve examples/reach/maze-3-windy.yaml --out plan.json --plot plan.png   # under a disturbance

  plansynth reach solve p.yaml --no-segment-safe        # the paper's guarantee: samples only

  plansynth reach solve examples/reach/claims/narrow-passage.yaml --prove   # its minimal horizon, for the problem

Exit status: 0 found (validated), 1 infeasible up to the max horizon, 2 bad input, 3 unknown (budget ran out).
"""


def planner_options_help() -> str:
    """Every planner's options for ``-O KEY=VALUE``, each with its default and its help
    line, read from the options values' field metadata (:mod:`plansynth.options`). The
    planners' entries and options modules are light: no solver loads. A planner whose
    options were listed before under another name (a named configuration, OMPL's three
    planners) is one line: what it may set, and its values that differ from the
    declared defaults."""
    from plansynth.options import describe, help_lines
    from plansynth.reach.planners import get_planner, planners

    blocks = [
        "Planner options (-O KEY=VALUE, repeatable; values true/false, none, numbers or text; dashes "
        "in keys are underscores):"
    ]
    listed: dict[type, str] = {}  # options class -> the first planner listed with it
    for name in planners():
        planner = get_planner(name)
        for mission, value in (
            (False, getattr(planner, "defaults", None)),
            (True, getattr(planner, "mission_defaults", None)),
        ):
            if value is None:
                continue
            title = f"{name}, for a problem with a mission" if mission and planner.defaults is not None else name
            settable = planner.option_names(mission=mission)
            if type(value) in listed:
                declared = {n: d for n, d, _ in describe(type(value))}
                own = [f"{n}={_shown(getattr(value, n))}" for n in declared if getattr(value, n) != declared[n]]
                blocks.append(
                    f"  {title}: {', '.join(settable)} (as {listed[type(value)]}"
                    + (f", with {', '.join(own)}" if own else "")
                    + ")"
                )
                continue
            listed[type(value)] = title
            rows = [line for line in help_lines(value) if line.split(" ", 1)[0] in settable]
            blocks.append("\n".join([f"  {title}:"] + [f"    {row}" for row in rows]))
    return "\n\n".join(blocks) + "\n"


def _shown(value: Any) -> str:
    return "none" if value is None else str(value).lower() if isinstance(value, bool) else str(value)


SOLVE_EPILOG = SOLVE_EXAMPLES + "\n" + planner_options_help()


#: ``reach solve`` flags that set an option every planner takes (parameter name -> flag)
_SHARED_FLAGS = {"max_horizon": "--max-horizon", "segment_safe": "--segment-safe/--no-segment-safe"}


def _planner_options(
    ctx: typer.Context, planner: str, items: list[str], paper: bool, mission: bool, prove: bool = False
) -> Any:
    """The planner's options value, built once from ``-O KEY=VALUE`` and the shared flags
    given (the flags win; ``--prove`` is ``-O prove=true``); an option the planner does not take is
    :class:`~plansynth.errors.InvalidOption` (exit 2, one line naming the planner and its
    options), never dropped. (For a mission ``--segment-safe`` is its reading: see
    :func:`mission_readings`.)"""
    from plansynth.options import parse_assignments
    from plansynth.reach.solve import configure

    values = parse_assignments(items, planner)
    flags = [n for n in _SHARED_FLAGS if not (mission and n == "segment_safe")]
    values.update({name: ctx.params[name] for name in flags if given(ctx, name)})
    if prove:
        if planner != "lazy-smt" or mission:
            raise typer.BadParameter(
                f"applies to the lazy-smt planner on a reach-avoid problem only, not {planner}"
                f"{' on a mission' if mission else ''} (-O prove=true)",
                param_hint="--prove",
            )
        values["prove"] = True
    base = None
    if paper:
        if planner != "lazy-smt" or mission:
            raise typer.BadParameter(
                f"applies to the lazy-smt planner on a reach-avoid problem only, not {planner}"
                f"{' on a mission' if mission else ''} (the paper's configurations are also "
                "planners: lazy-smt-paper, lazy-smt-paper-trivial)",
                param_hint="--paper",
            )
        from plansynth.reach.lazy.options import LazyOptions

        base = LazyOptions.paper()
    return configure(planner, base, mission=mission, **values)


def solve_command(
    ctx: typer.Context,
    file: Path = typer.Argument(..., help="Reach problem file (YAML or JSON, spec: reach-problem.md)."),
    planner: str = typer.Option(
        "lazy-smt",
        "--planner",
        "-p",
        help="lazy-smt (Algorithm 1 with our refinements), lazy-smt-window (without the timed route), lazy-smt-paper (as published), lazy-smt-paper-trivial, lazy-smt-zeroprefix, lazy-smt-minimal (horizon_search=minimal), milp, or a baseline: milp-bigm, rrt, est, kpiece, gcs (Drake's Graphs of Convex Sets; gcs-decomposition over our regions) and fpp (fast path planning through safe boxes): continuous-time curves; missions: lazy-smt, lazy-smt-minimal, milp-ltl, milp-ltl-oneshot; under a disturbance (robot.disturbance) the lazy-smt planners, milp, milp-bigm, the mission MILPs, and nominal-check (the nominal plan, then the robust check).",
    ),
    option: list[str] = typer.Option(
        [], "--option", "-O", help="A planner option KEY=VALUE, repeatable; each planner's options are listed below."
    ),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write the result JSON (spec: Result file) here."),
    plot: Path | None = typer.Option(None, "--plot", help="Draw regions, region sequence and trajectory to this PNG."),
    animate: Path | None = typer.Option(None, "--animate", help="Write an animated GIF of the trajectory."),
    timeout: float | None = typer.Option(
        None, "--timeout", callback=positive_seconds, help="Wall-clock budget in seconds (then status unknown)."
    ),
    max_horizon: int | None = typer.Option(
        None,
        "--max-horizon",
        min=0,
        max=MAX_HORIZON_OPTION,
        help="Largest horizon to try (overrides the file; at most 10,000; the option max_horizon every planner takes).",
    ),
    segment_safe: bool = typer.Option(
        True,
        "--segment-safe/--no-segment-safe",
        help="Keep whole segments in the regions (default), or only the samples (the paper; the option segment_safe).",
    ),
    paper: bool = typer.Option(
        False,
        "--paper",
        help="lazy-smt: start from the paper's loop and counterexamples (ZEROPREFIX, one horizon at a time, no refinements beyond the paper); the options given apply on top.",
    ),
    prove: bool = typer.Option(
        False,
        "--prove",
        help="lazy-smt: ask for claims about the problem: the horizon found proved minimal, or infeasible, for the problem, not only through the decomposition (the option prove; with exact_segments=auto, the default, a step may then cross several regions); within the budget.",
    ),
    reading: str | None = typer.Option(
        None,
        "--reading",
        help="Missions: read labels and obstacles along whole segments (segment, the default) or at the samples only (sample, as the discrete-time literature; --no-segment-safe selects it too). Overrides the file's mission.reading.",
    ),
    end: str | None = typer.Option(
        None,
        "--end",
        help="Missions: a finite plan ends at rest (rest, the default: its last labels hold forever) or free (the mission read on the finite word). Overrides the file's mission.end.",
    ),
    margin: float | None = typer.Option(
        None,
        "--margin",
        help="Missions: the label margin r: a label is visited at depth >= r and avoided at distance >= r (labels with their own margin in the file keep it). Overrides the file's mission.margin.",
    ),
    obstacle_margin: float | None = typer.Option(
        None,
        "--obstacle-margin",
        help="Missions: keep every obstacle at distance >= r too (each edge pushed out by r). Overrides the file's mission.obstacle_margin.",
    ),
) -> None:
    """Plan a trajectory: abstraction, then horizons in increasing order (SAT + LP)."""
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from plansynth.reach.solve import planners, solve
    from plansynth.reach.team.fileformat import load_problem

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    if planner not in planners():  # exit 2, naming every planner (all load on first use)
        raise typer.BadParameter(
            f"unknown planner {planner!r}; choose one of: {', '.join(planners())}", param_hint="--planner"
        )
    try:
        for path in (out, plot, animate):
            if path is not None:
                check_output_path(path)  # before solving: a result is never computed and then lost
        problem = load_problem(file)  # a team when the file has robots, separation or moving obstacles
        if getattr(problem, "robots", None) is not None:
            from plansynth.reach.team.solve import team_planner

            if paper:
                raise typer.BadParameter("applies to one robot, not a team", param_hint="--paper")
            planner = team_planner(planner)  # lazy-smt means lazy-smt-team on a team
        else:
            problem = mission_readings(ctx, problem, reading, end, margin, obstacle_margin)
        # an option the planner does not take, a planner this problem cannot use
        options = _planner_options(ctx, planner, option, paper, problem.mission is not None, prove)
    except PlansynthError as exc:
        raise fail(err, exc) from None
    with Progress(
        SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(), console=err, transient=True
    ) as bar:
        task = bar.add_task(f"{planner}: abstraction", total=None)

        def progress(horizon: int, iterations: int) -> None:
            bar.update(task, description=f"{planner}: horizon {horizon} ({iterations} iterations so far)")

        # the budget counts from the process's start, as grid solve's does (loading a large
        # problem file is part of the answer's time), less a reserve for printing and exiting
        left = None if timeout is None else max(timeout - seconds_since_start() - EXIT_RESERVE, 0.01)
        try:
            result = solve(problem, planner, Budget(seconds=left), options, progress=progress)
        except PlansynthError as exc:  # a planner this problem cannot use (gcs on a moving start, ...)
            raise fail(err, exc) from None
    console.print(result_table(result))
    try:
        _write_outputs(console, problem, result, out, plot, animate)
    except PlansynthError as exc:
        raise fail(err, exc) from None
    code = {"found": EXIT_FOUND, "infeasible": EXIT_INFEASIBLE}
    raise typer.Exit(code.get(result.status.value, EXIT_UNKNOWN))


def _write_outputs(
    console: Console, problem: Any, result: Any, out: Path | None, plot: Path | None, animate: Path | None
) -> None:
    """The result JSON, picture and animation of ``reach solve`` (each written atomically)."""
    if getattr(problem, "robots", None) is not None:  # a team (plansynth.reach.team.commands)
        from plansynth.reach.team.commands import write_outputs

        for line in write_outputs(problem, result, out, plot, animate):
            console.print(escape(line), highlight=False)
        return
    if out is not None:
        result.write(out)
        console.print(f"result written to {escape(str(out))}", highlight=False)
    if plot is None and animate is None:
        return
    from plansynth.reach.planner_regions import planner_abstraction
    from plansynth.reach.plot import animate as make_gif
    from plansynth.reach.plot import plot_problem

    abstraction = planner_abstraction(problem)
    if result.trajectory is None:  # the world the answer is about, titled with the answer
        if animate is not None:
            console.print("no trajectory to animate", highlight=False)
        if plot is not None:
            plot_problem(
                problem, abstraction, path=plot, title=f"{problem.name}: {result.solver}, {result.status.value}"
            )
            console.print(f"picture of the problem written to {escape(str(plot))} (no trajectory)", highlight=False)
        return
    if problem.disturbance is not None and plot is not None and getattr(result, "robust", None):
        from plansynth.reach.robust.picture import plot_robust

        plot_robust(problem, result, path=plot)
        console.print(f"picture written to {escape(str(plot))}", highlight=False)
        plot = None
    if plot is not None:
        plot_problem(
            problem,
            abstraction,
            result.regions,
            result.trajectory,
            path=plot,
            title=f"{problem.name}: {result.solver}, horizon {result.horizon}, {abstraction.n_regions} regions",
        )
        console.print(f"picture written to {escape(str(plot))}", highlight=False)
    if animate is not None:
        make_gif(problem, abstraction, result.trajectory, result.regions, animate)
        console.print(f"animation written to {escape(str(animate))}", highlight=False)

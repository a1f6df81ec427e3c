"""``plansynth reach`` sub-commands: a thin shell over :func:`plansynth.reach.solve`,
:func:`plansynth.reach.validate` and :mod:`plansynth.reach.plot` (STYLE.md, point 12).

Exit status of ``solve``: 0 found (validated trajectory), 1 infeasible, 2 bad input,
3 unknown (budget ran out, or a trajectory failed validation).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from plansynth.budget import Budget
from plansynth.cli_support import EXIT_BAD_INPUT, EXIT_UNKNOWN, fail, positive_seconds, seconds_since_start
from plansynth.cli_support import EXIT_NO as EXIT_INFEASIBLE
from plansynth.cli_support import EXIT_YES as EXIT_FOUND
from plansynth.errors import InvalidOption, InvalidProblem, PlansynthError
from plansynth.io import check_output_path

app = typer.Typer(no_args_is_help=True, add_completion=False)

#: seconds kept from --timeout for printing the result and exiting (as grid solve keeps)
EXIT_RESERVE = 0.5

#: plansynth.reach.problem's MAX_HORIZON and MAX_ORDER, repeated so that this module
#: loads without numpy (a test checks that they agree).
MAX_HORIZON_OPTION, MAX_ORDER_OPTION = 10_000, 50

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

VALIDATE_EPILOG = """\
Examples:

  plansynth reach validate examples/reach/maze-3.yaml traj.json

  plansynth reach validate examples/reach/maze-3.yaml traj.json --segment-safe

  plansynth reach validate examples/reach/maze-3-windy.yaml plan.json --disturbances 1000 --nominal

A problem with a disturbance (robot.disturbance): the plan is also checked against the
worst case at every step, with the gain K the result records (else the problem's
design); --disturbances N simulates the closed loop under N random and N vertex
disturbance sequences; --nominal runs a nominal plan under the same sequences.

Exit status: 0 valid, 1 invalid, 2 bad input.
"""

PLOT_EPILOG = """\
Examples:

  plansynth reach plot examples/reach/cluttered.yaml -o regions.png

  plansynth reach plot examples/reach/maze-3.yaml traj.json -o traj.png
"""

_STYLE = {"found": "bold green", "infeasible": "bold red", "unknown": "bold yellow"}


def _read_result(path: Path) -> dict[str, Any]:
    from plansynth.io import load_document

    doc, name = load_document(path)
    if not isinstance(doc, dict):
        raise InvalidProblem(name, "<document>", "a result file must be a JSON object")
    return doc


def _result_table(result: Any) -> Table:
    c, t = result.counters, result.timings
    table = Table(title=f"{result.solver}: {result.status.value}", show_header=False, title_justify="left")
    table.add_column("item", style="bold")
    table.add_column("value")
    style = _STYLE[result.status.value]
    table.add_row("status", f"[{style}]{result.status.value}[/{style}]")
    horizon = "-" if result.horizon is None else str(result.horizon)
    if result.status.value == "infeasible":
        horizon = f"none up to {result.horizon}"
    if result.status.value == "found" and c.get("minimal") is not None:
        relative = c.get("minimal_relative_to", "problem")  # (planners that do not say: as before)
        if c["minimal"] and relative != "problem":
            horizon += f" (minimal through the {relative} only)"
        else:
            horizon += " (proved minimal)" if c["minimal"] else " (not proved minimal)"
    table.add_row("horizon", horizon)
    for key in (
        "regions",
        "first_horizon",
        "iterations",
        "sat_calls",
        "lp_calls",
        "transit_conflicts",
        "clauses",
        "milp_calls",
        "mip_nodes",
    ):
        if key in c and c[key] is not None:
            table.add_row(key.replace("_", " "), str(c[key]))
    if c.get("lp_calls_by_kind"):
        table.add_row("LP calls by kind", ", ".join(f"{k} {v}" for k, v in c["lp_calls_by_kind"].items()))
    phases = [
        k
        for k in (
            "tighten",
            "abstraction",
            "bounds",
            "guide",
            "sat",
            "lp",
            "milp",
            "validate",
            "mission_check",
            "robust_check",
        )
        if k in t
    ]
    table.add_row("time per phase", ", ".join(f"{k} {t[k]:.3f} s" for k in phases))
    table.add_row("total time", f"{result.seconds:.3f} s")
    if result.solver_version:
        table.add_row("solver", escape(f"{result.solver} ({result.solver_version})"))
    if result.validated is not None:
        table.add_row("validated", "[green]yes[/green]" if result.validated else "[red]NO[/red]")
    if result.guarantee is not None:
        held = (
            "" if result.segment_safe is None else (", segments safe" if result.segment_safe else ", segments NOT safe")
        )
        table.add_row("guarantee", f"{result.guarantee}{held}")
    mission = getattr(result, "mission", None)
    if mission and mission.get("semantics"):  # LTL missions
        loop = "" if mission.get("loop_start") is None else f", loop from step {mission['loop_start']} (x_N = x_k)"
        verdict = {True: ", mission checked", False: ", mission check FAILED"}.get(mission.get("ok"), "")
        end = ", free end" if mission.get("semantics") == "finite" and mission.get("end") == "free" else ""
        table.add_row("mission", escape(f"{mission['formula']}: {mission['semantics']} plan{end}{loop}{verdict}"))
        margins = {n: r for n, r in (mission.get("margins") or {}).items() if r}
        asked = ", ".join(f"{n} {r:g}" for n, r in margins.items()) or "none"
        achieved = mission.get("robustness")
        table.add_row(
            "reading",
            escape(
                f"{mission.get('reading', 'segment')}; margins asked: {asked}; achieved margin: "
                + ("-" if achieved is None else f"{achieved:.4g}")
            ),
        )
    robust = getattr(result, "robust", None)
    if robust:  # under a disturbance (plansynth.reach.robust)
        for key, value in _robust_rows(robust, result.status.value == "found"):
            table.add_row(key, escape(value))
    if result.message:
        table.add_row("message", escape(result.message))
    return table


def _robust_rows(robust: dict[str, Any], found: bool) -> list[tuple[str, str]]:
    """The lines of a robust result: what it guarantees (or what a missing plan is
    relative to), the feedback law and gain, the margins, the worst-case check."""
    fb, mg = robust["feedback"], robust["margins"]
    gain = "; ".join(", ".join(f"{v + 0.0:.4g}" for v in row) for row in fb["gain"])
    grown = [max(a, b) for a, b in zip(mg["obstacles_grown_by"]["lo"], mg["obstacles_grown_by"]["hi"])]
    u = max([*mg["input_bound_at_most"]["lo"], *mg["input_bound_at_most"]["hi"]], default=0.0)
    rows = [
        ("robust", robust["guarantee"] if found else robust["relative_to"]),
        ("feedback", f"{robust['law']}, K = [{gain}]: {fb['how']}"),
        (
            "margins",
            "obstacles grown by "
            + ", ".join(f"{v:.4g}" for v in grown)
            + f" (the tube's largest cross-section); state bounds, workspace, input bound (by up to {u:.4g}) "
            f"and goal tightened by E_t at every step (exact for {mg['exact_steps']} steps, then bounded)",
        ),
    ]
    check = robust.get("check")
    if check is not None:
        verdict = "passed" if check["ok"] else "FAILED"
        room = "" if check.get("clearance") is None else f", worst-case clearance {check['clearance']:.3g}"
        rows.append(("robust check", f"{verdict}: the worst case at every step{room}"))
    return rows


#: ``reach solve`` flags that set an option every planner takes (parameter name -> flag)
_SHARED_FLAGS = {"max_horizon": "--max-horizon", "segment_safe": "--segment-safe/--no-segment-safe"}


def _given(ctx: typer.Context, name: str) -> bool:
    """Was the parameter ``name`` given on the command line (not left at its default)?"""
    source = ctx.get_parameter_source(name)
    return source is not None and source.name not in ("DEFAULT", "DEFAULT_MAP")


def _mission_readings(
    ctx: typer.Context | None,
    problem: Any,
    reading: str | None,
    end: str | None,
    margin: float | None,
    obstacle_margin: float | None,
) -> Any:
    """The problem with the mission's reading, end and margins the command line sets
    (checked like the file's: an :class:`~plansynth.errors.InvalidProblem` naming the
    field). For a mission, ``--no-segment-safe`` is the sample reading (and
    ``--segment-safe`` the segment one): the one choice planners and checker share."""
    from dataclasses import replace

    values: dict[str, Any] = {}
    if ctx is not None and _given(ctx, "segment_safe") and problem.mission is not None:
        implied = "segment" if ctx.params["segment_safe"] else "sample"
        if reading is not None and reading != implied:
            raise typer.BadParameter(
                f"--reading {reading} and --{'no-' if implied == 'sample' else ''}segment-safe disagree "
                "(for a mission, --no-segment-safe is the sample reading)",
                param_hint="--reading",
            )
        values["reading"] = implied
    for key, value in (("reading", reading), ("end", end), ("margin", margin), ("obstacle_margin", obstacle_margin)):
        if value is not None:
            values[key] = value
    return replace(problem, **values) if values else problem


def _planner_options(ctx: typer.Context, planner: str, items: list[str], paper: bool, mission: bool) -> Any:
    """The planner's options value, built once from ``-O KEY=VALUE`` and the shared flags
    given (the flags win); an option the planner does not take is
    :class:`~plansynth.errors.InvalidOption` (exit 2, one line naming the planner and its
    options), never dropped. (For a mission ``--segment-safe`` is its reading: see
    :func:`_mission_readings`.)"""
    from plansynth.options import parse_assignments
    from plansynth.reach.solve import configure

    values = parse_assignments(items, planner)
    flags = [n for n in _SHARED_FLAGS if not (mission and n == "segment_safe")]
    values.update({name: ctx.params[name] for name in flags if _given(ctx, name)})
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


@app.command("solve", epilog=SOLVE_EPILOG)
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
            problem = _mission_readings(ctx, problem, reading, end, margin, obstacle_margin)
        # an option the planner does not take, a planner this problem cannot use
        options = _planner_options(ctx, planner, option, paper, problem.mission is not None)
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
    console.print(_result_table(result))
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
    if (plot is not None or animate is not None) and result.trajectory is not None:
        from plansynth.reach.abstraction import abstract
        from plansynth.reach.plot import animate as make_gif
        from plansynth.reach.plot import plot_problem

        if problem.disturbance is not None:  # the regions of the tightened problem (plansynth.reach.robust)
            from plansynth.reach.robust.picture import plot_robust, robust_abstraction

            abstraction = robust_abstraction(problem)
            if plot is not None and getattr(result, "robust", None):
                plot_robust(problem, result, path=plot)
                console.print(f"picture written to {escape(str(plot))}", highlight=False)
                plot = None
        elif problem.mission is not None:  # missions plan in the label-refined regions
            from plansynth.reach.mission.labels import label_abstraction

            abstraction = label_abstraction(problem).abstraction
        else:
            from plansynth.reach.robot import configuration_space

            abstraction = abstract(configuration_space(problem))  # the regions the planner saw
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
    elif plot is not None or animate is not None:
        console.print("no trajectory to draw", highlight=False)


@app.command("validate", epilog=VALIDATE_EPILOG)
def validate_command(
    file: Path = typer.Argument(..., help="Reach problem file."),
    result_file: Path = typer.Argument(..., help="Result JSON with states and inputs."),
    segment_safe: bool = typer.Option(
        False, "--segment-safe", help="Also require every segment to avoid the obstacles."
    ),
    tol: float = typer.Option(1e-6, "--tol", help="Tolerance of every check."),
    dynamics: str | None = typer.Option(
        None,
        "--dynamics",
        help="exact (x' = A x + B u required) or curve (samples of a continuous-time curve: the dynamics residual is reported, not required); default: curve for a result whose guarantee is curve (gcs), else exact. A mission's plan is checked exactly.",
    ),
    reading: str | None = typer.Option(
        None, "--reading", help="Missions: check in this reading (segment or sample) instead of the file's."
    ),
    end: str | None = typer.Option(
        None, "--end", help="Missions: a finite plan's end (rest or free) instead of the file's."
    ),
    margin: float | None = typer.Option(None, "--margin", help="Missions: the label margin instead of the file's."),
    obstacle_margin: float | None = typer.Option(
        None, "--obstacle-margin", help="Missions: the obstacle margin instead of the file's."
    ),
    disturbances: int = typer.Option(
        0,
        "--disturbances",
        min=0,
        max=1_000_000,
        help="A problem with a disturbance: also simulate the closed loop under this many random and this many vertex disturbance sequences.",
    ),
    seed: int = typer.Option(0, "--seed", min=0, help="The disturbance sequences' random seed."),
    nominal: bool = typer.Option(
        False,
        "--nominal",
        help="With --disturbances: also plan the problem without its disturbance (lazy-smt) and run that plan, with the same gain, under the same sequences.",
    ),
) -> None:
    """Check a trajectory against a problem with the independent validator (and a
    mission's plan with the mission checker, which reports the achieved margin; a team's
    plan with the team validator)."""
    from plansynth.reach.team.fileformat import load_problem
    from plansynth.reach.trajectory import trajectory_from_dict
    from plansynth.reach.validate import tolerance_problem, validate

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    if dynamics is not None and dynamics not in ("exact", "curve"):
        raise typer.BadParameter("must be exact or curve", param_hint="--dynamics")
    try:
        problem = load_problem(file)
        if getattr(problem, "robots", None) is None:
            problem = _mission_readings(None, problem, reading, end, margin, obstacle_margin)
        doc = _read_result(result_file)
        if getattr(problem, "robots", None) is not None:  # a team: the team validator
            from plansynth.reach.team.commands import validate_file

            why = tolerance_problem(problem.robot_problems[0], tol)
            if why is not None:
                raise typer.BadParameter(why, param_hint="--tol")
            ok, lines = validate_file(problem, doc, str(result_file), tol=tol)
            for line in lines:
                console.print(escape(line), highlight=False)
            raise typer.Exit(0 if ok else 1)
        trajectory = trajectory_from_dict(doc, str(result_file))
        claim = doc.get("segment_safe")
        if claim is not None and not isinstance(claim, bool):
            raise InvalidProblem(str(result_file), "segment_safe", f"expected true or false, got {claim!r}")
        if problem.mission is not None:
            from plansynth.reach.mission.check import check_result_mission

            check_result_mission(doc, trajectory.horizon, str(result_file))
    except PlansynthError as exc:
        raise fail(err, exc) from None
    if problem.mission is not None and dynamics == "curve":
        raise typer.BadParameter(
            "a mission's plan is a trajectory of the exact dynamics (curve: reach-avoid results only)",
            param_hint="--dynamics",
        )
    why = tolerance_problem(problem, tol)
    if why is not None:
        raise typer.BadParameter(why, param_hint="--tol")
    # a claim in the file is checked: a file that says segment_safe must be segment-safe
    claimed = claim is True or doc.get("guarantee") == "segments"
    if claimed and not segment_safe:
        console.print("the result claims segment safety: segments are checked too", highlight=False)
    if disturbances and problem.disturbance is None:
        raise typer.BadParameter("the problem has no disturbance (robot.disturbance)", param_hint="--disturbances")
    if nominal and not disturbances:
        raise typer.BadParameter("needs --disturbances", param_hint="--nominal")
    if problem.mission is not None:  # LTL missions: validator + mission checker
        from plansynth.reach.mission.check import validate_mission_file

        planned = doc.get("mission") or {}
        for key in ("reading", "end"):
            if planned.get(key) not in (None, getattr(problem, key)):
                console.print(
                    f"the plan was made with {key} {planned[key]!s}; it is checked with {key} "
                    f"{getattr(problem, key)} (--{key} {planned[key]!s} checks it as it was made)",
                    highlight=False,
                    markup=False,
                )
        ok, lines = validate_mission_file(problem, trajectory, doc, segment_safe=segment_safe or claimed, tol=tol)
        for line in lines:
            console.print(line, highlight=False)
        if problem.disturbance is not None:
            ok = (
                _validate_robust(console, err, problem, trajectory, doc, result_file, tol, disturbances, seed, nominal)
                and ok
            )
        raise typer.Exit(0 if ok else 1)
    if dynamics is None:
        dynamics = "curve" if doc.get("guarantee") == "curve" else "exact"
    report = validate(problem, trajectory, require_segment_safe=segment_safe or claimed, tol=tol, dynamics=dynamics)
    if dynamics == "curve":
        console.print(
            "dynamics: curve (the samples of a continuous-time curve; x' = A x + B u is not required)", highlight=False
        )
    style = "bold green" if report.ok else "bold red"
    console.print(
        f"[{style}]{'valid' if report.ok else 'INVALID'}[/{style}]: {escape(report.summary())}", highlight=False
    )
    for v in report.violations[:50]:
        console.print(f"  {escape(str(v))}", highlight=False)
    if len(report.violations) > 50:
        console.print(f"  ... and {len(report.violations) - 50} more", highlight=False)
    ok = report.ok
    if problem.disturbance is not None:
        ok = (
            _validate_robust(console, err, problem, trajectory, doc, result_file, tol, disturbances, seed, nominal)
            and ok
        )
    raise typer.Exit(0 if ok else 1)


def _validate_robust(
    console: Console,
    err: Console,
    problem: Any,
    trajectory: Any,
    doc: dict[str, Any],
    result_file: Path,
    tol: float,
    disturbances: int,
    seed: int,
    nominal: bool,
) -> bool:
    """``reach validate`` on a problem with a disturbance: the worst case at every step
    with the result's gain (else the problem's design), then the sampled runs."""
    import numpy as np

    from plansynth.reach.robust.check import check_robust
    from plansynth.reach.robust.simulate import simulate
    from plansynth.reach.robust.tighten import robust_design

    try:
        K, source = _result_gain(doc, str(result_file), problem)
        if K is None:
            K, source = robust_design(problem).K, "the problem's feedback design"
    except PlansynthError as exc:
        raise fail(err, exc) from None
    mission = doc.get("mission") if isinstance(doc.get("mission"), dict) else {}
    loop = mission.get("loop_start")
    if loop is None and mission.get("semantics") == "finite":
        loop = trajectory.horizon
    segments = doc.get("guarantee", "segments") != "samples"
    report = check_robust(problem, trajectory, K, tol=tol, loop_start=loop, segments=segments)
    gain = "; ".join(", ".join(f"{v + 0.0:.4g}" for v in row) for row in np.asarray(K))
    console.print(f"feedback: u = v + K (x - x_nom), K = [{gain}] ({source})", highlight=False)
    style = "bold green" if report.ok else "bold red"
    console.print(
        f"[{style}]{'robust' if report.ok else 'NOT robust'}[/{style}]: {escape(report.summary())}", highlight=False
    )
    for v in report.violations[:20]:
        console.print(f"  {escape(str(v))}", highlight=False)
    for note in report.notes:
        console.print(f"  note: {escape(note)}", highlight=False)
    ok = report.ok
    if disturbances:
        runs = simulate(problem, trajectory, K, sequences=disturbances, seed=seed, tol=tol, loop_start=loop)
        style = "bold green" if runs.violated == 0 else "bold red"
        console.print(f"[{style}]simulated[/{style}]: {escape(runs.summary())}", highlight=False)
        ok = ok and runs.violated == 0
        if nominal:
            _nominal_runs(console, problem, K, disturbances, seed, tol)
    return ok


def _result_gain(doc: dict[str, Any], name: str, problem: Any) -> tuple[Any, str]:
    """The gain K a result file records (``robust.feedback.gain``), checked; (None, "")
    when it records none."""
    import numpy as np

    robust = doc.get("robust")
    if robust is None:
        return None, ""
    try:
        K = np.array(robust["feedback"]["gain"], dtype=float)
    except (KeyError, TypeError, ValueError):
        raise InvalidProblem(name, "robust.feedback.gain", "expected the gain K as a list of rows of numbers") from None
    m, n = problem.dynamics.n_inputs, problem.dynamics.n_states
    if K.shape != (m, n) or not np.all(np.isfinite(K)):
        raise InvalidProblem(name, "robust.feedback.gain", f"expected an {m} x {n} matrix of finite numbers")
    return K, "the result's"


def _nominal_runs(console: Console, problem: Any, K: Any, disturbances: int, seed: int, tol: float) -> None:
    """A nominal plan (lazy-smt, the disturbance ignored) under the same sequences."""
    from dataclasses import replace

    from plansynth.reach.robust.simulate import simulate
    from plansynth.reach.solve import solve

    plain = replace(problem, disturbance=None)
    result = solve(plain, "lazy-smt", Budget(seconds=60.0))
    if result.trajectory is None:
        console.print(f"nominal plan: none ({escape(result.message)})", highlight=False)
        return
    runs = simulate(
        problem,
        result.trajectory,
        K,
        sequences=disturbances,
        seed=seed,
        tol=tol,
        loop_start=(result.mission or {}).get("loop_start"),
    )
    kinds = ", ".join(f"{k} in {v}" for k, v in runs.kinds_violated.items())
    console.print(
        f"nominal plan (horizon {result.horizon}, the disturbance ignored), same gain and sequences: "
        f"{escape(runs.summary())}" + (f"; runs with each violation: {escape(kinds)}" if kinds else ""),
        highlight=False,
    )


def configuration_space_of(problem: Any) -> Any:
    """The point-robot problem of ``problem`` (:func:`plansynth.reach.robot.configuration_space`)."""
    from plansynth.reach.robot import configuration_space

    return configuration_space(problem)


@app.command("plot", epilog=PLOT_EPILOG)
def plot_command(
    file: Path = typer.Argument(..., help="Reach problem file."),
    result_file: Path | None = typer.Argument(None, help="Optional result JSON (trajectory and regions)."),
    output: Path = typer.Option(..., "--output", "-o", help="PNG file to write."),
) -> None:
    """Draw the workspace, the convex regions and (with a result) the trajectory."""
    from plansynth.reach.abstraction import abstract
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

            doc = None if result_file is None else _read_result(result_file)
            plot_file(problem, doc, None if result_file is None else str(result_file), output)
            console.print(f"picture written to {escape(str(output))}", highlight=False)
            return
        trajectory, regions = None, None
        if result_file is not None:
            doc = _read_result(result_file)
            trajectory = trajectory_from_dict(doc, str(result_file))
            raw = doc.get("regions")
            if raw is not None:
                if not isinstance(raw, list) or not all(isinstance(r, int) and not isinstance(r, bool) for r in raw):
                    raise InvalidProblem(str(result_file), "regions", "expected a list of region indices")
                regions = tuple(raw)
    except PlansynthError as exc:
        raise fail(err, exc) from None
    if problem.disturbance is not None:  # the regions of the tightened problem (plansynth.reach.robust)
        from plansynth.reach.robust.picture import robust_abstraction

        abstraction = robust_abstraction(problem)
        if abstraction is None:
            abstraction = abstract(configuration_space_of(problem))
    elif problem.mission is not None:  # missions plan in the label-refined regions
        from plansynth.reach.mission.labels import label_abstraction

        abstraction = label_abstraction(problem).abstraction
    else:
        abstraction = abstract(configuration_space_of(problem))  # the regions the planners see
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


__all__ = ["app"]


TABLE_EPILOG = """\
Examples:

  plansynth reach table                                   # maze-1..4, double integrator, defaults

  plansynth reach table --mazes 1,2 -c zeroprefix -c trivial -c iis -O generalize=false --timeout 120

  plansynth reach table --mazes 1,2 -O generalize=false -O slack_weights=uniform   # the paper's method as published

  plansynth reach table --mazes 4 --order 25 --timeout 600  # the scalability study (n = 50 states)

Times are wall clock and process CPU seconds of the whole solve (abstraction, bounds,
SAT, LP, validation); on a shared machine the CPU column is the steadier one. The
options -O sets are lazy-smt's (see plansynth reach solve --help).
"""


@app.command("table", epilog=TABLE_EPILOG)
def table_command(
    mazes: str = typer.Option("1,2,3,4", "--mazes", help="Comma-separated passage counts."),
    order: int = typer.Option(
        2, "--order", min=1, max=MAX_ORDER_OPTION, help="Integrators per axis (2: the paper's double integrator)."
    ),
    counterexample: list[str] = typer.Option(
        ["zeroprefix"],
        "--counterexample",
        "-c",
        help="Counterexample strategies to compare, one row each (repeatable).",
    ),
    option: list[str] = typer.Option(
        [],
        "--option",
        "-O",
        help="Another lazy-smt option KEY=VALUE for every row, repeatable (generalize, minimize, slack_weights, ...).",
    ),
    timeout: float = typer.Option(120.0, "--timeout", callback=positive_seconds, help="Budget per solve in seconds."),
) -> None:
    """Solve the paper's maze family (Section VI, Table I and Figure 4) and print the
    time of each phase and the SAT/LP call counts, one row per maze and strategy."""
    import time

    from plansynth.options import parse_assignments
    from plansynth.reach.families import maze
    from plansynth.reach.solve import configure, solve

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    if not console.is_terminal:
        console = Console(width=160)
    try:
        ns = [int(x) for x in mazes.split(",") if x.strip()]
    except ValueError:
        raise typer.BadParameter("expected comma-separated integers", param_hint="--mazes") from None
    try:  # every row's options, checked before the first solve
        values = parse_assignments(option, "lazy-smt")
        if "counterexample" in values:
            raise InvalidOption("lazy-smt", "counterexample", "the strategies compared are given by -c")
        rows = [configure("lazy-smt", counterexample=ce, **values) for ce in counterexample]
    except PlansynthError as exc:
        raise fail(err, exc) from None
    table = Table(title=f"maze-n, integrator chains of order {order} ({2 * order} states)")
    for col in (
        "maze",
        "strategy",
        "status",
        "horizon",
        "abstraction s",
        "SAT s",
        "LP s",
        "total s",
        "CPU s",
        "iterations",
        "SAT calls",
        "LP calls",
    ):
        table.add_column(col, justify="right" if col not in ("strategy", "status") else "left")
    for n in ns:
        problem = maze(n, order=order)
        for opts in rows:
            c0 = time.process_time()
            r = solve(problem, "lazy-smt", Budget(seconds=timeout), opts)
            cpu = time.process_time() - c0
            t, c = r.timings, r.counters
            style = _STYLE[r.status.value]
            strategy = (
                opts.counterexample
                + ("+gen" if opts.generalize else "")
                + ("+min" if opts.generalize and opts.minimize else "")
            )
            table.add_row(
                str(n),
                strategy,
                f"[{style}]{r.status.value}[/{style}]",
                str(r.horizon),
                f"{t.get('abstraction', 0):.3f}",
                f"{t.get('sat', 0):.3f}",
                f"{t.get('lp', 0):.3f}",
                f"{r.seconds:.3f}",
                f"{cpu:.3f}",
                str(c.get("iterations")),
                str(c.get("sat_calls")),
                str(c.get("lp_calls")),
            )
    console.print(table)

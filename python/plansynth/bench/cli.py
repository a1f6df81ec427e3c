"""`plansynth bench` sub-commands: thin shells over :mod:`plansynth.bench` (STYLE.md, point 12)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import typer
from rich.console import Console

app = typer.Typer(no_args_is_help=True, add_completion=False)
console = Console()

DB_OPTION = typer.Option(
    Path("bench-results.db"), "--db", help="SQLite results database (created if absent; resumed if present)."
)

GRID_EPILOG = """\
Examples:

  plansynth bench grid --family steps --solvers native,cvc5 --timeout 300 --repeat 3

  plansynth bench grid --family obstacles --values 5,10,15 --solvers native --db out/grid.db

  plansynth bench grid --family all --solvers native,cvc5 --timeout 60 --cluster tcp://10.0.0.5:8786

  plansynth bench grid --family depth --solvers native,external -O "external:command=cvc5 --lang=sygus2 {file}"

  plansynth bench grid --family moving-obstacle --values 8,16,24 --solvers native,omega --timeout 600

Families: figure1, depth, steps, obstacles, dimensions (the paper's), crossing, crossing-stall, patrol, patrol-walk, door, door-stall, lanes, lanes-rush, doors, doors-rush, doors-jam, patrols, patrols-walk (reactive, ours), reactive-suite (the shared suite; it, doors* and patrols* run through the CLI), moving-obstacle, robot-grid, robot-grid-fast (SYNTCOMP's robot benchmarks; --values are grid sizes, map numbers), or all.
Solvers: the grid backends (native, cvc5, external) and the peer omega (safety and recurrence games only).
Rerunning the same command resumes: runs already in the database are skipped.
"""

REACH_EPILOG = """\
Examples:

  plansynth bench reach --family maze --planners lazy-smt,rrt,milp --repeat 5

  plansynth bench reach --family chain --values 1,2 --orders 1,2,5,10 --planners lazy-smt --timeout 120

  plansynth bench reach --family random --values 0,1,2 --planners lazy-smt,rrt,milp-bigm
  plansynth bench reach --family missions --planners lazy-smt,milp-ltl --timeout 120

  plansynth bench reach --family maze --planners lazy-smt,gcs --repeat 3

  plansynth bench reach --family random-dynamics --values 1,2,3,4 --states 4,10,50 --planners lazy-smt

  plansynth bench reach --family team --planners lazy-smt-team,milp-team,prioritized

  plansynth bench reach --family robust --values 3,4 --planners lazy-smt,milp-bigm,nominal-check --timeout 300

Families: maze (Table I), chain (Figure 4: integrator chains, 2k states), random-dynamics
(Figure 4 with random controllable A, B of n states), random, missions (LTL missions on
the mazes: use --planners lazy-smt,milp-ltl,milp-ltl-oneshot), gcs-maze, robust (the mazes
under bounded disturbances: lazy-smt, milp-bigm on the same tightened problem,
nominal-check, and milp-ltl for its mission; --values windy-swap: a team under
disturbances, --planners lazy-smt-team,milp-team), team (teams of robots and moving obstacles:
--planners lazy-smt-team,milp-team,prioritized; --values are case names, e.g.
smc-crossing), or all.
Planners: lazy-smt, milp (region-graph MILP), milp-bigm (one-shot big-M MILP, the paper's LTL OPT stand-in), rrt, est, kpiece (OMPL).
"""


def _split(text: str) -> list[str]:
    return [t.strip() for t in text.split(",") if t.strip()]


def _options(items: list[str]) -> dict[str, dict[str, str]]:
    """``solver:key=value`` items -> {solver: {key: value}}."""
    out: dict[str, dict[str, str]] = {}
    for item in items:
        solver, sep, kv = item.partition(":")
        key, eq, value = kv.partition("=")
        if not (sep and eq and solver and key):
            console.print(f"[red]bad --option {item!r}: expected SOLVER:KEY=VALUE")
            raise typer.Exit(2)
        out.setdefault(solver, {})[key] = value
    return out


def _refuse(option: str, reason: str) -> None:
    """One line naming the option and the reason; exit 2 before anything is written."""
    console.print(f"[red]error: {option}: {reason}", highlight=False, soft_wrap=True)
    raise typer.Exit(2)


def _known_solvers(kind: str) -> list[str]:
    if kind == "grid":
        from plansynth.bench.execute.omega import GRID_PEERS
        from plansynth.grid.result import backend_names

        return list(backend_names()) + list(GRID_PEERS)
    from plansynth.bench.solvers import REACH_ORDER
    from plansynth.reach.solve import planners

    return list(dict.fromkeys([*REACH_ORDER, *planners()]))


def _check_arguments(
    kind: str, solvers: list[str], *, timeout: float, repeat: int, jobs: int, memory: int, orders: list[int]
) -> None:
    """Validate a sweep's arguments at the door (STYLE.md, point 2)."""
    import math

    flag = "--solvers" if kind == "grid" else "--planners"
    if not solvers:
        _refuse(flag, "give at least one name")
    from plansynth.bench.execute import DEBUG_SOLVERS

    known = _known_solvers(kind)
    for name in solvers:
        if name not in known and name not in DEBUG_SOLVERS:
            _refuse(
                flag, f"unknown {'grid solver' if kind == 'grid' else 'planner'} {name!r} (known: {', '.join(known)})"
            )
    if not (math.isfinite(timeout) and timeout > 0):
        _refuse("--timeout", f"must be a positive number of seconds, got {timeout}")
    if memory < 1:
        _refuse("--memory", f"must be a positive number of MB, got {memory}")
    if repeat < 1:
        _refuse("--repeat", f"must be at least 1, got {repeat}")
    if jobs < 1:
        _refuse("--jobs", f"must be at least 1, got {jobs}")
    if any(k < 1 for k in orders):
        _refuse("--orders", f"chain orders must be at least 1, got {','.join(map(str, orders))}")


def _check_mission_planners(families: list[str], solvers: list[str]) -> None:
    """A family with LTL missions needs mission planners, the others reach-avoid
    planners: a planner that cannot plan a family's problems is refused at the door."""
    from plansynth.bench.execute import DEBUG_SOLVERS
    from plansynth.bench.families.reach import MISSION_FAMILIES
    from plansynth.reach.planners import get_planner

    for name in solvers:
        if name in DEBUG_SOLVERS:
            continue
        planner = get_planner(name)
        for f in families:
            mission = f in MISSION_FAMILIES
            takes = getattr(planner, "mission_defaults" if mission else "defaults", None) is not None
            if not takes:
                what = "plans no LTL missions" if mission else "plans LTL missions only"
                _refuse("--planners", f"{name} {what}, and family {f!r} {'has' if mission else 'has no'} missions")


def _sweep(
    kind: str,
    families: list[str],
    values: str | None,
    solvers: list[str],
    *,
    orders: list[int],
    timeout: float,
    repeat: int,
    db: Path,
    jobs: int,
    memory: int,
    cluster: str | None,
    seed: int,
    retry: str = "",
    options: list[str] | None = None,
    states: list[int] | None = None,
) -> None:
    from plansynth.bench.families import GRID_FAMILIES, REACH_FAMILIES, family
    from plansynth.bench.runner import run_sweep
    from plansynth.bench.tasks import make_tasks

    _check_arguments(kind, solvers, timeout=timeout, repeat=repeat, jobs=jobs, memory=memory, orders=orders)

    known = list(GRID_FAMILIES) if kind == "grid" else list(REACH_FAMILIES)
    every = families == ["all"]
    if every:
        families = known
    insts = []
    vals = None if values is None else [int(v) if v.lstrip("-").isdigit() else v for v in _split(values)]
    for f in families:
        if f not in known:
            console.print(f"[red]unknown {kind} family {f!r}; choose from {', '.join(known)} or all")
            raise typer.Exit(2)
        kw: dict = {"orders": orders} if kind == "reach" else {}
        if kind == "reach" and states:
            kw["states"] = states
        try:
            insts += family(kind, f, vals, **kw)
        except FileNotFoundError as exc:  # the shared reactive suite is not there
            console.print(f"[red]{exc}")
            if not every:
                raise typer.Exit(2) from None
        except (ValueError, TypeError, KeyError):  # a value the family cannot use (a name, a value it lacks)
            _refuse(
                "--values",
                f"expected comma-separated integers (or, for reactive-suite, instance names; for "
                f"missions-literature, scenario names) "
                f"that family {f!r} has, got {values!r}",
            )
    if kind == "reach":
        _check_mission_planners(families, solvers)
    if kind == "reach" and "milp" in solvers:
        console.print(
            "[dim]note: `milp` is the region-graph MILP planner; `milp-bigm` is the one-shot big-M MILP (LTL OPT stand-in)"
        )
    solver_options = _options(options or [])
    for name, kv in solver_options.items():  # an option for no solver of the sweep is an error, not dropped
        if name not in solvers:
            _refuse("--option", f"{name!r} is not one of --solvers ({', '.join(solvers)})")
        if kind == "grid" and name == "native":
            from plansynth.grid.native.options import InvalidOption, NativeOptions

            try:
                NativeOptions.parse([f"{k}={v}" for k, v in kv.items()])
            except InvalidOption as exc:
                _refuse("--option", str(exc))
    tasks = make_tasks(
        insts, solvers, repeat=repeat, timeout=timeout, memory_mb=memory, seed=seed, options=solver_options
    )
    console.print(f"{len(tasks)} runs ({len(insts)} instances x {len(solvers)} solvers x {repeat}) -> {db}")
    from plansynth.bench.errors import ClusterUnreachable
    from plansynth.errors import OutputUnwritable

    try:
        counts = run_sweep(db, tasks, jobs=jobs, cluster=cluster, progress=True, retry=_split(retry))
    except OutputUnwritable as exc:  # the database (not SQLite, a folder that does not exist)
        console.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        raise typer.Exit(2) from None
    except ClusterUnreachable as exc:  # no scheduler answers: refused before the database is touched
        _refuse("--cluster", str(exc))
    except KeyboardInterrupt:
        console.print(f"[yellow]interrupted: every finished run is kept in {db}; rerun the same command to resume")
        raise typer.Exit(130) from None
    console.print("finished: " + ", ".join(f"{k} {v}" for k, v in counts.items()))


@app.command("grid", epilog=GRID_EPILOG)
def grid_cmd(
    family: list[str] = typer.Option(
        ["all"], "--family", "-f", help="Family name (repeatable, or comma-separated), or all."
    ),
    values: str | None = typer.Option(
        None, "--values", help="Only these parameter values, e.g. 5,10 (steps L, obstacles N, ...)."
    ),
    solvers: str = typer.Option("native,cvc5", "--solvers", help="Comma-separated grid backends."),
    timeout: float = typer.Option(
        300.0, "--timeout", help="Seconds per run (the solver's budget; the child is killed a little later)."
    ),
    repeat: int = typer.Option(1, "--repeat", help="Repeats per instance and solver."),
    db: Path = DB_OPTION,
    jobs: int = typer.Option(1, "--jobs", "-j", help="Runs at once on the local pool."),
    memory: int = typer.Option(8192, "--memory", help="Memory limit per run, MB."),
    cluster: str | None = typer.Option(
        None, "--cluster", help="Dask scheduler address (tcp://host:8786); default: local pool."
    ),
    seed: int = typer.Option(0, "--seed"),
    retry: str = typer.Option("", "--retry", help="Rerun recorded runs with these statuses, e.g. crash,timeout."),
    option: list[str] = typer.Option(
        [], "--option", "-O", help='Solver option SOLVER:KEY=VALUE, e.g. "external:command=cvc5 --lang=sygus2 {file}".'
    ),
) -> None:
    """Run grid families with several backends into the results database."""
    fams = [x for f in family for x in _split(f)]
    _sweep(
        "grid",
        fams,
        values,
        _split(solvers),
        orders=[],
        timeout=timeout,
        repeat=repeat,
        db=db,
        jobs=jobs,
        memory=memory,
        cluster=cluster,
        seed=seed,
        retry=retry,
        options=option,
    )


@app.command("reach", epilog=REACH_EPILOG)
def reach_cmd(
    family: list[str] = typer.Option(
        ["maze"],
        "--family",
        "-f",
        help="maze, chain, random, random-dynamics, missions, gcs-maze, robust, team (repeatable or comma-separated), or all.",
    ),
    values: str | None = typer.Option(
        None, "--values", help="Passages (maze, chain, robust), seeds (random) or case names (team), e.g. 1,2."
    ),
    orders: str = typer.Option("1,2,3,5", "--orders", help="Chain orders k for the chain family (2k states)."),
    states: str = typer.Option("4,10,20,50", "--states", help="State counts n for the random-dynamics family."),
    planners: str = typer.Option("lazy-smt,rrt,milp-bigm", "--planners", help="Comma-separated planners (also gcs)."),
    timeout: float = typer.Option(60.0, "--timeout"),
    repeat: int = typer.Option(1, "--repeat"),
    db: Path = DB_OPTION,
    jobs: int = typer.Option(1, "--jobs", "-j"),
    memory: int = typer.Option(8192, "--memory"),
    cluster: str | None = typer.Option(None, "--cluster"),
    seed: int = typer.Option(0, "--seed", help="Base seed of the sampling planners (repeat r uses seed + r)."),
    retry: str = typer.Option("", "--retry", help="Rerun recorded runs with these statuses, e.g. crash,timeout."),
) -> None:
    """Run reach-avoid families with several planners into the results database."""
    fams = [x for f in family for x in _split(f)]
    try:
        order_list = [int(k) for k in _split(orders)]
    except ValueError:
        _refuse("--orders", f"expected comma-separated integers, got {orders!r}")
    try:
        state_list = [int(k) for k in _split(states)]
    except ValueError:
        _refuse("--states", f"expected comma-separated integers, got {states!r}")
    _sweep(
        "reach",
        fams,
        values,
        _split(planners),
        orders=order_list,
        timeout=timeout,
        repeat=repeat,
        db=db,
        jobs=jobs,
        memory=memory,
        cluster=cluster,
        seed=seed,
        retry=retry,
        states=state_list,
    )


@contextmanager
def _outputs_checked(folder: Path) -> Iterator[None]:
    """Check the output folder before the work and turn an unwritable file into one
    line and exit 2 (every file is written atomically, see plansynth.io)."""
    from plansynth.errors import OutputUnwritable
    from plansynth.io import check_output_folder

    try:
        check_output_folder(folder)
        yield
    except OutputUnwritable as exc:
        console.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        raise typer.Exit(2) from None


def _require_runs(db: Path, out: Path) -> None:
    """One line and exit 2, before any output is written, when ``db`` does not exist, is
    not a results database or holds no run (a report of nothing is not a report). An
    output ``out`` that is a file is left to the folder check, which names it first."""
    from plansynth.bench.db import ResultsDB
    from plansynth.bench.errors import NoRuns
    from plansynth.errors import OutputUnwritable

    if not db.exists():
        console.print(f"[red]{db}: no such results database")
        raise typer.Exit(2)
    if out.exists() and not out.is_dir():
        return
    try:
        with ResultsDB(db) as d:
            if d.run_count() == 0:
                raise NoRuns(str(db))
    except (OutputUnwritable, NoRuns) as exc:
        console.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        raise typer.Exit(2) from None


HTML_OPTION_HELP = (
    "Also write the report as one self-contained HTML page beside the Markdown: a table of "
    "contents, sortable tables, the plots embedded; it loads nothing from the network."
)


def _written(markdown: Path, html: bool) -> str:
    return f"{markdown} and {markdown.with_suffix('.html')}" if html else str(markdown)


@app.command("report")
def report_cmd(
    db: Path = DB_OPTION,
    out: Path = typer.Option(
        Path("bench-report"), "--out", "-o", help="Directory for REPORT.md, REPORT.html and the PNG plots."
    ),
    html: bool = typer.Option(True, "--html/--no-html", help=HTML_OPTION_HELP),
) -> None:
    """Markdown tables (paper numbers beside ours and the peers') and log-scale PNG plots,
    and the same report as one HTML page (REPORT.html) with the plots embedded.

    Example: plansynth bench report --db bench-results.db --out bench-report/
    """
    from plansynth.bench.report import write_report

    _require_runs(db, out)
    with _outputs_checked(out):
        path = write_report(db, out, html=html)
    console.print(f"wrote {_written(path, html)} and {len(list(out.glob('*.png')))} plots")


@app.command("merge")
def merge_cmd(
    sources: list[Path] = typer.Argument(..., help="Results databases whose runs are copied."),
    db: Path = typer.Option(..., "--db", help="The results database they are merged into (created if absent)."),
) -> None:
    """Merge the runs of other results databases into one (sweeps run on other machines
    or checkouts): a run both hold is kept from the newer one.

    Example: plansynth bench merge other-results.db --db benchmarks/results.db
    """
    from plansynth.bench.db import ResultsDB
    from plansynth.bench.errors import NoDatabase
    from plansynth.errors import OutputUnwritable

    try:
        with ResultsDB(db) as d:
            for src in sources:
                n = d.merge(src)
                console.print(f"{src}: {n} runs merged into {db}")
    except (OutputUnwritable, NoDatabase) as exc:
        console.print(f"[red]error:[/red] {exc}", highlight=False, soft_wrap=True)
        raise typer.Exit(2) from None


@app.command("families")
def families_cmd(
    out: Path = typer.Option(Path("benchmarks/families"), "--out", "-o"),
) -> None:
    """Write every benchmark instance as a problem file (YAML), per kind and family."""
    from plansynth.bench.families import GRID_FAMILIES, REACH_FAMILIES, family, write_family_files

    insts = [i for f in GRID_FAMILIES if f != "reactive-suite" for i in family("grid", f)]
    insts += [i for f in REACH_FAMILIES for i in family("reach", f)]
    with _outputs_checked(out):
        paths = write_family_files(out, insts)
    console.print(f"wrote {len(paths)} problem files under {out}")


@app.command("publish")
def publish_cmd(
    db: Path = typer.Option(Path("benchmarks/results.db"), "--db"),
    out: Path = typer.Option(
        Path("benchmarks"), "--out", "-o", help="Directory of RESULTS.md, RESULTS.html and the figures."
    ),
    report_only: bool = typer.Option(
        False, "--report-only", help="Only regenerate RESULTS.md (and RESULTS.html) from the database."
    ),
    html: bool = typer.Option(True, "--html/--no-html", help=HTML_OPTION_HELP),
    grid_timeout: float = typer.Option(120.0, "--grid-timeout"),
    reach_timeout: float = typer.Option(60.0, "--reach-timeout"),
    jobs: int = typer.Option(1, "--jobs", "-j"),
    cluster: str | None = typer.Option(None, "--cluster"),
) -> None:
    """Run (or resume) the published sweep and write benchmarks/RESULTS.md from it, and
    benchmarks/RESULTS.html, the same report as one page with the figures embedded.

    Example: plansynth bench publish            # resumable; rerun to continue
    """
    from plansynth.bench.errors import ClusterUnreachable
    from plansynth.bench.publish import publish

    if report_only:
        _require_runs(db, out)
    with _outputs_checked(out):
        try:
            path = publish(
                db,
                out,
                run=not report_only,
                grid_timeout=grid_timeout,
                reach_timeout=reach_timeout,
                jobs=jobs,
                cluster=cluster,
                html=html,
            )
        except ClusterUnreachable as exc:
            _refuse("--cluster", str(exc))
    console.print(f"wrote {_written(path, html)}")

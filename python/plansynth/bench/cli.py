"""`plansynth bench` sub-commands: thin shells over :mod:`plansynth.bench` (STYLE.md, point 12)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console

app = typer.Typer(no_args_is_help=True, add_completion=False)
console = Console()

DB_OPTION = typer.Option(Path("bench-results.db"), "--db", help="SQLite results database (created if absent; resumed if present).")

GRID_EPILOG = """\
Examples:

  plansynth bench grid --family steps --solvers native,cvc5 --timeout 300 --repeat 3

  plansynth bench grid --family obstacles --values 5,10,15 --solvers native --db out/grid.db

  plansynth bench grid --family all --solvers native,cvc5 --timeout 60 --cluster tcp://10.0.0.5:8786

  plansynth bench grid --family depth --solvers native,external -O "external:command=cvc5 --lang=sygus2 {file}"

Families: figure1, depth, steps, obstacles, dimensions (the paper's), crossing, crossing-stall, patrol, patrol-walk (reactive, ours), or all.
Rerunning the same command resumes: runs already in the database are skipped.
"""

REACH_EPILOG = """\
Examples:

  plansynth bench reach --family maze --planners lazy-smt,rrt,milp --repeat 5

  plansynth bench reach --family chain --values 1,2 --orders 1,2,5,10 --planners lazy-smt --timeout 120

  plansynth bench reach --family random --values 0,1,2 --planners lazy-smt,rrt,milp-bigm
  plansynth bench reach --family missions --planners lazy-smt,milp-ltl --timeout 120

Families: maze (Table I), chain (Figure 4: integrator chains, 2k states), random, missions (LTL missions on the mazes: use --planners lazy-smt,milp-ltl), or all.
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


def _sweep(kind: str, families: list[str], values: Optional[str], solvers: list[str], *, orders: list[int],
           timeout: float, repeat: int, db: Path, jobs: int, memory: int, cluster: Optional[str], seed: int,
           retry: str = "", options: Optional[list[str]] = None) -> None:
    from plansynth.bench.families import GRID_FAMILIES, REACH_FAMILIES, family
    from plansynth.bench.runner import make_tasks, run_sweep

    known = list(GRID_FAMILIES) if kind == "grid" else list(REACH_FAMILIES)
    if families == ["all"]:
        families = known
    insts = []
    vals = None if values is None else [int(v) for v in _split(values)]
    for f in families:
        if f not in known:
            console.print(f"[red]unknown {kind} family {f!r}; choose from {', '.join(known)} or all")
            raise typer.Exit(2)
        kw = {"orders": orders} if kind == "reach" else {}
        insts += family(kind, f, vals, **kw)
    if kind == "reach" and "milp" in solvers:
        console.print("[dim]note: `milp` is the region-graph MILP planner; `milp-bigm` is the one-shot big-M MILP (LTL OPT stand-in)")
    tasks = make_tasks(insts, solvers, repeat=repeat, timeout=timeout, memory_mb=memory, seed=seed,
                       options=_options(options or []))
    console.print(f"{len(tasks)} runs ({len(insts)} instances x {len(solvers)} solvers x {repeat}) -> {db}")
    counts = run_sweep(db, tasks, jobs=jobs, cluster=cluster, progress=True, retry=_split(retry))
    console.print("finished: " + ", ".join(f"{k} {v}" for k, v in counts.items()))


@app.command("grid", epilog=GRID_EPILOG)
def grid_cmd(
    family: list[str] = typer.Option(["all"], "--family", "-f", help="Family name (repeatable, or comma-separated), or all."),
    values: Optional[str] = typer.Option(None, "--values", help="Only these parameter values, e.g. 5,10 (steps L, obstacles N, ...)."),
    solvers: str = typer.Option("native,cvc5", "--solvers", help="Comma-separated grid backends."),
    timeout: float = typer.Option(300.0, "--timeout", help="Seconds per run (the solver's budget; the child is killed a little later)."),
    repeat: int = typer.Option(1, "--repeat", help="Repeats per instance and solver."),
    db: Path = DB_OPTION,
    jobs: int = typer.Option(1, "--jobs", "-j", help="Runs at once on the local pool."),
    memory: int = typer.Option(8192, "--memory", help="Memory limit per run, MB."),
    cluster: Optional[str] = typer.Option(None, "--cluster", help="Dask scheduler address (tcp://host:8786); default: local pool."),
    seed: int = typer.Option(0, "--seed"),
    retry: str = typer.Option("", "--retry", help="Rerun recorded runs with these statuses, e.g. crash,timeout."),
    option: list[str] = typer.Option([], "--option", "-O", help='Solver option SOLVER:KEY=VALUE, e.g. "external:command=cvc5 --lang=sygus2 {file}".'),
) -> None:
    """Run grid families with several backends into the results database."""
    fams = [x for f in family for x in _split(f)]
    _sweep("grid", fams, values, _split(solvers), orders=[], timeout=timeout, repeat=repeat, db=db, jobs=jobs,
           memory=memory, cluster=cluster, seed=seed, retry=retry, options=option)


@app.command("reach", epilog=REACH_EPILOG)
def reach_cmd(
    family: list[str] = typer.Option(["maze"], "--family", "-f", help="maze, chain, random, missions (repeatable or comma-separated), or all."),
    values: Optional[str] = typer.Option(None, "--values", help="Passages (maze, chain) or seeds (random), e.g. 1,2."),
    orders: str = typer.Option("1,2,3,5", "--orders", help="Chain orders k for the chain family (2k states)."),
    planners: str = typer.Option("lazy-smt,rrt,milp-bigm", "--planners", help="Comma-separated planners."),
    timeout: float = typer.Option(60.0, "--timeout"),
    repeat: int = typer.Option(1, "--repeat"),
    db: Path = DB_OPTION,
    jobs: int = typer.Option(1, "--jobs", "-j"),
    memory: int = typer.Option(8192, "--memory"),
    cluster: Optional[str] = typer.Option(None, "--cluster"),
    seed: int = typer.Option(0, "--seed", help="Base seed of the sampling planners (repeat r uses seed + r)."),
    retry: str = typer.Option("", "--retry", help="Rerun recorded runs with these statuses, e.g. crash,timeout."),
) -> None:
    """Run reach-avoid families with several planners into the results database."""
    fams = [x for f in family for x in _split(f)]
    _sweep("reach", fams, values, _split(planners), orders=[int(k) for k in _split(orders)], timeout=timeout,
           repeat=repeat, db=db, jobs=jobs, memory=memory, cluster=cluster, seed=seed, retry=retry)


@app.command("report")
def report_cmd(
    db: Path = DB_OPTION,
    out: Path = typer.Option(Path("bench-report"), "--out", "-o", help="Directory for REPORT.md and the PNG plots."),
) -> None:
    """Markdown tables (paper numbers beside ours and the peers') and log-scale PNG plots.

    Example: plansynth bench report --db bench-results.db --out bench-report/
    """
    from plansynth.bench.report import write_report

    if not db.exists():
        console.print(f"[red]{db}: no such results database")
        raise typer.Exit(2)
    path = write_report(db, out)
    console.print(f"wrote {path} and {len(list(out.glob('*.png')))} plots")


@app.command("families")
def families_cmd(
    out: Path = typer.Option(Path("benchmarks/families"), "--out", "-o"),
) -> None:
    """Write every benchmark instance as a problem file (YAML), per kind and family."""
    from plansynth.bench.families import GRID_FAMILIES, REACH_FAMILIES, family, write_family_files

    insts = [i for f in GRID_FAMILIES for i in family("grid", f)]
    insts += [i for f in REACH_FAMILIES for i in family("reach", f)]
    paths = write_family_files(out, insts)
    console.print(f"wrote {len(paths)} problem files under {out}")


@app.command("publish")
def publish_cmd(
    db: Path = typer.Option(Path("benchmarks/results.db"), "--db"),
    out: Path = typer.Option(Path("benchmarks"), "--out", "-o", help="Directory of RESULTS.md and its figures."),
    report_only: bool = typer.Option(False, "--report-only", help="Only regenerate RESULTS.md from the database."),
    grid_timeout: float = typer.Option(120.0, "--grid-timeout"),
    reach_timeout: float = typer.Option(60.0, "--reach-timeout"),
    jobs: int = typer.Option(1, "--jobs", "-j"),
    cluster: Optional[str] = typer.Option(None, "--cluster"),
) -> None:
    """Run (or resume) the published sweep and write benchmarks/RESULTS.md from it.

    Example: plansynth bench publish            # resumable; rerun to continue
    """
    from plansynth.bench.publish import publish

    path = publish(db, out, run=not report_only, grid_timeout=grid_timeout, reach_timeout=reach_timeout,
                   jobs=jobs, cluster=cluster)
    console.print(f"wrote {path}")

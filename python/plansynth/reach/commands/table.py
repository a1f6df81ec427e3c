"""``plansynth reach table``: the paper's maze family (Section VI, Table I and Figure 4),
the time of each phase and the SAT/LP call counts per maze and strategy."""

from __future__ import annotations

import typer
from rich.console import Console
from rich.table import Table

from plansynth.budget import Budget
from plansynth.cli_support import fail, positive_seconds
from plansynth.errors import InvalidOption, PlansynthError
from plansynth.reach.commands.common import MAX_ORDER_OPTION
from plansynth.reach.commands.results import STYLE

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
            style = STYLE[r.status.value]
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

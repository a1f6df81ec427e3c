"""``plansynth view``: a problem and its result as an interactive page in the browser
(a thin shell over :mod:`plansynth.view`, STYLE.md point 12).

One command, not a group: ``plansynth view PROBLEM [--result R] [-o OUT.html]
[--serve] [--port N] [--timeout T]``. Exit status: 0 written (or served until
stopped), 2 bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from typer.core import TyperGroup

EPILOG = """\
Examples:

  plansynth grid solve examples/grid/traffic.yaml -o traffic.json

  plansynth view examples/grid/traffic.yaml --result traffic.json -o traffic.html

  plansynth reach solve examples/reach/mission-patrol.yaml -o patrol.json

  plansynth view examples/reach/mission-patrol.yaml --result patrol.json -o patrol.html

  plansynth view examples/reach/maze-3.yaml --serve          # a local page that plans

  plansynth reach solve examples/reach/team-crossing.yaml -o crossing.json

  plansynth view examples/reach/team-crossing.yaml --result crossing.json -o crossing.html

A page written with -o is one self-contained file: scripts, styles and data inlined, nothing loaded from the network. Without -o and --serve the page is written to PROBLEM's stem + .html in the current directory.

--serve serves the page on 127.0.0.1 only (port 0: a free one, printed) and re-plans the problem when the page asks (reach problems); Ctrl-C stops it.

Exit status: 0 written (or served until stopped), 2 bad input.
"""


class OneCommand(TyperGroup):
    """``plansynth view`` is one command; the top-level CLI loads every sub-command as
    a Typer app's group (plansynth.cli.GROUPS), so this group takes its options
    anywhere on the line and has no sub-commands."""

    allow_interspersed_args = True

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        ctx.fail(f"unexpected extra argument: {args[0]!r} (one problem file)")

    def collect_usage_pieces(self, ctx: Any) -> list[str]:
        return [piece for piece in super().collect_usage_pieces(ctx) if piece != self.subcommand_metavar]


app = typer.Typer(
    cls=OneCommand,
    add_completion=False,
    invoke_without_command=True,
    no_args_is_help=True,
    subcommand_metavar="",
    epilog=EPILOG,
)


def _timeout(value: float) -> float:
    from plansynth.view.server import MAX_TIMEOUT

    if not 0 < value <= MAX_TIMEOUT:
        raise typer.BadParameter(f"must be in (0, {MAX_TIMEOUT:g}] seconds, got {value:g}")
    return value


@app.callback(epilog=EPILOG)
def view(
    problem: Path = typer.Argument(..., help="Grid, reach or team problem file (YAML or JSON)."),
    result: Path | None = typer.Option(
        None, "--result", "-r", help="Result JSON of plansynth grid solve -o or reach solve -o for this problem."
    ),
    output: Path | None = typer.Option(
        None, "--output", "-o", help="Write the page to this HTML file (one self-contained file)."
    ),
    serve: bool = typer.Option(
        False, "--serve", help="Serve a page that re-plans the problem on 127.0.0.1 (reach problems)."
    ),
    port: int = typer.Option(0, "--port", min=0, max=65535, help="--serve: the port (0: a free one)."),
    timeout: float = typer.Option(
        10.0,
        "--timeout",
        callback=_timeout,
        help="--serve: the budget of each re-plan in seconds (at most 30; the page may lower it).",
    ),
) -> None:
    """Show a problem and its result as an interactive page: a grid controller against
    obstacles you move, a reach trajectory with its regions, labels and bounds, or a
    team's trajectories among moving obstacles."""
    from rich.console import Console
    from rich.markup import escape

    from plansynth.cli_support import fail
    from plansynth.errors import PlansynthError
    from plansynth.io import check_output_path
    from plansynth.view import build_page, problem_kind

    console = Console(soft_wrap=True, highlight=False)
    err = Console(stderr=True, soft_wrap=True)
    try:
        kind = problem_kind(problem)
        if serve and kind != "reach":
            raise typer.BadParameter(
                f"plans single-robot reach problems only; write a {kind} page with -o", param_hint="--serve"
            )
        if output is None and not serve:
            output = Path(problem.stem + ".html")
        if output is not None:
            check_output_path(output)
        html = build_page(problem, result, serve=False) if output is not None else None
        page = build_page(problem, result, serve=True, timeout=timeout) if serve else None
        if html is not None:
            from plansynth.io import write_output

            write_output(output, html)
            console.print(f"page written to {escape(str(output))}")
    except PlansynthError as exc:
        raise fail(err, exc) from None
    if page is not None:
        from plansynth.view.server import PlanServer, serve_forever

        try:
            server = PlanServer(page, port, timeout)
        except OSError as exc:
            raise fail(err, f"--port {port}: cannot listen on 127.0.0.1: {exc.strerror or exc}") from None
        serve_forever(server, lambda line: console.print(escape(line)))

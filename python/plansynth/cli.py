"""The ``plansynth`` command: a thin shell over the API (STYLE.md, point 12).

Each half of the toolkit owns its sub-command group in its own ``cli`` module; this
module only assembles them.
"""

from __future__ import annotations

import typer

from plansynth.bench.cli import app as bench_app
from plansynth.cli_support import OneLineErrorsGroup
from plansynth.grid.cli import app as grid_app
from plansynth.reach.cli import app as reach_app

app = typer.Typer(
    name="plansynth",
    help="Correct-by-construction robot motion planning with off-the-shelf solvers.",
    no_args_is_help=True,
    add_completion=False,
    cls=OneLineErrorsGroup,  # usage errors as one line, exit 2 (plansynth.cli_support)
)
app.add_typer(grid_app, name="grid", help="Reactive grid controllers (Chasins & Newcomb, SYNT 2016).")
app.add_typer(reach_app, name="reach", help="Reach-avoid planning with linear dynamics (Shoukry et al., CDC 2016).")
app.add_typer(bench_app, name="bench", help="Benchmarks: both papers' evaluations side by side with peers.")


@app.command()
def version() -> None:
    """Print the versions of plansynth, its compiled core and its solvers."""
    import plansynth
    from plansynth import _core

    typer.echo(f"plansynth {plansynth.__version__} (core {_core.core_version()})")


def main() -> None:
    app()


if __name__ == "__main__":
    main()

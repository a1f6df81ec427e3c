"""The ``plansynth`` command: a thin shell over the API (STYLE.md, point 12).

Each half of the toolkit owns its sub-command group in its own ``cli`` module; this
module only assembles them, and imports a group only when its sub-command runs (or its
own ``--help`` is asked for). So ``plansynth --version`` and ``plansynth --help`` load
neither half (no highspy, shapely, matplotlib, cvc5 or pysat), and ``plansynth grid ...``
does not load the reach half. A new group is one line of :data:`GROUPS`.
"""

from __future__ import annotations

import gc
import importlib
from typing import Any

import typer
from typer.core import TyperGroup

from plansynth.cli_support import OneLineErrorsGroup

#: The sub-command groups: name -> (module holding a Typer ``app``, one-line help).
GROUPS: dict[str, tuple[str, str]] = {
    "grid": ("plansynth.grid.cli", "Reactive grid controllers (Chasins & Newcomb, SYNT 2016)."),
    "reach": ("plansynth.reach.cli", "Reach-avoid planning with linear dynamics (Shoukry et al., CDC 2016)."),
    "bench": ("plansynth.bench.cli", "Benchmarks: both papers' evaluations side by side with peers."),
    "view": (
        "plansynth.view.cli",
        "Interactive pages in the browser: a controller against your obstacle moves, a trajectory.",
    ),
}


class LazyGroup(OneLineErrorsGroup):
    """A Typer group whose sub-groups (:data:`GROUPS`) are imported on first use; usage
    errors are one line, exit 2 (:class:`~plansynth.cli_support.OneLineErrorsGroup`).

    Listing them (``plansynth --help``) shows their one-line help without importing them.
    """

    _listing = False

    def list_commands(self, ctx: Any) -> list[str]:
        return [*GROUPS, *(name for name in super().list_commands(ctx) if name not in GROUPS)]

    def get_command(self, ctx: Any, cmd_name: str) -> Any | None:
        if cmd_name not in GROUPS:
            return super().get_command(ctx, cmd_name)
        module, help_text = GROUPS[cmd_name]
        if self._listing:
            return TyperGroup(name=cmd_name, help=help_text)
        command = typer.main.get_group(importlib.import_module(module).app)
        command.name = cmd_name
        command.help = help_text
        return command

    def format_help(self, ctx: Any, formatter: Any) -> None:
        self._listing = True
        try:
            super().format_help(ctx, formatter)
        finally:
            self._listing = False


app = typer.Typer(
    name="plansynth",
    cls=LazyGroup,
    help="Correct-by-construction robot motion planning with off-the-shelf solvers.",
    no_args_is_help=True,
    add_completion=False,
)


def _version_text() -> str:
    import plansynth
    from plansynth import _core

    return f"plansynth {plansynth.__version__} (core {_core.core_version()})"


def _print_version(value: bool) -> None:
    if value:
        typer.echo(_version_text())
        raise typer.Exit(0)


@app.callback()
def _root(
    show_version: bool = typer.Option(
        False,
        "--version",
        help="Print the versions of plansynth and its compiled core, and exit.",
        callback=_print_version,
        is_eager=True,
    ),
) -> None:
    """Correct-by-construction robot motion planning with off-the-shelf solvers."""


@app.command()
def version() -> None:
    """Print the versions of plansynth and its compiled core (as --version)."""
    typer.echo(_version_text())


def main(args: Any = None) -> None:
    from plansynth.cli_support import mark_process_start
    from plansynth.procs import terminate_as_interrupt

    mark_process_start()  # --timeout counts from the process's start (grid solve)
    terminate_as_interrupt()  # SIGTERM unwinds like Ctrl-C: solver children are killed
    try:
        app(args)
    finally:
        # The command is done (its children killed, its files closed by their with
        # blocks): the interpreter's exit need not have the collector traverse every
        # object of every module loaded, which took 30-50 ms of a 0.3 s grid solve.
        # atexit handlers still run; only objects in reference cycles still alive at
        # exit are left to the process's end, as Python allows.
        gc.freeze()


if __name__ == "__main__":
    main()

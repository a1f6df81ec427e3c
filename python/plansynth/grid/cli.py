"""`plansynth grid` sub-commands.

The commands are defined beside the code they front, each module registering its own:
``cli_solve`` (solve, compile), ``cli_inspect`` (verify, animate, export) and
``cli_native`` (explain).
"""

from __future__ import annotations

import typer

from plansynth.grid import cli_inspect, cli_native, cli_solve

app = typer.Typer(no_args_is_help=True, add_completion=False)

for _module in (cli_solve, cli_inspect, cli_native):
    _module.register(app)

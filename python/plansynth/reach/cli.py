"""``plansynth reach`` sub-commands: a thin shell over :func:`plansynth.reach.solve`,
:func:`plansynth.reach.validate` and :mod:`plansynth.reach.plot` (STYLE.md, point 12).

Exit status of ``solve``: 0 found (validated trajectory), 1 infeasible, 2 bad input,
3 unknown (budget ran out, or a trajectory failed validation).

The app is assembled here; each command lives in its own module of
:mod:`plansynth.reach.commands`.
"""

from __future__ import annotations

import typer

from plansynth.reach.commands.common import MAX_HORIZON_OPTION, MAX_ORDER_OPTION
from plansynth.reach.commands.plot import PLOT_EPILOG, configuration_space_of, plot_command
from plansynth.reach.commands.solve import EXIT_RESERVE, SOLVE_EPILOG, planner_options_help, solve_command
from plansynth.reach.commands.table import TABLE_EPILOG, table_command
from plansynth.reach.commands.validate import VALIDATE_EPILOG, validate_command

app = typer.Typer(no_args_is_help=True, add_completion=False)
app.command("solve", epilog=SOLVE_EPILOG)(solve_command)
app.command("validate", epilog=VALIDATE_EPILOG)(validate_command)
app.command("plot", epilog=PLOT_EPILOG)(plot_command)
app.command("table", epilog=TABLE_EPILOG)(table_command)

__all__ = [
    "EXIT_RESERVE",
    "MAX_HORIZON_OPTION",
    "MAX_ORDER_OPTION",
    "app",
    "configuration_space_of",
    "planner_options_help",
    "plot_command",
    "solve_command",
    "table_command",
    "validate_command",
]

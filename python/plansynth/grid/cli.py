"""`plansynth grid` sub-commands.

The commands are defined beside the code they front, each module registering its own:
``cli_solve`` (solve, compile), ``cli_inspect`` (verify, animate, export) and
``cli_native`` (explain, minimize). A module is imported only when one of its commands
runs (or when the group's help lists them all), so ``plansynth grid solve`` does not
pay for the imports of ``verify``'s or ``explain``'s shells (rich tables, the renderer).
"""

from __future__ import annotations

import importlib
from typing import Any

import typer
from typer.core import TyperGroup

#: Each command of ``plansynth grid`` -> the module that registers it, in help order.
COMMANDS: dict[str, str] = {
    "solve": "plansynth.grid.cli_solve",
    "compile": "plansynth.grid.cli_solve",
    "verify": "plansynth.grid.cli_inspect",
    "animate": "plansynth.grid.cli_inspect",
    "export": "plansynth.grid.cli_inspect",
    "explain": "plansynth.grid.cli_native",
    "minimize": "plansynth.grid.cli_native",
}


class LazyCommands(TyperGroup):
    """The ``plansynth grid`` group: a command's module is imported on first use."""

    _loaded: dict[str, Any] = {}

    def list_commands(self, ctx: Any) -> list[str]:
        return [*COMMANDS, *(name for name in super().list_commands(ctx) if name not in COMMANDS)]

    def get_command(self, ctx: Any, cmd_name: str) -> Any | None:
        module = COMMANDS.get(cmd_name)
        if module is None:
            return super().get_command(ctx, cmd_name)
        group = self._loaded.get(module)
        if group is None:
            sub = typer.Typer(add_completion=False)
            importlib.import_module(module).register(sub)
            group = self._loaded[module] = typer.main.get_group(sub)
        return group.get_command(ctx, cmd_name)


app = typer.Typer(cls=LazyCommands, no_args_is_help=True, add_completion=False)

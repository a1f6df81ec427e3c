"""CLI commands (registered on the `plansynth grid` app by :mod:`plansynth.grid.cli`)."""

from __future__ import annotations

import typer


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app``."""

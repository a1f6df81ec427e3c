"""The mission readings the command line sets (``--reading``, ``--end``, ``--margin``,
``--obstacle-margin``, and ``--segment-safe`` for a mission), shared by ``reach solve``
and ``reach validate``."""

from __future__ import annotations

from typing import Any

import typer


def given(ctx: typer.Context, name: str) -> bool:
    """Was the parameter ``name`` given on the command line (not left at its default)?"""
    source = ctx.get_parameter_source(name)
    return source is not None and source.name not in ("DEFAULT", "DEFAULT_MAP")


def mission_readings(
    ctx: typer.Context | None,
    problem: Any,
    reading: str | None,
    end: str | None,
    margin: float | None,
    obstacle_margin: float | None,
) -> Any:
    """The problem with the mission's reading, end and margins the command line sets
    (checked like the file's: an :class:`~plansynth.errors.InvalidProblem` naming the
    field). For a mission, ``--no-segment-safe`` is the sample reading (and
    ``--segment-safe`` the segment one): the one choice planners and checker share."""
    from dataclasses import replace

    values: dict[str, Any] = {}
    if ctx is not None and given(ctx, "segment_safe") and problem.mission is not None:
        implied = "segment" if ctx.params["segment_safe"] else "sample"
        if reading is not None and reading != implied:
            raise typer.BadParameter(
                f"--reading {reading} and --{'no-' if implied == 'sample' else ''}segment-safe disagree "
                "(for a mission, --no-segment-safe is the sample reading)",
                param_hint="--reading",
            )
        values["reading"] = implied
    for key, value in (("reading", reading), ("end", end), ("margin", margin), ("obstacle_margin", obstacle_margin)):
        if value is not None:
            values[key] = value
    return replace(problem, **values) if values else problem

"""What every ``plansynth`` sub-command shares at the door (STYLE.md, points 2 and 12):
usage errors as one line, the exit statuses, the one-line error of a bad input, and
checks of the budget options.

A bad command line exits with status 2 and one line on standard error, like a bad
problem file (``error: FILE: FIELD: REASON``): click's own usage errors (unknown
option, value out of range, ...) are printed as ``error: COMMAND: MESSAGE`` instead of
click's several-line box.

>>> positive_seconds(2.5)
2.5
>>> positive_seconds(float("nan"))  # doctest: +IGNORE_EXCEPTION_DETAIL
Traceback (most recent call last):
...
BadParameter: expected a finite number of seconds > 0, got nan
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Sequence
from typing import Any

import typer
from typer.core import TyperGroup

try:  # recent typer vendors its own click as typer._click; older ones use click itself
    from typer._click import echo
    from typer._click.exceptions import ClickException, NoArgsIsHelpError
except ImportError:  # pragma: no cover - depends on the installed typer
    from click import echo
    from click.exceptions import ClickException

    try:
        from click.exceptions import NoArgsIsHelpError
    except ImportError:
        NoArgsIsHelpError = ()  # type: ignore[assignment,misc]  # click < 8.2 exits 0 instead


#: The exit statuses of every command of both halves: the answer is yes (found,
#: realizable, valid), no (infeasible, unrealizable, invalid: proved), bad input (a file,
#: an option, a solver that is unavailable, an output that cannot be written), unknown
#: (a budget ran out, or no proof either way).
EXIT_YES, EXIT_NO, EXIT_BAD_INPUT, EXIT_UNKNOWN = 0, 1, 2, 3


def fail(err: Any, error: Exception | str) -> typer.Exit:
    """Print ``error: MESSAGE`` (one line, markup escaped) on the console ``err`` and
    return the exit of a bad input, for ``raise fail(err, exc) from None``."""
    from rich.markup import escape

    err.print(f"[bold red]error:[/bold red] {escape(str(error))}", highlight=False)
    return typer.Exit(EXIT_BAD_INPUT)


#: ``time.monotonic()`` when this process began, set by :func:`mark_process_start`
#: (the ``plansynth`` console script calls it first); None in-process (tests, the API).
_STARTED: float | None = None


def mark_process_start() -> None:
    """Remember when this process began (from ``/proc`` on Linux, else now), so that a
    command's ``--timeout`` covers the interpreter's start-up too: ``plansynth grid
    solve P --timeout 10`` answers within 10 s of being started, not of its imports."""
    global _STARTED
    now = time.monotonic()
    try:
        with open("/proc/self/stat") as f:
            after_name = f.read().rsplit(")", 1)[1].split()
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        age = max(0.0, uptime - int(after_name[19]) / os.sysconf("SC_CLK_TCK"))  # field 22: starttime
    except (OSError, ValueError, IndexError):
        age = 0.0
    _STARTED = now - min(age, 60.0)


def seconds_since_start() -> float:
    """Seconds since :func:`mark_process_start`'s process began (0 when not marked)."""
    return 0.0 if _STARTED is None else max(0.0, time.monotonic() - _STARTED)


class OneLineErrorsGroup(TyperGroup):
    """The top-level ``plansynth`` group: click usage errors become one line, exit 2."""

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, False, windows_expand_args, **extra)
        try:
            rv = super().main(args, prog_name, complete_var, False, windows_expand_args, **extra)
        except NoArgsIsHelpError as exc:  # no arguments: the help, as before
            exc.show()
            sys.exit(exc.exit_code)
        except ClickException as exc:
            echo(f"error: {usage_error_line(exc)}", err=True)
            sys.exit(exc.exit_code)
        except typer.Abort:
            echo("Aborted!", err=True)
            sys.exit(1)
        sys.exit(rv if isinstance(rv, int) and not isinstance(rv, bool) else 0)


def usage_error_line(exc: ClickException) -> str:
    """One line for a click error: the command, the message, where to find help.

    The message is whitespace-folded and cut to 500 characters: it may quote an
    argument of any length.
    """
    message = " ".join(exc.format_message().split())
    if len(message) > 500:
        message = message[:497] + "..."
    ctx = getattr(exc, "ctx", None)
    if ctx is None:
        return message
    return f"{ctx.command_path}: {message} (see {ctx.command_path} --help)"


def positive_seconds(value: float | None) -> float | None:
    """Typer callback of a time budget option (``--timeout``): finite and > 0."""
    if value is not None and not (math.isfinite(value) and value > 0):
        raise typer.BadParameter(f"expected a finite number of seconds > 0, got {value}")
    return value


def finite_positive(value: float | None) -> float | None:
    """Typer callback of a real-valued option that must be finite and > 0."""
    if value is not None and not (math.isfinite(value) and value > 0):
        raise typer.BadParameter(f"expected a finite number > 0, got {value}")
    return value

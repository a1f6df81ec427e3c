"""Runs that exercise the runner, not a solver: solver names starting with ``debug-``.

``debug-ok`` returns at once, ``debug-sleep`` sleeps past any limit, ``debug-crash``
kills its own process with SIGSEGV, ``debug-raise`` raises, ``debug-memory`` allocates
until the memory limit stops it.

>>> run_debug("debug-ok")["status"]
'solved'
"""

from __future__ import annotations

import os
import time
from typing import Any

__all__ = ["DEBUG_SOLVERS", "run_debug"]

DEBUG_SOLVERS = ("debug-ok", "debug-sleep", "debug-crash", "debug-raise", "debug-memory")


def run_debug(solver: str) -> dict[str, Any]:
    """The attributes of debug run ``solver`` (or its end: a sleep, a crash, an error)."""
    if solver == "debug-ok":
        return {"status": "solved", "solved": 1, "valid": 1, "time": 0.001, "solver_version": "debug"}
    if solver == "debug-sleep":
        time.sleep(10_000)
    if solver == "debug-crash":
        import signal

        os.kill(os.getpid(), signal.SIGSEGV)
    if solver == "debug-raise":
        raise RuntimeError("debug-raise: a solver bug")
    if solver == "debug-memory":
        hog = []
        while True:
            hog.append(bytearray(50 * 1024 * 1024))
    raise ValueError(f"unknown debug solver {solver!r}")

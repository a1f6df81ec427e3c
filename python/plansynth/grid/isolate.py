"""Run a function in a child process with a wall-clock limit and a memory limit.

Solvers crash, hang and exhaust memory; none of that may take the caller down or lose
the caller's results (STYLE.md, point 4: a budget that runs out gives ``unknown``,
never a hang). :func:`run_isolated` calls ``fn(*args, **kwargs)`` in a fresh child
process and returns exactly one of:

- :class:`Finished` -- the function returned; ``value`` is its (pickled) return value;
- :class:`Timeout` -- the wall-clock limit passed; the child (and anything it started
  in its process group) was killed;
- :class:`Crash` -- the child raised (``error`` holds the traceback text), ran out of
  memory, or died without answering (``exitcode``; negative: killed by that signal).

The child runs in its own session, so a solver that starts helper processes is killed
with them. The memory limit is ``RLIMIT_AS`` set in the child before ``fn`` runs.

``fn`` and its arguments must be picklable (a module-level function). Children are
started with the ``forkserver`` method (fast, and safe when the parent has threads);
``spawn`` is available too. A child imports the modules ``fn`` needs; :func:`preload`
makes the fork server import heavy ones once (for cvc5: 0.5 s less per call).

>>> run_isolated(pow, 2, 10, timeout=30)
Finished(value=1024, seconds=...)
>>> run_isolated(int, "x", timeout=30).error.splitlines()[-1]
"ValueError: invalid literal for int() with base 10: 'x'"
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar, Union

__all__ = ["Finished", "Timeout", "Crash", "Outcome", "run_isolated", "preload"]

T = TypeVar("T")


@dataclass(frozen=True)
class Finished(Generic[T]):
    """The function returned ``value`` after ``seconds`` of wall-clock time."""

    value: T
    seconds: float = field(repr=False)

    def __repr__(self) -> str:  # seconds vary run to run; keep doctest output stable
        return f"Finished(value={self.value!r}, seconds=...)"


@dataclass(frozen=True)
class Timeout:
    """The wall-clock limit ``limit`` passed; the child was killed."""

    limit: float
    seconds: float


@dataclass(frozen=True)
class Crash:
    """The child raised or died. ``exitcode`` < 0 means killed by signal ``-exitcode``."""

    exitcode: int | None
    error: str
    seconds: float
    memory_out: bool = False

    def describe(self) -> str:
        """One line for a user: what happened to the child."""
        if self.memory_out:
            return "ran out of memory"
        if self.error:
            return self.error.strip().splitlines()[-1]
        if self.exitcode is not None and self.exitcode < 0:
            try:
                name = signal.Signals(-self.exitcode).name
            except ValueError:
                name = f"signal {-self.exitcode}"
            return f"killed by {name}"
        return f"exited with code {self.exitcode} without answering"


Outcome = Union[Finished[T], Timeout, Crash]


_PRELOAD: list[str] = ["__main__"]  # multiprocessing's default for the fork server


def preload(*modules: str) -> None:
    """Have the ``forkserver`` import ``modules`` once, so that children start with them.

    Takes effect if called before this process starts its first forkserver child
    (later calls are harmless and do nothing until a new fork server starts).
    """
    for m in modules:
        if m not in _PRELOAD:
            _PRELOAD.append(m)
    multiprocessing.get_context("forkserver").set_forkserver_preload(list(_PRELOAD))


def _child(conn: Any, fn: Callable[..., Any], args: tuple, kwargs: dict, memory_mb: int | None) -> None:
    """Body of the child process: limit memory, run, send ("ok", value) or ("error", text)."""
    try:
        os.setsid()  # own process group: the parent kills the whole group
    except OSError:
        pass
    if memory_mb is not None:
        import resource

        limit = memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        value = fn(*args, **kwargs)
    except MemoryError:
        conn.send(("memory", traceback.format_exc()))
    except BaseException:  # noqa: BLE001 - everything must reach the parent
        conn.send(("error", traceback.format_exc()))
    else:
        try:
            conn.send(("ok", value))
        except Exception:  # noqa: BLE001 - an unpicklable value is a crash, reported as such
            conn.send(("error", traceback.format_exc()))
    finally:
        conn.close()


def _kill(proc: multiprocessing.process.BaseProcess) -> None:
    """Kill the child's process group (it called setsid), then the child itself."""
    pid = proc.pid
    if pid is not None:
        try:
            os.killpg(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    proc.kill()
    proc.join(5)


def run_isolated(
    fn: Callable[..., T],
    *args: Any,
    timeout: float | None = None,
    memory_mb: int | None = None,
    method: str = "forkserver",
    **kwargs: Any,
) -> Outcome[T]:
    """Call ``fn(*args, **kwargs)`` in a child process; see the module docstring.

    ``timeout`` is wall-clock seconds (None: no limit; <= 0: a :class:`Timeout` without
    starting anything). ``memory_mb`` caps the child's address space. ``method`` is a
    :mod:`multiprocessing` start method (``forkserver`` or ``spawn``).
    """
    start = time.perf_counter()
    if timeout is not None and timeout <= 0:
        return Timeout(timeout, 0.0)
    ctx = multiprocessing.get_context(method)
    receive, send = ctx.Pipe(duplex=False)
    # Not a daemon, so that fn may start its own multiprocessing children; the finally
    # clause below kills the child whatever happens (timeout, KeyboardInterrupt, ...).
    proc = ctx.Process(target=_child, args=(send, fn, args, kwargs, memory_mb), daemon=False)
    proc.start()
    send.close()
    try:
        deadline = None if timeout is None else start + timeout
        while True:
            wait = 0.5 if deadline is None else min(0.5, max(0.0, deadline - time.perf_counter()))
            if receive.poll(wait):
                try:
                    kind, payload = receive.recv()
                except (EOFError, OSError):
                    proc.join(5)  # the child died without answering
                    return Crash(proc.exitcode, "", time.perf_counter() - start)
                proc.join(5)
                seconds = time.perf_counter() - start
                if kind == "ok":
                    return Finished(payload, seconds)
                return Crash(proc.exitcode, payload, seconds, memory_out=(kind == "memory"))
            if not proc.is_alive() and not receive.poll(0):
                proc.join(5)
                return Crash(proc.exitcode, "", time.perf_counter() - start)
            if deadline is not None and time.perf_counter() >= deadline:
                _kill(proc)
                return Timeout(timeout, time.perf_counter() - start)  # type: ignore[arg-type]
    finally:
        if proc.is_alive():
            _kill(proc)
        receive.close()

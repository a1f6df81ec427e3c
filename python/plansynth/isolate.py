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
with them, and it dies with its parent (``PR_SET_PDEATHSIG``, :mod:`plansynth.procs`);
so does the fork server, so that ``SIGKILL`` of the caller leaves nothing running. The
memory limit is ``RLIMIT_AS`` set in the child before ``fn`` runs. :func:`cancel_all`
kills every running child (a benchmark sweep on Ctrl-C): their :func:`run_isolated`
calls raise :class:`Cancelled`.

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
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

__all__ = ["Finished", "Timeout", "Crash", "Outcome", "Cancelled", "run_isolated", "preload", "cancel_all"]

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


Outcome = Finished[T] | Timeout | Crash


class Cancelled(Exception):
    """:func:`cancel_all` killed the child of this :func:`run_isolated` call."""


# "__main__" is multiprocessing's default for the fork server; the guard module makes the
# fork server die with the process that started it (it calls PR_SET_PDEATHSIG on import)
_PRELOAD: list[str] = ["__main__", "plansynth._forkserver_guard"]
_PRELOAD_SET = False

_LIVE_LOCK = threading.Lock()
_LIVE: dict[int, tuple[multiprocessing.process.BaseProcess, str]] = {}
_CANCELLED: set[int] = set()


def cancel_all() -> int:
    """Kill every child that a :func:`run_isolated` call of this process is waiting for
    (with its process group and descendants); those calls raise :class:`Cancelled`.
    Returns the number of children killed."""
    from plansynth.procs import kill_tree

    with _LIVE_LOCK:
        procs = list(_LIVE.items())
        _CANCELLED.update(pid for pid, _ in procs)
    for pid, (_, tag) in procs:
        kill_tree(pid, tag=tag)
    return len(procs)


def preload(*modules: str) -> None:
    """Have the ``forkserver`` import ``modules`` once, so that children start with them.

    Takes effect if called before this process starts its first forkserver child
    (later calls are harmless and do nothing until a new fork server starts).
    """
    global _PRELOAD_SET
    for m in modules:
        if m not in _PRELOAD:
            _PRELOAD.append(m)
    multiprocessing.get_context("forkserver").set_forkserver_preload(list(_PRELOAD))
    _PRELOAD_SET = True


def _child(conn: Any, fn: Callable[..., Any], args: tuple, kwargs: dict, memory_mb: int | None, tag: str = "") -> None:
    """Body of the child process: limit memory, run, send ("ok", value) or ("error", text).
    Processes it starts inherit ``tag`` in their environment (found and killed with it,
    even orphaned: :func:`plansynth.procs.kill_tree`)."""
    try:
        os.setsid()  # own process group: the parent kills the whole group
    except OSError:
        pass
    from plansynth.procs import die_with_parent, tagged_env

    die_with_parent()  # SIGKILL when the parent (the fork server, or the caller) dies
    if tag:
        os.environ.update(tagged_env(tag))
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


def _kill(proc: multiprocessing.process.BaseProcess, tag: str | None = None) -> None:
    """Kill the child's process group (it called setsid), its descendants and the
    processes carrying its ``tag``, then the child."""
    from plansynth.procs import kill_tree

    pid = proc.pid
    if pid is not None:
        kill_tree(pid, tag=tag)
    proc.kill()
    proc.join(5)


_OWNER_LOCK = threading.Lock()
_OWNER: dict[int, Any] = {}  # pid -> the request queue of that process's owner thread


def _ensure_forkserver() -> None:
    """Start the fork server (if it is not running) from one thread that lives as long
    as this process. The fork server dies with the thread that started it
    (``PR_SET_PDEATHSIG`` is tied to the thread that forked): started from a
    short-lived thread, it would take the children of other threads with it."""
    import queue

    with _OWNER_LOCK:
        if os.getpid() not in _OWNER:  # (a forked child has no owner thread of its own yet)
            requests: queue.Queue[tuple[threading.Event, list[BaseException]]] = queue.Queue()

            def serve() -> None:
                from multiprocessing import forkserver

                while True:
                    event, errors = requests.get()
                    try:
                        forkserver.ensure_running()
                    except BaseException as exc:  # noqa: BLE001 - handed to the caller
                        errors.append(exc)
                    finally:
                        event.set()

            threading.Thread(target=serve, name="plansynth-forkserver-owner", daemon=True).start()
            _OWNER[os.getpid()] = requests
        requests = _OWNER[os.getpid()]
    event, errors = threading.Event(), []
    requests.put((event, errors))
    event.wait()
    if errors:
        raise errors[0]


def _start_by(
    proc: multiprocessing.process.BaseProcess, deadline: float | None, tag: str, send: Any, receive: Any
) -> bool:
    """Start ``proc`` by ``deadline``; False if it could not be. The first start of a
    fork server imports its preloaded modules (cvc5: a second or more on a loaded
    machine) and ``Process.start`` waits for that, so it runs in a helper thread: when
    the deadline passes first, the helper kills the child as soon as it exists."""
    if deadline is None:
        proc.start()
        return True
    done = threading.Event()
    failed: list[BaseException] = []

    def start() -> None:
        try:
            proc.start()
        except BaseException as exc:  # noqa: BLE001 - handed to the caller below
            failed.append(exc)
        finally:
            done.set()

    def late() -> None:  # the caller gave up waiting: kill the child once it exists
        done.wait()
        if not failed:
            _kill(proc, tag)
        send.close()
        receive.close()

    threading.Thread(target=start, name="plansynth-isolate-start", daemon=True).start()
    try:
        ready = done.wait(max(0.0, deadline - time.perf_counter()))
    except BaseException:
        threading.Thread(target=late, name="plansynth-isolate-late", daemon=True).start()
        raise
    if not ready:
        threading.Thread(target=late, name="plansynth-isolate-late", daemon=True).start()
        return False
    if failed:
        raise failed[0]
    return True


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
    if method == "forkserver":
        if not _PRELOAD_SET:
            preload()
        _ensure_forkserver()
    from plansynth.procs import new_tag

    ctx = multiprocessing.get_context(method)
    tag = new_tag()
    receive, send = ctx.Pipe(duplex=False)
    # Not a daemon, so that fn may start its own multiprocessing children; the finally
    # clause below kills the child whatever happens (timeout, KeyboardInterrupt, ...).
    proc = ctx.Process(target=_child, args=(send, fn, args, kwargs, memory_mb, tag), daemon=False)
    deadline = None if timeout is None else start + timeout
    if not _start_by(proc, deadline, tag, send, receive):
        return Timeout(timeout, time.perf_counter() - start)  # type: ignore[arg-type]
    send.close()
    with _LIVE_LOCK:
        _LIVE[proc.pid] = (proc, tag)  # type: ignore[index]

    def cancelled() -> None:
        with _LIVE_LOCK:
            hit = proc.pid in _CANCELLED
        if hit:
            raise Cancelled(f"child {proc.pid} cancelled")

    try:
        while True:
            wait = 0.2 if deadline is None else min(0.2, max(0.0, deadline - time.perf_counter()))
            ready = receive.poll(wait)
            cancelled()
            if ready:
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
                _kill(proc, tag)
                return Timeout(timeout, time.perf_counter() - start)  # type: ignore[arg-type]
    finally:
        if proc.is_alive():
            _kill(proc, tag)
        receive.close()
        with _LIVE_LOCK:
            _LIVE.pop(proc.pid, None)  # type: ignore[arg-type]
            _CANCELLED.discard(proc.pid)  # type: ignore[arg-type]

"""Child processes that never outlive their budget or their parent (STYLE.md, point 4).

Solvers run as child processes (cvc5 through :mod:`plansynth.isolate`, external
SyGuS solvers through :mod:`plansynth.grid.backends.external`, benchmark runs through
:mod:`plansynth.bench.runner`). Three rules keep them from being left behind:

- each child runs in its own session and process group, and is killed as a group,
  together with every descendant still traceable to it (:func:`kill_tree`); a helper
  that escaped with ``setsid`` and was orphaned is found by the tag its environment
  inherited (:func:`tagged_env`, the technique of Jenkins' process tree killer);
- each child asks the kernel to kill it when its parent dies (:func:`die_with_parent`,
  ``PR_SET_PDEATHSIG`` through ``prctl`` on Linux), so that even ``SIGKILL`` of the
  ``plansynth`` process takes its solvers with it;
- ``SIGTERM`` to the ``plansynth`` command unwinds like Ctrl-C
  (:func:`terminate_as_interrupt`), so the clean-up code runs.

>>> import subprocess
>>> child = subprocess.Popen(["sleep", "30"], start_new_session=True)
>>> child.pid in descendants(os.getpid())
True
>>> kill_tree(child.pid); child.wait()
-9
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Callable, Mapping

__all__ = [
    "die_with_parent",
    "pdeathsig_preexec",
    "descendants",
    "snapshot",
    "kill_tree",
    "terminate_as_interrupt",
    "new_tag",
    "tagged_env",
    "tagged",
    "TAG_VARIABLE",
]

#: Environment variable that marks the processes of one solver run (":"-separated tags).
TAG_VARIABLE = "PLANSYNTH_RUN_TAGS"

_PR_SET_PDEATHSIG = 1


def die_with_parent(sig: int = signal.SIGKILL) -> bool:
    """Ask the kernel to send ``sig`` to this process when its parent dies (Linux
    ``prctl(PR_SET_PDEATHSIG)``); returns False where that is not available.

    Call it in the child, as early as possible. If the parent died already (the child
    was reparented before the call), the signal is sent at once.
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        parent = os.getppid()
        if libc.prctl(_PR_SET_PDEATHSIG, int(sig), 0, 0, 0) != 0:
            return False
    except (OSError, AttributeError):
        return False
    if parent == 1 or os.getppid() != parent:  # the parent is gone already
        os.kill(os.getpid(), sig)
    return True


def pdeathsig_preexec(sig: int = signal.SIGKILL) -> Callable[[], None] | None:
    """A ``preexec_fn`` for :class:`subprocess.Popen` that sets ``PR_SET_PDEATHSIG`` in
    the child (None where unavailable). The C function is looked up here, in the
    parent, so the child only makes the system call."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None

    def preexec() -> None:
        prctl(_PR_SET_PDEATHSIG, int(sig), 0, 0, 0)

    return preexec


def _stat(name: str) -> tuple[int, int] | None:
    """(parent pid, start time in clock ticks) of process ``name``, or None."""
    try:
        with open(f"/proc/{name}/stat", "rb") as f:
            stat = f.read()
    except OSError:
        return None
    # "pid (comm) state ppid ...": comm may contain spaces and parentheses
    rest = stat[stat.rfind(b")") + 2 :].split()
    if len(rest) < 20:
        return None
    return int(rest[1]), int(rest[19])


def _table() -> dict[int, tuple[int, int]]:
    """pid -> (parent pid, start time) of every process visible in /proc."""
    out: dict[int, tuple[int, int]] = {}
    try:
        entries = os.listdir("/proc")
    except OSError:
        return out
    for name in entries:
        if name.isdigit():
            st = _stat(name)
            if st is not None:
                out[int(name)] = st
    return out


def snapshot(pid: int) -> dict[int, int]:
    """Every live descendant of ``pid`` with its start time (to recognise it later even
    after it was reparented, and never to mistake a recycled pid for it)."""
    table = _table()
    children: dict[int, list[int]] = {}
    for p, (pp, _) in table.items():
        children.setdefault(pp, []).append(p)
    out: dict[int, int] = {}
    todo = [pid]
    while todo:
        for c in children.get(todo.pop(), ()):
            if c not in out:
                out[c] = table[c][1]
                todo.append(c)
    return out


def descendants(pid: int) -> set[int]:
    """Every live process whose chain of parents leads to ``pid`` (not ``pid`` itself)."""
    return set(snapshot(pid))


def new_tag() -> str:
    """A fresh tag for one solver run."""
    import uuid

    return uuid.uuid4().hex[:16]


def tagged_env(tag: str, base: Mapping[str, str] | None = None) -> dict[str, str]:
    """``base`` (default: this process's environment) with ``tag`` added to
    :data:`TAG_VARIABLE`; every process started with it, and every process those start,
    inherit the tag (unless they clear their environment)."""
    env = dict(os.environ if base is None else base)
    old = env.get(TAG_VARIABLE, "")
    env[TAG_VARIABLE] = f"{old}:{tag}" if old else tag
    return env


def tagged(tag: str) -> set[int]:
    """Live processes (other than this one) whose environment carries ``tag``."""
    needle = f"{TAG_VARIABLE}=".encode()
    out: set[int] = set()
    me = os.getpid()
    try:
        entries = os.listdir("/proc")
    except OSError:
        return out
    for name in entries:
        if not name.isdigit() or int(name) == me:
            continue
        try:
            with open(f"/proc/{name}/environ", "rb") as f:
                env = f.read()
        except OSError:
            continue
        for var in env.split(b"\0"):
            if var.startswith(needle) and tag.encode() in var[len(needle) :].split(b":"):
                out.add(int(name))
                break
    return out


def kill_tree(pid: int, *, group: bool = True, known: Mapping[int, int] | None = None, tag: str | None = None) -> None:
    """SIGKILL ``pid``'s process group (``group``: it called setsid), ``pid`` itself and
    every descendant of ``pid`` (found before anything is killed), plus the processes of
    ``known`` (pid -> start time, from earlier :func:`snapshot` calls: helpers that were
    orphaned meanwhile) that still have the start time they had then, and every process
    whose environment carries ``tag`` (:func:`tagged_env`). Processes already gone are
    ignored."""
    victims = snapshot(pid)
    if tag is not None:
        victims.update((p, 0) for p in tagged(tag) if p not in victims)
    for p, started in (known or {}).items():
        st = _stat(str(p))
        if st is not None and st[1] == started:
            victims[p] = started
    if group:
        try:
            os.killpg(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError, OSError):
            pass
    for p in (pid, *victims):
        try:
            os.kill(p, signal.SIGKILL)
        except (ProcessLookupError, PermissionError, OSError):
            pass


def _raise_interrupt(signum: int, frame: object) -> None:
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


def terminate_as_interrupt() -> None:
    """Make SIGTERM (and SIGHUP) raise :class:`KeyboardInterrupt` in the main thread, so
    that ``finally`` clauses kill the solver children before the process exits.
    Does nothing outside the main thread."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGTERM, signal.SIGHUP):
        try:
            signal.signal(sig, _raise_interrupt)
        except (ValueError, OSError):  # pragma: no cover - not the main thread
            pass

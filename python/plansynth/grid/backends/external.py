"""The ``external`` grid backend: any SyGuS-IF v2 solver, run as a command.

The problem is compiled per path length by :func:`plansynth.grid.sygus.compile_sygus`,
written to a .sl file, and the user's command is run on it. ``{file}`` in the command
stands for the file's path (appended at the end when absent). The solver must print its
answer to ``(check-synth)`` on stdout: a ``define-fun`` of ``move`` (realizable),
``infeasible`` (unrealizable) or anything else (unknown)::

    plansynth grid solve p.yaml --solver external --command "cvc5 --lang=sygus2 {file}"
    plansynth grid solve p.yaml --solver external \\
        --command "python -m plansynth.grid.backends.cvc5_cli {file}"

The command is split like a shell would (:func:`shlex.split`) but run without a shell.
It runs in its own session and process group, killed as a whole (with any helper it
started) when the time budget runs out or the caller stops, and it dies with the caller.
"""

from __future__ import annotations

import os
import selectors
import shlex
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.grid.backends._common import keep_file, outcome_from_answer, sl_file_name
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import GridStatus, LengthOutcome
from plansynth.grid.sygus import compile_sygus, sygus_limitation
from plansynth.io import write_output

__all__ = ["ExternalBackend", "command_argv"]

_EXAMPLE = 'e.g. --command "cvc5 --lang=sygus2 {file}"'


def command_argv(command: str, file: str) -> list[str]:
    """The argument vector for ``command`` on ``file``.

    >>> command_argv("cvc5 --lang=sygus2 {file}", "a b.sl")
    ['cvc5', '--lang=sygus2', 'a b.sl']
    >>> command_argv("mysolver -v", "p.sl")
    ['mysolver', '-v', 'p.sl']
    """
    argv = shlex.split(command)
    if any("{file}" in a for a in argv):
        return [a.replace("{file}", file) for a in argv]
    return argv + [file]


class ExternalBackend:
    """Run a SyGuS-IF v2 solver command on each compiled .sl file.

    ``command``: the command line (see the module docstring). ``keep_sl``: a directory in
    which to keep the .sl files (otherwise a temporary directory, removed afterwards).
    """

    name = "external"

    def __init__(self, command: str | None = None, keep_sl: str | Path | None = None) -> None:
        if not command or not command.strip():
            raise SolverUnavailable("external", f"give the solver's command line, {_EXAMPLE}")
        try:
            argv = shlex.split(command)
        except ValueError as exc:
            raise SolverUnavailable("external", f"cannot read the command {command!r}: {exc}") from None
        if not argv or shutil.which(argv[0]) is None:
            raise SolverUnavailable(
                "external", f"command {argv[0] if argv else command!r} not found on PATH ({_EXAMPLE})"
            )
        self.command = command
        self.keep_sl = keep_sl

    def version(self) -> str:
        return f"command: {self.command}"

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        limited = sygus_limitation(problem)
        if limited is not None:
            return LengthOutcome(GridStatus.UNKNOWN, steps, message=f"{self.name}: {limited[1]}")
        start = time.perf_counter()
        text = compile_sygus(problem, steps, depth_bound)
        kept = keep_file(self.keep_sl, problem, steps, depth_bound, text)
        counters: dict[str, Any] = {"universal_variables": steps * len(problem.obstacles), "sl_chars": len(text)}
        with tempfile.TemporaryDirectory(prefix="plansynth-") as tmp:
            path = kept or str(Path(tmp) / sl_file_name(problem, steps, depth_bound))
            if kept is None:
                write_output(path, text)  # atomic; a full /tmp is OutputUnwritable, not a traceback
            argv = command_argv(self.command, path)
            status, stdout, stderr, code = _run(argv, budget.seconds)
        seconds = time.perf_counter() - start
        counters["exit_status"] = code
        if status == "timeout":
            return LengthOutcome(
                GridStatus.UNKNOWN,
                steps,
                seconds=seconds,
                counters=counters,
                message=f"{argv[0]} ran out of the time budget ({budget.seconds:.3g} s)",
                artefact=kept,
            )
        outcome = outcome_from_answer(problem, steps, stdout, argv[0], seconds, counters, kept)
        if outcome.status is GridStatus.UNKNOWN and stderr.strip():
            tail = " ".join(stderr.strip().split())[-300:]
            outcome = LengthOutcome(
                GridStatus.UNKNOWN,
                steps,
                seconds=seconds,
                counters=counters,
                message=f"{outcome.message} (exit status {code}; stderr: {tail})",
                artefact=kept,
            )
        return outcome


#: Seconds to keep reading after the solver exited: a helper it left behind may hold its
#: output pipe open, and its end-of-file is not waited for beyond this.
DRAIN_SECONDS = 0.5
#: Output kept per stream (the rest is read and dropped, so a chatty solver cannot fill memory).
MAX_OUTPUT = 16 * 2**20


def _run(argv: list[str], timeout: float | None) -> tuple[str, str, str, int | None]:
    """Run ``argv`` in its own session; ("done" | "timeout", stdout, stderr, exit status).

    The solver dies with this process (``PR_SET_PDEATHSIG``), is killed with its process
    group and every descendant seen while it ran, whatever happens (budget, Ctrl-C,
    an error here), and its output is read against the deadline: a helper that escaped
    the group and holds the pipe cannot make this wait (:mod:`plansynth.procs`).
    """
    from plansynth.procs import kill_tree, new_tag, pdeathsig_preexec, snapshot, tagged_env

    tag = new_tag()
    proc = subprocess.Popen(
        argv,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
        preexec_fn=pdeathsig_preexec(),
        env=tagged_env(tag),
    )
    assert proc.stdout is not None and proc.stderr is not None
    fd_out, fd_err = proc.stdout.fileno(), proc.stderr.fileno()
    buffers = {fd_out: bytearray(), fd_err: bytearray()}
    status = "done"
    seen: dict[int, int] = {}
    start = time.monotonic()
    deadline = None if timeout is None else start + timeout
    exited: float | None = None
    cleaned = False  # its group and helpers killed once it exited
    next_look = start
    try:
        with selectors.DefaultSelector() as sel:
            for stream in (proc.stdout, proc.stderr):
                sel.register(stream, selectors.EVENT_READ)
            while sel.get_map():
                now = time.monotonic()
                if exited is None and proc.poll() is not None:
                    exited = now
                    kill_tree(proc.pid, known=seen, tag=tag)  # its helpers: the pipe closes now
                    cleaned = True
                if exited is not None and now - exited > DRAIN_SECONDS:
                    break  # whoever still holds the pipe is not the solver
                if deadline is not None and now >= deadline:
                    status = "timeout"
                    break
                if exited is None and now >= next_look:
                    seen.update(snapshot(proc.pid))  # helpers, found while they are still its descendants
                    next_look = now + 0.5
                wait = 0.1 if deadline is None else max(0.0, min(0.1, deadline - now))
                for key, _ in sel.select(wait):
                    chunk = os.read(key.fd, 65536)
                    if not chunk:
                        sel.unregister(key.fileobj)
                        continue
                    buf = buffers[key.fd]
                    if len(buf) < MAX_OUTPUT:
                        buf += chunk[: MAX_OUTPUT - len(buf)]
        if status == "done" and exited is None:
            # both pipes closed; let the solver exit by itself, within the budget
            try:
                proc.wait(None if deadline is None else max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                status = "timeout"
    finally:
        if not cleaned or proc.poll() is None:
            kill_tree(proc.pid, known=seen, tag=tag)
        proc.wait()
        proc.stdout.close()
        proc.stderr.close()
    out, err = (bytes(buffers[fd]).decode("utf-8", errors="replace") for fd in (fd_out, fd_err))
    return status, out, err, proc.returncode

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
It runs in its own process group, killed as a whole when the time budget runs out.
"""

from __future__ import annotations

import os
import shlex
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.grid.backends._common import keep_file, outcome_from_answer, sl_file_name
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import GridStatus, LengthOutcome, register_backend
from plansynth.grid.sygus import compile_sygus
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
            raise SolverUnavailable("external", f"command {argv[0] if argv else command!r} not found on PATH ({_EXAMPLE})")
        self.command = command
        self.keep_sl = keep_sl

    def version(self) -> str:
        return f"command: {self.command}"

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
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
            return LengthOutcome(GridStatus.UNKNOWN, steps, seconds=seconds, counters=counters,
                                 message=f"{argv[0]} ran out of the time budget ({budget.seconds:.3g} s)", artefact=kept)
        outcome = outcome_from_answer(problem, steps, stdout, argv[0], seconds, counters, kept)
        if outcome.status is GridStatus.UNKNOWN and stderr.strip():
            tail = " ".join(stderr.strip().split())[-300:]
            outcome = LengthOutcome(GridStatus.UNKNOWN, steps, seconds=seconds, counters=counters,
                                    message=f"{outcome.message} (exit status {code}; stderr: {tail})", artefact=kept)
        return outcome


def _run(argv: list[str], timeout: float | None) -> tuple[str, str, str, int | None]:
    """Run ``argv`` in its own process group; ("done" | "timeout", stdout, stderr, exit status)."""
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
        return "done", out, err, proc.returncode
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = proc.communicate()
        return "timeout", out, err, proc.returncode


register_backend("external", ExternalBackend)

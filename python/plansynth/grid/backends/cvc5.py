"""The ``cvc5`` grid backend: the compiled SyGuS-IF v2 text, solved by cvc5's Python API.

For each path length the problem is compiled by :func:`plansynth.grid.sygus.compile_sygus`
and the *exact text* is handed to cvc5's parser (``cvc5.InputParser`` reading a string),
so what the solver sees is what ``--keep-sl DIR`` writes and what a user can rerun by
hand (``python -m plansynth.grid.backends.cvc5_cli FILE``, or a cvc5 binary with
``--lang=sygus2``). The solver runs in a child process (:mod:`plansynth.isolate`),
so the time budget really stops it and a crash costs one answer, not the session.

cvc5 answers ``(check-synth)`` with a ``define-fun`` (realizable), ``infeasible`` (no
program of the grammar wins: unrealizable, relative to the depth bound if one is given)
or ``fail`` (unknown). cvc5 options are passed by name, as on its command line without
the dashes, e.g. ``{"sygus-enum": "fast"}``.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import cvc5

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem
from plansynth.grid.backends._common import keep_file, outcome_from_answer, sl_file_name
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import GridStatus, LengthOutcome
from plansynth.grid.sygus import compile_sygus, sygus_limitation
from plansynth.isolate import Crash, Finished, preload, run_isolated

__all__ = ["Cvc5Backend", "run_sygus_text", "run_smt_text", "cvc5_version", "parse_options", "check_options"]


def cvc5_version() -> str:
    """The version of the cvc5 Python package, as cvc5 reports it."""
    v = cvc5.Solver(cvc5.TermManager()).getVersion()
    return v.decode() if isinstance(v, bytes) else str(v)


def parse_options(items: Sequence[str] | Mapping[str, Any] | None) -> dict[str, str]:
    """cvc5 options from ``KEY=VALUE`` strings (``--KEY=VALUE`` and bare ``KEY`` also work)
    or a mapping; the values are strings as on cvc5's command line.

    >>> parse_options(["--sygus-enum=fast", "sygus-simple-sym-break=none", "stats"])
    {'sygus-enum': 'fast', 'sygus-simple-sym-break': 'none', 'stats': 'true'}
    """
    if items is None:
        return {}
    if isinstance(items, Mapping):
        return {str(k).lstrip("-"): _value(v) for k, v in items.items()}
    out: dict[str, str] = {}
    for item in items:
        key, sep, value = item.partition("=")
        out[key.strip().lstrip("-")] = value.strip() if sep else "true"
    return out


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def check_options(options: Mapping[str, str]) -> None:
    """Raise :class:`InvalidProblem` naming the option cvc5 rejects, if any."""
    solver = cvc5.Solver(cvc5.TermManager())
    for key, value in options.items():
        try:
            solver.setOption(key, value)
        except RuntimeError as exc:
            raise InvalidProblem("cvc5 options", key, str(exc).strip()) from None


def run_sygus_text(text: str, options: Mapping[str, str] | None = None, name: str = "input.sl") -> str:
    """Run SyGuS-IF v2 ``text`` through cvc5's parser and solver, as the cvc5 binary would;
    return everything the commands print (the ``(check-synth)`` answer included).

    This runs in the calling process; the backend calls it in a child process.

    >>> print(run_sygus_text('''(set-logic LIA)
    ... (synth-fun f ((x Int)) Int ((Start Int)) ((Start Int (x 0 1 (+ Start Start)))))
    ... (declare-var x Int)
    ... (constraint (= (f x) (+ x 1)))
    ... (check-synth)''').strip())
    (
    (define-fun f ((x Int)) Int (+ x 1))
    )
    """
    return _run_text(text, {"sygus": "true", **(options or {})}, cvc5.InputLanguage.SYGUS_2_1, name)


def run_smt_text(text: str, options: Mapping[str, str] | None = None, name: str = "input.smt2") -> str:
    """Run SMT-LIB 2.6 ``text`` (for example :func:`plansynth.grid.sygus.compile_check`'s)
    with cvc5 in the calling process; return what the commands print.

    >>> run_smt_text("(set-logic LIA) (declare-fun x () Int) (assert (< x x)) (check-sat)")
    'unsat\\n'
    """
    return _run_text(text, dict(options or {}), cvc5.InputLanguage.SMT_LIB_2_6, name)


def _run_text(text: str, options: Mapping[str, str], lang: Any, name: str) -> str:
    solver = cvc5.Solver(cvc5.TermManager())
    for key, value in options.items():
        solver.setOption(key, value)
    symbols = cvc5.SymbolManager(solver.getTermManager())
    parser = cvc5.InputParser(solver, symbols)
    parser.setStringInput(lang, text, name)
    printed: list[str] = []
    while True:
        command = parser.nextCommand()
        if command.isNull():
            break
        out = command.invoke(solver, symbols)
        if out:
            printed.append(out)
    return "".join(printed)


def _timed_run(text: str, options: Mapping[str, str], name: str) -> tuple[str, float]:
    """Child-process body: the solver's output and the CPU seconds it took (the wall
    clock says little on a loaded machine)."""
    cpu = time.process_time()
    out = run_sygus_text(text, options, name)
    return out, time.process_time() - cpu


class Cvc5Backend:
    """Solve one path length with cvc5 (see the module docstring).

    ``options``: cvc5 options (mapping or ``KEY=VALUE`` strings). ``keep_sl``: a
    directory in which to keep the .sl file of every attempt.
    """

    name = "cvc5"

    def __init__(
        self, options: Sequence[str] | Mapping[str, Any] | None = None, keep_sl: str | Path | None = None
    ) -> None:
        self.options = parse_options(options)
        check_options(self.options)
        self.keep_sl = keep_sl
        preload(__name__)  # children start with cvc5 imported

    def version(self) -> str:
        return cvc5_version()

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        limited = sygus_limitation(problem)
        if limited is not None:
            return LengthOutcome(GridStatus.UNKNOWN, steps, message=f"{self.name}: {limited[1]}")
        start = time.perf_counter()
        text = compile_sygus(problem, steps, depth_bound)
        artefact = keep_file(self.keep_sl, problem, steps, depth_bound, text)
        counters: dict[str, Any] = {
            "universal_variables": steps * len(problem.obstacles),
            "sl_chars": len(text),
        }
        outcome = run_isolated(
            _timed_run,
            text,
            self.options,
            sl_file_name(problem, steps, depth_bound),
            timeout=budget.seconds,
            memory_mb=budget.memory_mb,
        )
        seconds = time.perf_counter() - start
        if isinstance(outcome, Finished):
            output, cpu = outcome.value
            counters["solver_seconds"] = round(outcome.seconds, 6)
            counters["solver_cpu_seconds"] = round(cpu, 6)
            return outcome_from_answer(problem, steps, output, "cvc5", seconds, counters, artefact)
        if isinstance(outcome, Crash):
            limit = "" if budget.memory_mb is None else f" (memory limit {budget.memory_mb} MB)"
            return LengthOutcome(
                GridStatus.UNKNOWN,
                steps,
                seconds=seconds,
                counters=counters,
                message=f"cvc5 crashed: {outcome.describe()}{limit}",
                artefact=artefact,
            )
        return LengthOutcome(
            GridStatus.UNKNOWN,
            steps,
            seconds=seconds,
            counters=counters,
            message=f"cvc5 ran out of the time budget ({budget.seconds:.3g} s)",
            artefact=artefact,
        )

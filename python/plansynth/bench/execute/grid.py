"""A grid run: a grid backend on one instance, in this process or through the CLI.

Every registered grid backend (``native``, ``cvc5``, ``external``) runs through
:func:`plansynth.grid.solve.solve`, which checks every controller with the independent
verifier. Grid families in :data:`plansynth.bench.families.CLI_TIMED_FAMILIES` (the
reactive suite and our reactive families) run through the command line instead, in a
fresh process, as their targets are stated: ``plansynth grid solve FILE --timeout T``;
the run records that process's wall clock (``cli_wall``, start-up included), whether the
budget was kept (``budget_kept``: ``cli_wall <= T + 1 s``) and ``depth_minimal`` beside
the solve time the result file reports (``time``). Both ways map the answer to a status
and sum the attempts' counters the same way.

>>> _grid_status("realizable", True, {}), _grid_status(None, None, {"refuted_by_verifier": 1})
('solved', 'invalid')
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping
from typing import Any

from plansynth.bench.families.grid import CLI_TIMED_FAMILIES
from plansynth.budget import Budget

__all__ = ["run_grid", "BUDGET_SLACK_SECONDS"]


#: Slack of the budget check: a run through the CLI keeps ``--timeout T`` when its whole
#: process (start-up included) ends within T + 1 s (the CLI timing target: "at most T + 1 s").
BUDGET_SLACK_SECONDS = 1.0

#: The families with the omega peer (:mod:`plansynth.bench.execute.omega`), whose time
#: starts after omega and dd are imported: there a backend's modules are imported before
#: its clock starts too, so that neither side's time counts module imports.
UNTIMED_IMPORT_FAMILIES = ("moving-obstacle", "robot-grid", "robot-grid-fast")

#: What a solve imports on first use, per backend (its engine's and the verifier's
#: modules); importing a module twice costs nothing.
SOLVE_MODULES = {
    "native": (
        "numpy",
        "plansynth.grid.native.engine",
        "plansynth.grid.native.synth",
        "plansynth.grid.native.product.solve",
        "plansynth.grid.native.product.fast_safety",
        "plansynth.grid.native.product.compiled_witness",
        "plansynth.grid.verify",
        "plansynth.grid.verify.invariant_compiled",
    ),
}


def run_grid(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    """The attributes of grid ``task`` on instance ``inst``."""
    if inst.family in CLI_TIMED_FAMILIES:
        return _grid_cli(inst, task)
    return _grid_in_process(inst, task)


def _cli_command(solver: str, problem_file: str, out: str, timeout: float, options: Mapping[str, Any]) -> list[str]:
    """The ``plansynth grid solve`` command line of one run (the installed console
    script beside this interpreter, else the same entry point through ``python -c``)."""
    import shutil
    import sys
    from pathlib import Path

    script = Path(sys.executable).with_name("plansynth")
    exe = (
        [str(script)]
        if script.is_file()
        else (
            [shutil.which("plansynth")]
            if shutil.which("plansynth")
            else [sys.executable, "-c", "from plansynth.cli import main; main()"]
        )
    )
    cmd = [*exe, "grid", "solve", problem_file, "--solver", solver, "--timeout", f"{float(timeout):g}", "--out", out]
    for key, value in options.items():
        cmd += ["--command", str(value)] if key == "command" else ["-O", f"{key}={value}"]
    return cmd


def _grid_cli(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    """One run of ``plansynth grid solve FILE --timeout T`` in a fresh process, as a user
    runs it (the CLI timing targets): ``cli_wall`` is that process's wall clock from spawn
    to exit, start-up included; ``time`` is the solve time the result file reports.
    The answer, program, depth, ``depth_minimal`` and verification are read from the
    result file (the CLI runs the independent verifier before writing it)."""
    import json
    import subprocess
    import tempfile
    from pathlib import Path

    import yaml

    from plansynth.bench.families.grid_problems import reactive_suite_dir
    from plansynth.procs import pdeathsig_preexec

    timeout = float(task["timeout"])
    with tempfile.TemporaryDirectory(prefix="plansynth-bench-") as tmp:
        if inst.family == "reactive-suite":
            problem_file = str(reactive_suite_dir() / f"{inst.name}.yaml")
        else:
            problem_file = str(Path(tmp) / f"{inst.name}.yaml")
            Path(problem_file).write_text(
                yaml.safe_dump(json.loads(json.dumps(inst.document())), sort_keys=False), encoding="utf-8"
            )
        out = str(Path(tmp) / "result.json")
        cmd = _cli_command(task["solver"], problem_file, out, timeout, dict(task.get("options") or {}))
        t0 = time.perf_counter()
        proc = subprocess.Popen(
            cmd,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            errors="replace",
            preexec_fn=pdeathsig_preexec(),
        )
        killed = False
        try:
            # the runner's hard limit (T + grace) kills this whole process group anyway
            stdout, stderr = proc.communicate(timeout=timeout + 4 * BUDGET_SLACK_SECONDS)
        except subprocess.TimeoutExpired:
            proc.kill()
            killed = True
            stdout, stderr = proc.communicate()
        wall = time.perf_counter() - t0
        result = json.loads(Path(out).read_text(encoding="utf-8")) if Path(out).is_file() else None
    kept = wall <= timeout + BUDGET_SLACK_SECONDS
    shown = [
        f"{inst.name}.yaml" if a == problem_file else "result.json" if a == out else a for a in cmd[cmd.index("grid") :]
    ]  # the command as a user types it, without this machine's paths
    attributes: dict[str, Any] = {
        "cli_wall": wall,
        "budget_kept": kept,
        "exit_status": proc.returncode,
        "expected": inst.expected,
        "command": "plansynth " + " ".join(shown),
    }
    if result is None:  # no result file: bad input, a crash, or killed past its budget
        status = "timeout" if killed else "crash"
        return {
            "status": status,
            "solved": 0,
            "time": wall,
            "wall": wall,
            "message": (stderr or stdout or f"exit status {proc.returncode}")[-2000:],
            "attributes": attributes,
        }
    counters = _summed(a.get("counters") or {} for a in result.get("attempts") or [])
    status = _grid_status(result.get("status"), result.get("verified"), counters)
    program = result.get("program")
    attributes.update(
        {
            "program": program,
            "depth_minimal": result.get("depth_minimal"),
            "counters": counters,
            "attempts": [
                (a.get("steps"), a.get("status"), round(float(a.get("seconds") or 0), 4))
                for a in result.get("attempts") or []
            ],
        }
    )
    from plansynth.grid.programs import parse_program, size

    return {
        "status": status,
        "solved": int(status == "solved"),
        "valid": None if program is None else int(result.get("verified") is True),
        "time": wall if result.get("seconds") is None else float(result["seconds"]),
        "depth": result.get("depth"),
        "size": None if program is None else size(parse_program(program)),
        "steps": result.get("steps"),
        "iterations": len(result.get("attempts") or []),
        "solver_version": result.get("solver_version"),
        "message": str(result.get("message") or "")[:2000],
        "attributes": attributes,
    }


def _summed(per_attempt: Iterable[Mapping[str, Any]]) -> dict[str, Any]:
    """The numeric counters of a grid run's attempts (one per path length), summed."""
    out: dict[str, Any] = {}
    for counters in per_attempt:
        for k, v in counters.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                out[k] = out.get(k, 0) + v
    return out


def _grid_status(answer: str | None, verified: Any, counters: Mapping[str, Any]) -> str:
    """A grid run's status from its answer (``status`` of the result): a program the
    verifier refuted, in any attempt, is a wrong answer, ``invalid``, not a missing one."""
    if answer == "realizable":
        return "solved" if verified is True else "invalid"
    if answer == "unrealizable":
        return "unrealizable"
    return "invalid" if counters.get("refuted_by_verifier") else "unknown"


def _import_solve_modules(solver: str) -> None:
    """Import what a solve with ``solver`` loads on first use (:data:`SOLVE_MODULES`),
    before its clock starts."""
    import importlib

    from plansynth.grid.result import backend_factory

    backend_factory(solver)
    for name in SOLVE_MODULES.get(solver, ()):
        importlib.import_module(name)


def _grid_in_process(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.grid.programs import size
    from plansynth.grid.solve import solve

    problem = inst.build()
    if inst.family in UNTIMED_IMPORT_FAMILIES:
        _import_solve_modules(task["solver"])
    # the sweep's memory limit is the solver's budget too (as for omega): without it the
    # engines' default applies, and a game between the two stops at the default
    budget = Budget(seconds=float(task["timeout"]), memory_mb=task.get("memory_mb"))
    options = dict(task.get("options") or {})
    if task["solver"] == "native":  # one NativeOptions value, built from the sweep's -O native:KEY=VALUE
        from plansynth.grid.native.options import NativeOptions

        options = {"options": NativeOptions.parse([f"{k}={v}" for k, v in options.items()])}
    res = solve(problem, solver=task["solver"], budget=budget, **options)
    counters = _summed(a.counters for a in res.attempts)
    status = _grid_status(res.status.value, res.verified, counters)
    return {
        "status": status,
        "solved": int(status == "solved"),
        "valid": None if res.program is None else int(bool(res.verified)),
        "time": res.seconds,
        "depth": res.depth,
        "size": None if res.program is None else size(res.program),
        "steps": res.steps,
        "iterations": len(res.attempts),
        "solver_version": res.solver_version,
        "message": res.message[:2000],
        "attributes": {
            "program": None if res.program is None else str(res.program),
            "expected": inst.expected,
            "counters": counters,
            "attempts": [(a.steps, a.status.value, round(a.seconds, 4)) for a in res.attempts],
        },
    }

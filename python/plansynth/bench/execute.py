"""One benchmark run, executed inside the child process the runner starts.

:func:`execute` maps a task (a plain dict: instance, solver, repeat, timeout, seed,
options) to the run's attributes (a plain dict, a row of the ``runs`` table). Every
plan or controller a solver returns is checked by the same independent checker for
every solver -- :func:`plansynth.grid.verify.verify` (inside
:func:`plansynth.grid.solve.solve`) for grid controllers, :func:`plansynth.reach.validate.validate`
for trajectories -- and counted as solved only if it passes.

Solver names: grid -- any registered grid backend (``native``, ``cvc5``, ``external``);
reach -- every planner of :func:`plansynth.reach.solve` (``lazy-smt`` and its named
configurations, ``milp``, ``milp-bigm``, ``rrt``, ``est``, ``kpiece``, ``gcs``, ``milp-ltl``),
run through :func:`plansynth.reach.solve`, which validates every answer (a gcs curve in the
validator's ``dynamics="curve"`` mode; a mission also by the mission checker).
Grid families in :data:`plansynth.bench.families.CLI_TIMED_FAMILIES` (the reactive
suite and our reactive families) run through the command line instead, in a fresh
process, as issue 11's targets are stated: ``plansynth grid solve FILE --timeout T``;
the run records that process's wall clock (``cli_wall``, start-up included), whether the
budget was kept (``budget_kept``: ``cli_wall <= T + 1 s``) and ``depth_minimal`` beside
the solve time the result file reports (``time``).
For every solved run whose regions are one per time step, the run also records
``oracle_lp``: the time of one cold LP over its final region sequence
(:func:`plansynth.reach.oracle.oracle_lp`), the limit its total is compared with.
Names starting with ``debug-`` exercise the runner:
``debug-ok`` returns at once, ``debug-sleep`` sleeps past any limit, ``debug-crash``
kills its own process with SIGSEGV, ``debug-raise`` raises, ``debug-memory`` allocates
until the memory limit stops it.
"""

from __future__ import annotations

import os
import resource
import time
from collections.abc import Iterable, Mapping
from typing import Any

from plansynth.budget import Budget
from plansynth.bench.families import instance_from_task

__all__ = ["execute", "solver_version", "REACH_SOLVERS"]

REACH_SOLVERS = ("lazy-smt", "milp", "milp-bigm", "rrt", "est", "kpiece", "gcs")


def _peak_memory_mb() -> float:
    # Peak RSS of this child and of any solver process it waited for (Linux: KiB).
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return max(own, children) / 1024.0


def execute(task: Mapping[str, Any]) -> dict[str, Any]:
    """Run ``task`` and return its attributes (status, time, counters, ...)."""
    solver = task["solver"]
    _allow_children()
    t0 = time.perf_counter()
    from plansynth.errors import SolverUnavailable

    try:
        if solver.startswith("debug-"):
            attrs = _debug(solver, task)
        else:
            inst = instance_from_task(task)
            attrs = _grid(inst, task) if inst.kind == "grid" else _reach(inst, task)
    except SolverUnavailable as exc:
        attrs = {"status": "unavailable", "solved": 0, "message": str(exc)}
    attrs.setdefault("wall", time.perf_counter() - t0)
    attrs["memory"] = _peak_memory_mb()
    return attrs


def _allow_children() -> None:
    """Let this (daemonic) child start its own children: some backends isolate the
    solver once more (cvc5 in a child process). They kill those children themselves
    when their budget ends, which is before our hard limit."""
    import multiprocessing

    multiprocessing.current_process()._config["daemon"] = False  # type: ignore[attr-defined]


def _debug(solver: str, task: Mapping[str, Any]) -> dict[str, Any]:
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


# ---------------------------------------------------------------------------- grid


#: Slack of the budget check: a run through the CLI keeps ``--timeout T`` when its whole
#: process (start-up included) ends within T + 1 s (issue 11, Targets: "at most T + 1 s").
BUDGET_SLACK_SECONDS = 1.0


def _grid(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.bench.families import CLI_TIMED_FAMILIES

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
    exe = [str(script)] if script.is_file() else ([shutil.which("plansynth")] if shutil.which("plansynth") else
                                                  [sys.executable, "-c", "from plansynth.cli import main; main()"])
    cmd = [*exe, "grid", "solve", problem_file, "--solver", solver, "--timeout", f"{float(timeout):g}", "--out", out]
    for key, value in options.items():
        cmd += ["--command", str(value)] if key == "command" else ["-O", f"{key}={value}"]
    return cmd


def _grid_cli(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    """One run of ``plansynth grid solve FILE --timeout T`` in a fresh process, as a user
    runs it (issue 11, Targets): ``cli_wall`` is that process's wall clock from spawn
    to exit, start-up included; ``time`` is the solve time the result file reports.
    The answer, program, depth, ``depth_minimal`` and verification are read from the
    result file (the CLI runs the independent verifier before writing it)."""
    import json
    import subprocess
    import tempfile
    from pathlib import Path

    import yaml

    from plansynth.bench.families import reactive_suite_dir
    from plansynth.procs import pdeathsig_preexec

    timeout = float(task["timeout"])
    with tempfile.TemporaryDirectory(prefix="plansynth-bench-") as tmp:
        if inst.family == "reactive-suite":
            problem_file = str(reactive_suite_dir() / f"{inst.name}.yaml")
        else:
            problem_file = str(Path(tmp) / f"{inst.name}.yaml")
            Path(problem_file).write_text(yaml.safe_dump(json.loads(json.dumps(inst.document())), sort_keys=False),
                                          encoding="utf-8")
        out = str(Path(tmp) / "result.json")
        cmd = _cli_command(task["solver"], problem_file, out, timeout, dict(task.get("options") or {}))
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                                preexec_fn=pdeathsig_preexec())
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
    shown = [f"{inst.name}.yaml" if a == problem_file else "result.json" if a == out else a
             for a in cmd[cmd.index("grid"):]]  # the command as a user types it, without this machine's paths
    attributes: dict[str, Any] = {"cli_wall": wall, "budget_kept": kept, "exit_status": proc.returncode,
                                  "expected": inst.expected, "command": "plansynth " + " ".join(shown)}
    if result is None:  # no result file: bad input, a crash, or killed past its budget
        status = "timeout" if killed else "crash"
        return {"status": status, "solved": 0, "time": wall, "wall": wall,
                "message": (stderr or stdout or f"exit status {proc.returncode}")[-2000:], "attributes": attributes}
    counters = _summed(a.get("counters") or {} for a in result.get("attempts") or [])
    status = _grid_status(result.get("status"), result.get("verified"), counters)
    program = result.get("program")
    attributes.update({"program": program, "depth_minimal": result.get("depth_minimal"), "counters": counters,
                       "attempts": [(a.get("steps"), a.get("status"), round(float(a.get("seconds") or 0), 4))
                                    for a in result.get("attempts") or []]})
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


def _grid_in_process(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.grid.programs import size
    from plansynth.grid.solve import solve

    problem = inst.build()
    budget = Budget(seconds=float(task["timeout"]))
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
        "attributes": {"program": None if res.program is None else str(res.program), "expected": inst.expected,
                       "counters": counters, "attempts": [(a.steps, a.status.value, round(a.seconds, 4)) for a in res.attempts]},
    }


# ---------------------------------------------------------------------------- reach


def solver_version(solver: str) -> str:
    from importlib.metadata import version

    pkg = {"rrt": "ompl", "est": "ompl", "kpiece": "ompl", "milp-bigm": "highspy", "milp": "highspy",
           "lazy-smt": "python-sat", "native": "plansynth", "cvc5": "cvc5", "gcs": "drake"}.get(solver, "plansynth")
    try:
        return f"{pkg} {version(pkg)}"
    except Exception:
        return pkg


def _reach(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.reach.solve import get_planner, solve

    started = time.perf_counter()
    problem = inst.build()
    solver = task["solver"]
    budget = Budget(seconds=float(task["timeout"]))
    seed = int(task.get("seed", 0)) + int(task.get("repeat", 0))
    planner = get_planner(solver)
    values = dict(task.get("options") or {})
    if "seed" in getattr(planner, "option_names", lambda: ())():  # the sampling planners (OMPL)
        values["seed"] = seed
    # one path for every planner: solve() plans (a sized robot in its configuration
    # space) and validates (missions also mission-checked); its verdict is the run's
    res = solve(problem, solver, budget, planner.configure(**values))
    valid = None if res.validated is None else int(bool(res.validated))
    dense = getattr(res, "curve_validation", None)
    if dense is not None:  # a continuous-time curve (gcs): its dense sampling says whether segments are safe
        segment_safe = int(bool(dense.segment_safe))
    else:
        segment_safe = None if res.validation is None else int(bool(res.validation.segment_safe))
    if res.status.value == "found":
        status = "solved" if valid == 1 else "invalid"
    elif res.status.value == "infeasible":
        status = "infeasible"
    else:
        status = "invalid" if valid == 0 else "unknown"
    c = dict(res.counters or {})
    timings = {k: float(v) for k, v in (res.timings or {}).items() if isinstance(v, (int, float))}
    oracle = None
    # (not for a mission: its regions index the label-refined abstraction, and a lasso's
    # loop closure is no CON-PLAN row, so the reach-avoid oracle LP does not apply)
    if status == "solved" and res.regions is not None and res.horizon is not None and problem.mission is None \
            and len(res.regions) == res.horizon + 1 and getattr(res, "guarantee", None) in ("segments", "samples"):
        from plansynth.reach.oracle import oracle_lp

        from plansynth.bench.runner import wall_limit

        # within the child's wall-clock limit (the budget plus its grace), 2 s kept for the rest;
        # with less than a second left the run records no limit
        left = wall_limit(task) - (time.perf_counter() - started) - 2.0
        lim = None if left < 1.0 else oracle_lp(problem, res.regions, segment_safe=res.guarantee == "segments",
                                                seconds=left)
        if lim is not None:
            oracle = {"seconds": lim.seconds, "build": lim.build_seconds, "solve": lim.solve_seconds,
                      "feasible": lim.feasible}
    return {
        "status": status,
        "solved": int(status == "solved"),
        "valid": valid,
        "segment_safe": segment_safe,
        "time": float(res.seconds),
        "horizon": res.horizon,
        "iterations": c.get("iterations", c.get("milp_calls")),
        "lp_calls": c.get("lp_calls"),
        "sat_calls": c.get("sat_calls"),
        "regions": c.get("regions"),
        "solver_version": solver_version(solver),
        "message": (res.message or "")[:2000],
        "attributes": {"counters": {k: v for k, v in c.items() if isinstance(v, (int, float, str))},
                       "timings": timings, "seed": seed, "oracle_lp": oracle,
                       "guarantee": getattr(res, "guarantee", None),
                       "duration": None if res.trajectory is None or res.horizon is None or not problem.dynamics.dt
                       else res.horizon * float(problem.dynamics.dt)},
    }

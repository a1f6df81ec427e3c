"""One benchmark run, executed inside the child process the runner starts.

:func:`execute` maps a task (a plain dict: instance, solver, repeat, timeout, seed,
options) to the run's attributes (a plain dict, a row of the ``runs`` table). Every
plan or controller a solver returns is checked by the same independent checker for
every solver -- :func:`plansynth.grid.verify.verify` (inside
:func:`plansynth.grid.solve.solve`) for grid controllers, :func:`plansynth.reach.validate.validate`
for trajectories -- and counted as solved only if it passes.

Solver names: grid -- any registered grid backend (``native``, ``cvc5``, ``external``);
reach -- ``lazy-smt`` and ``milp`` (R2's planners, through :func:`plansynth.reach.solve`),
``milp-bigm`` (:mod:`plansynth.reach.milp_bigm`), ``rrt``, ``est``, ``kpiece``
(:mod:`plansynth.reach.rrt`), ``gcs`` (:mod:`plansynth.reach.gcs`, Drake's Graphs of Convex
Sets, through :func:`plansynth.reach.solve`; its continuous-time curve is validated in the
validator's ``dynamics="curve"`` mode, the exact discrete dynamics are not required).
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
from collections.abc import Mapping
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


def _grid(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.grid.programs import size
    from plansynth.grid.result import GridStatus
    from plansynth.grid.solve import solve

    problem = inst.build()
    budget = Budget(seconds=float(task["timeout"]))
    options = dict(task.get("options") or {})
    if task["solver"] == "native":  # one NativeOptions value, built from the sweep's -O native:KEY=VALUE
        from plansynth.grid.native.options import NativeOptions

        options = {"options": NativeOptions.parse([f"{k}={v}" for k, v in options.items()])}
    res = solve(problem, solver=task["solver"], budget=budget, **options)
    counters: dict[str, Any] = {}
    for a in res.attempts:
        for k, v in a.counters.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                counters[k] = counters.get(k, 0) + v
    if res.status == GridStatus.REALIZABLE:
        status = "solved" if res.verified is True else "invalid"
    elif res.status == GridStatus.UNREALIZABLE:
        status = "unrealizable"
    else:
        status = "invalid" if "verif" in res.message.lower() and "fail" in res.message.lower() else "unknown"
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


def _reach_planner(problem: Any, solver: str, budget: Budget, options: dict[str, Any]) -> Any:
    """R2's planners through :func:`plansynth.reach.solve`; while that entry point does not
    exist yet, ``lazy-smt`` is run through :func:`plansynth.reach.lazy.plan_lazy` (the
    trajectory is validated below either way)."""
    try:
        from plansynth.reach.solve import solve
    except ImportError:
        solve = None  # type: ignore[assignment]
    if solve is not None:
        return solve(problem, planner=solver, budget=budget, **options)
    if solver == "lazy-smt":
        from plansynth.reach.lazy import plan_lazy

        return plan_lazy(problem, budget, **options)
    from plansynth.errors import SolverUnavailable

    raise SolverUnavailable(solver, "plansynth.reach.solve is not available in this checkout")


def _reach(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    from plansynth.reach.validate import validate

    problem = inst.build()
    solver = task["solver"]
    budget = Budget(seconds=float(task["timeout"]))
    options = dict(task.get("options") or {})
    seed = int(task.get("seed", 0)) + int(task.get("repeat", 0))
    from plansynth.reach.robot import configuration_space

    if solver in ("rrt", "est", "kpiece"):
        from plansynth.reach.rrt import plan_rrt

        # a sized robot plans in its configuration space (as solve() does for the others)
        res = plan_rrt(configuration_space(problem), budget, seed=seed, planner=solver, **options)
    elif solver == "milp-bigm":
        from plansynth.reach.milp_bigm import plan_milp_bigm

        res = plan_milp_bigm(configuration_space(problem), budget, **options)
    else:
        res = _reach_planner(problem, solver, budget, options)
    status_value = getattr(res.status, "value", str(res.status))
    valid = None
    segment_safe = None
    if res.trajectory is not None and getattr(res, "guarantee", None) == "curve":
        # A continuous-time curve (gcs): the validator's curve mode, on the samples at dt
        # and on the dense curve (segment-safe, derivative check); not the exact dynamics.
        import numpy as np

        report = validate(problem, res.trajectory, dynamics="curve")
        dense = None if res.curve is None else validate(
            problem, res.curve, require_segment_safe=True, dynamics="curve",
            times=None if res.curve_times is None else np.array(res.curve_times))
        valid = int(bool(report.ok and dense is not None and dense.ok))
        segment_safe = int(bool(dense is not None and dense.segment_safe))
    elif res.trajectory is not None:
        # The same independent validator for every planner, whatever the planner says.
        if getattr(problem, "mission", None) is not None:  # and the mission checker (issue 14)
            from plansynth.reach.mission.check import check_mission
            from plansynth.reach.mission.labels import planning_problem

            report = validate(planning_problem(problem), res.trajectory)
            holds = check_mission(problem, res.trajectory, (res.mission or {}).get("loop_start")).ok
            valid = int(bool(report.ok) and holds)
        else:
            report = validate(problem, res.trajectory)
            valid = int(bool(report.ok))
        segment_safe = int(bool(report.segment_safe))
    if status_value == "found":
        status = "solved" if valid == 1 else "invalid"
    elif status_value == "infeasible":
        status = "infeasible"
    else:
        status = "invalid" if valid == 0 else "unknown"
    c = dict(res.counters or {})
    timings = {k: float(v) for k, v in (res.timings or {}).items() if isinstance(v, (int, float))}
    oracle = None
    if status == "solved" and res.regions is not None and res.horizon is not None \
            and len(res.regions) == res.horizon + 1 and getattr(res, "guarantee", None) in ("segments", "samples"):
        from plansynth.reach.oracle import oracle_lp

        lim = oracle_lp(problem, res.regions, segment_safe=res.guarantee == "segments")
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

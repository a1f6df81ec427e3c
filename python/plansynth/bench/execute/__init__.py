"""One benchmark run, executed inside the child process the runner starts.

:func:`execute` maps a task (a plain dict: instance, solver, repeat, timeout, seed,
options; :mod:`plansynth.bench.tasks`) to the run's attributes (a plain dict, a row of
the ``runs`` table). Every plan or controller a solver returns is checked by the same
independent checker for every solver -- :func:`plansynth.grid.verify.verify` (inside
:func:`plansynth.grid.solve.solve`) for grid controllers,
:func:`plansynth.reach.validate.validate` for trajectories -- and counted as solved only
if it passes. The runs themselves:

- :mod:`~plansynth.bench.execute.grid` -- a grid backend (``native``, ``cvc5``,
  ``external``), in this process or, for the families timed through the command line,
  as ``plansynth grid solve FILE --timeout T`` in a fresh one;
- :mod:`~plansynth.bench.execute.omega` -- the bench-only peer ``omega`` on the grid
  games it can be posed (safety and recurrence, the SYNTCOMP families);
- :mod:`~plansynth.bench.execute.reach` -- a reach planner through
  :func:`plansynth.reach.solve`, with the version the result reports;
- :mod:`~plansynth.bench.execute.debug` -- ``debug-*`` runs that exercise the runner.

A solver that cannot run here is recorded ``unavailable`` with what to install.

>>> execute({"solver": "debug-ok"})["status"]
'solved'
"""

from __future__ import annotations

import resource
import time
from collections.abc import Mapping
from typing import Any

from plansynth.bench.execute.debug import DEBUG_SOLVERS, run_debug
from plansynth.bench.execute.grid import run_grid
from plansynth.bench.execute.omega import GRID_PEERS, run_omega
from plansynth.bench.execute.reach import run_reach
from plansynth.bench.families.instance import instance_from_task

__all__ = ["execute", "DEBUG_SOLVERS", "GRID_PEERS"]


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
            attrs = run_debug(solver)
        else:
            inst = instance_from_task(task)
            if inst.kind == "grid" and solver in GRID_PEERS:
                attrs = run_omega(inst, task)
            else:
                attrs = run_grid(inst, task) if inst.kind == "grid" else run_reach(inst, task)
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

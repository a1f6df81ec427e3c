"""One task in its own child process: the unit of work a pool runs (locally or on a
Dask worker).

:func:`run_task` runs :func:`plansynth.bench.execute.execute` in a fresh child
(:func:`plansynth.isolate.run_isolated`) with the task's wall-clock limit
(:func:`plansynth.bench.tasks.wall_limit`) and memory limit, and always returns the
run's attributes: a hung solver is a ``timeout``, one that dies a ``crash``, one that
runs out of memory a ``memout``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from plansynth.bench.tasks import wall_limit

__all__ = ["run_task"]


def run_task(task: Mapping[str, Any]) -> dict[str, Any]:
    """Run one task in an isolated child process; always returns the run's attributes.

    Safe to call inside a daemonic process (a Dask worker): the child is started anyway.
    """
    import multiprocessing

    from plansynth.bench.execute import execute
    from plansynth.isolate import Crash, Finished, run_isolated

    limit = wall_limit(task)
    proc = multiprocessing.current_process()
    was_daemon = proc._config.get("daemon")  # type: ignore[attr-defined]
    if was_daemon:
        # Dask's worker processes are daemonic, and multiprocessing refuses to start
        # children from daemonic processes. Our child is always killed by run_isolated
        # (timeout, or its own end), so the reason for that rule does not apply here.
        proc._config["daemon"] = False  # type: ignore[attr-defined]
    try:
        out = run_isolated(execute, dict(task), timeout=limit, memory_mb=task.get("memory_mb"))
    finally:
        if was_daemon:
            proc._config["daemon"] = was_daemon  # type: ignore[attr-defined]
    if isinstance(out, Finished):
        attrs = dict(out.value)
        attrs["wall"] = out.seconds
        attrs.setdefault("time", out.seconds)
        return attrs
    if isinstance(out, Crash):
        status = "memout" if out.memory_out else "crash"
        return {
            "status": status,
            "solved": 0,
            "time": out.seconds,
            "wall": out.seconds,
            "message": (out.describe() + "\n" + (out.error or ""))[:4000],
            "attributes": {"exitcode": out.exitcode},
        }
    return {
        "status": "timeout",
        "solved": 0,
        "time": out.seconds,
        "wall": out.seconds,
        "message": f"killed after {out.seconds:.1f} s (limit {limit:.1f} s)",
    }

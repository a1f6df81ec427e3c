"""The sweep runner: every run in its own child process, results written as they finish.

A sweep is a list of tasks (instance x solver x repeat). :func:`run_sweep`

- skips tasks whose resume key (experiment, solver, repeat) is already in the database
  with the same budget (time and memory limit), so an interrupted sweep resumes where
  it stopped, and a run recorded under another budget is run again (its new row
  replaces the old one);
- runs each task in a fresh child process (:func:`plansynth.isolate.run_isolated`)
  with a wall-clock limit (the solver's budget plus a grace period) and a memory limit,
  so a hung solver is recorded as ``timeout``, one that dies as ``crash``, one that runs
  out of memory as ``memout``, and nothing else is lost;
- writes each run to the database the moment it finishes; on Ctrl-C (KeyboardInterrupt)
  it stops at once: queued runs are dropped, running children are killed
  (:func:`plansynth.isolate.cancel_all`), every finished run is kept, and the
  interrupt is raised again;
- runs tasks on a local pool (``jobs`` children at once, default 1 so that timings are
  not disturbed) or on an existing Dask distributed cluster (``cluster="tcp://..."``),
  where each worker again isolates every run in a child process.

>>> from plansynth.bench.families import grid_family
>>> tasks = make_tasks(grid_family("depth", [1]), ["native", "cvc5"], repeat=2, timeout=5)
>>> [(t["instance"]["name"], t["solver"], t["repeat"]) for t in tasks][:3]
[('depth-1', 'native', 0), ('depth-1', 'native', 1), ('depth-1', 'cvc5', 0)]
"""

from __future__ import annotations

import json
import os
import platform
import socket
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from plansynth.bench.db import UNRECORDED, ResultsDB
from plansynth.bench.families import Instance

__all__ = ["make_tasks", "run_sweep", "run_task", "machine_info", "DEFAULT_MEMORY_MB"]

DEFAULT_MEMORY_MB = 8192


def make_tasks(
    instances: Iterable[Instance],
    solvers: Sequence[str],
    *,
    repeat: int = 1,
    timeout: float = 60.0,
    memory_mb: int | None = DEFAULT_MEMORY_MB,
    seed: int = 0,
    options: Mapping[str, Mapping[str, Any]] | None = None,
) -> list[dict[str, Any]]:
    """Tasks (plain, picklable dicts) for every instance x solver x repeat."""
    out = []
    for inst in instances:
        for solver in solvers:
            for r in range(repeat):
                out.append({
                    "instance": inst.to_dict(),
                    "experiment": inst.key,
                    "solver": solver,
                    "repeat": r,
                    "timeout": float(timeout),
                    "memory_mb": memory_mb,
                    "seed": seed,
                    "options": dict((options or {}).get(solver, {})),
                })
    return out


def grace(timeout: float) -> float:
    """Extra wall-clock time a child gets beyond its solver budget before it is killed."""
    return max(5.0, 0.2 * timeout)


def wall_limit(task: Mapping[str, Any]) -> float:
    """The child's wall-clock limit for ``task``: its budget plus the task's grace (default
    :func:`grace`)."""
    extra = task.get("grace")
    return float(task["timeout"]) + (grace(float(task["timeout"])) if extra is None else float(extra))


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
        return {"status": status, "solved": 0, "time": out.seconds, "wall": out.seconds,
                "message": (out.describe() + "\n" + (out.error or ""))[:4000],
                "attributes": {"exitcode": out.exitcode}}
    return {"status": "timeout", "solved": 0, "time": out.seconds, "wall": out.seconds,
            "message": f"killed after {out.seconds:.1f} s (limit {limit:.1f} s)"}


def scrub_paths(text: str) -> str:
    """Shorten absolute file paths in tracebacks to what follows ``site-packages/`` or
    the ``plansynth`` package, so a shared results database names no local directories.

    >>> scrub_paths('File "/home/me/src/python/plansynth/grid/solve.py", line 3')
    'File ".../plansynth/grid/solve.py", line 3'
    """
    import re

    text = re.sub(r'(?:/[^\s"\']+)?/(site-packages|plansynth)/', r".../\1/", text)
    return re.sub(r'(?<![\w.])/(?:tmp|home|root|work|Users)/[^\s"\']*', "<path>", text)


def machine_info() -> dict[str, Any]:
    """Host, CPU, memory and software versions, recorded with every experiment."""
    from importlib.metadata import PackageNotFoundError, version

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gb = None
    try:
        mem_gb = round(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30, 1)
    except (ValueError, OSError, AttributeError):
        pass
    versions = {}
    for pkg in ("plansynth", "cvc5", "python-sat", "highspy", "ompl", "shapely", "numpy"):
        try:
            versions[pkg] = version(pkg)
        except PackageNotFoundError:
            versions[pkg] = None
    return {
        "hostname": socket.gethostname(),
        "cpuinfo": f"{cpu}, {os.cpu_count()} cores, {mem_gb} GB",
        "version": f"plansynth {versions['plansynth']}",
        "python": platform.python_version(),
        "platform": platform.platform(),
        "versions": versions,
    }


def run_sweep(
    db_path: str | Path,
    tasks: Sequence[Mapping[str, Any]],
    *,
    jobs: int = 1,
    cluster: str | Any | None = None,
    progress: bool = True,
    on_result: Callable[[Mapping[str, Any], Mapping[str, Any]], None] | None = None,
    retry: Sequence[str] = (),
) -> dict[str, int]:
    """Run the tasks not yet in the database; returns counts (done, skipped, per status).

    ``cluster`` is a Dask scheduler address (or a ``distributed.Client``); without it, a
    local pool of ``jobs`` concurrent children runs the tasks. Recorded runs whose status
    is in ``retry`` (e.g. ``("crash", "timeout")``) are run again.
    """
    db = ResultsDB(db_path)
    try:
        machine = machine_info()
        info = db.info()
        planned = {tuple(k) for k in json.loads(info.get("planned", "[]"))}
        planned |= {(t["experiment"], t["solver"], int(t["repeat"])) for t in tasks}
        db.set_info({"machine": machine, "last_sweep": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
                     "planned": sorted(planned)})
        done = db.recorded_budgets(retry)
        todo = [t for t in tasks if not _same_budget(done.get((t["experiment"], t["solver"], int(t["repeat"]))), t)]
        counts: dict[str, int] = {"skipped": len(tasks) - len(todo), "done": 0}
        ids: dict[tuple[str, str], tuple[int, int]] = {}
        runcount: dict[str, int] = {}
        for t in tasks:
            runcount[t["experiment"]] = max(runcount.get(t["experiment"], 0), int(t["repeat"]) + 1)
        for t in tasks:
            key = (t["experiment"], t["solver"])
            if key in ids:
                continue
            inst = t["instance"]
            eid = db.experiment(
                t["experiment"], kind=inst["kind"], family=inst["family"], instance=inst["name"], setup=inst,
                timelimit=t["timeout"], memorylimit=t.get("memory_mb"), runcount=runcount[t["experiment"]],
                machine=machine, seed=t.get("seed"),
            )
            pid = db.planner(t["solver"], {"options": t.get("options") or {}})
            ids[key] = (eid, pid)

        def record(task: Mapping[str, Any], attrs: Mapping[str, Any]) -> None:
            eid, pid = ids[(task["experiment"], task["solver"])]
            attrs = dict(attrs)
            if attrs.get("message"):
                attrs["message"] = scrub_paths(str(attrs["message"]))
            attrs["attributes"] = {**dict(attrs.get("attributes") or {}), "timelimit": float(task["timeout"]),
                                   "memorylimit": task.get("memory_mb"), "options": dict(task.get("options") or {})}
            db.add_run(eid, pid, int(task["repeat"]), attrs)
            counts["done"] += 1
            counts[attrs.get("status", "?")] = counts.get(attrs.get("status", "?"), 0) + 1
            if on_result is not None:
                on_result(task, attrs)

        bar = _progress(len(todo)) if progress and todo else None
        try:
            if cluster is not None:
                _run_dask(cluster, todo, record, bar)
            else:
                _run_local(todo, jobs, record, bar)
        finally:
            if bar is not None:
                bar.stop()
        return counts
    finally:
        db.close()


def _same_budget(recorded: tuple[Any, Any, Any] | None, task: Mapping[str, Any]) -> bool:
    """Was a recorded run (its time and memory limit and solver options,
    :meth:`ResultsDB.recorded_budgets`; None: no such run) made under ``task``'s budget
    and with its options? (A run under other options answers another question.)"""
    if recorded is None:
        return False
    timelimit, memorylimit, options = recorded
    if options != UNRECORDED and dict(options or {}) != dict(task.get("options") or {}):
        return False
    if timelimit is not None and float(timelimit) != float(task["timeout"]):
        return False
    if memorylimit != UNRECORDED:
        mem = task.get("memory_mb")
        if (memorylimit is None) != (mem is None) or (mem is not None and float(memorylimit) != float(mem)):
            return False
    return True


def _run_local(todo: Sequence[Mapping[str, Any]], jobs: int, record: Callable[..., None], bar: Any) -> None:
    """Run ``todo`` on ``jobs`` threads, each waiting for its isolated child; record
    each run as it finishes. On KeyboardInterrupt: drop the queued runs, kill the
    running children, record the runs that finished meanwhile, raise again."""
    from plansynth.isolate import cancel_all

    pool = ThreadPoolExecutor(max_workers=max(1, jobs))
    futures = {pool.submit(run_task, t): t for t in todo}
    recorded: set[Any] = set()
    try:
        for fut in as_completed(futures):
            task = futures[fut]
            recorded.add(fut)
            result = _safe_result(fut, task)
            if result is not None:
                record(task, result)
            if bar is not None:
                bar.advance(task)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        cancel_all()
        for fut, task in futures.items():  # runs that finished before the children were killed
            if fut in recorded or fut.cancelled():
                continue
            try:
                fut.result(timeout=5)
            except BaseException:  # noqa: BLE001 - cancelled, killed or failed: not a finished run
                continue
            result = _safe_result(fut, task)
            if result is not None:
                record(task, result)
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _safe_result(fut: Any, task: Mapping[str, Any]) -> dict[str, Any] | None:
    """The run's attributes; None when its child was cancelled (not a finished run)."""
    from plansynth.isolate import Cancelled

    try:
        return dict(fut.result())
    except Cancelled:
        return None
    except Exception as exc:  # the runner itself failed for this task: record, go on
        return {"status": "crash", "solved": 0, "message": f"runner error: {type(exc).__name__}: {exc}"[:4000]}


def _run_dask(cluster: str | Any, todo: Sequence[Mapping[str, Any]], record: Callable[..., None], bar: Any) -> None:
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError as exc:  # pragma: no cover - dask is a test/bench extra
        from plansynth.errors import SolverUnavailable

        raise SolverUnavailable("dask", 'install dask.distributed: pip install "dask[distributed]"') from exc
    client = cluster if isinstance(cluster, Client) else Client(cluster)
    try:
        futures = {}
        for t in todo:
            f = client.submit(run_task, dict(t), pure=False, key=f"plansynth-{t['experiment']}-{t['solver']}-{t['repeat']}-{time.time_ns()}")
            futures[f.key] = (f, t)
        seen: set[str] = set()
        try:
            for fut in dask_completed([f for f, _ in futures.values()]):
                task = futures[fut.key][1]
                seen.add(fut.key)
                result = _safe_result(fut, task)
                if result is not None:
                    record(task, result)
                if bar is not None:
                    bar.advance(task)
        except BaseException:  # Ctrl-C: keep what finished, drop what is queued or running
            pending = [f for f, _ in futures.values() if not f.done()]
            client.cancel(pending)
            for key, (f, task) in futures.items():
                if key not in seen and f.status == "finished":
                    try:
                        result = _safe_result(f, task)
                    except BaseException:  # noqa: BLE001 - not a finished run
                        continue
                    if result is not None:
                        record(task, result)
            raise
    finally:
        if not isinstance(cluster, Client):
            client.close()


class _Bar:
    def __init__(self, total: int) -> None:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        self.progress = Progress(TextColumn("[bold]bench"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                                 TextColumn("{task.description}"), transient=False)
        self.task = self.progress.add_task("", total=total)
        self.progress.start()

    def advance(self, task: Mapping[str, Any]) -> None:
        self.progress.update(self.task, advance=1, description=f"{task['experiment']} {task['solver']} #{task['repeat']}")

    def stop(self) -> None:
        self.progress.stop()


def _progress(total: int) -> _Bar:
    return _Bar(total)


def tasks_to_json(tasks: Sequence[Mapping[str, Any]]) -> str:
    return json.dumps(list(tasks), indent=1)

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
  where each worker again isolates every run in a child process
  (:mod:`plansynth.bench.pools`); a scheduler that does not answer within a few
  seconds is :class:`~plansynth.bench.errors.ClusterUnreachable`, before anything is
  written.

The tasks come from :func:`plansynth.bench.tasks.make_tasks`; the run inside each child
is :func:`plansynth.bench.execute.execute`.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from plansynth.bench.db import UNRECORDED, ResultsDB
from plansynth.bench.machine import machine_info, scrub_paths
from plansynth.bench.pools import connect, run_local, run_on_cluster

__all__ = ["run_sweep"]


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
    is in ``retry`` (e.g. ``("crash", "timeout")``) are run again. A scheduler that does
    not answer is :class:`~plansynth.bench.errors.ClusterUnreachable`, raised before the
    database is opened.
    """
    client, owned = connect(cluster) if cluster is not None else (None, False)
    try:
        return _sweep(db_path, tasks, jobs=jobs, client=client, progress=progress, on_result=on_result, retry=retry)
    finally:
        if owned:
            client.close()


def _sweep(
    db_path: str | Path,
    tasks: Sequence[Mapping[str, Any]],
    *,
    jobs: int,
    client: Any,
    progress: bool,
    on_result: Callable[[Mapping[str, Any], Mapping[str, Any]], None] | None,
    retry: Sequence[str],
) -> dict[str, int]:
    db = ResultsDB(db_path)
    try:
        machine = machine_info()
        info = db.info()
        planned = {tuple(k) for k in json.loads(info.get("planned", "[]"))}
        planned |= {(t["experiment"], t["solver"], int(t["repeat"])) for t in tasks}
        db.set_info(
            {
                "machine": machine,
                "last_sweep": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
                "planned": sorted(planned),
            }
        )
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
                t["experiment"],
                kind=inst["kind"],
                family=inst["family"],
                instance=inst["name"],
                setup=inst,
                timelimit=t["timeout"],
                memorylimit=t.get("memory_mb"),
                runcount=runcount[t["experiment"]],
                machine=machine,
                seed=t.get("seed"),
            )
            pid = db.planner(t["solver"], {"options": t.get("options") or {}})
            ids[key] = (eid, pid)

        def record(task: Mapping[str, Any], attrs: Mapping[str, Any]) -> None:
            eid, pid = ids[(task["experiment"], task["solver"])]
            attrs = dict(attrs)
            if attrs.get("message"):
                attrs["message"] = scrub_paths(str(attrs["message"]))
            attrs["attributes"] = {
                **dict(attrs.get("attributes") or {}),
                "timelimit": float(task["timeout"]),
                "memorylimit": task.get("memory_mb"),
                "options": dict(task.get("options") or {}),
            }
            db.add_run(eid, pid, int(task["repeat"]), attrs)
            counts["done"] += 1
            counts[attrs.get("status", "?")] = counts.get(attrs.get("status", "?"), 0) + 1
            if on_result is not None:
                on_result(task, attrs)

        bar = _progress(len(todo)) if progress and todo else None
        try:
            if client is not None:
                run_on_cluster(client, todo, record, bar)
            else:
                run_local(todo, jobs, record, bar)
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


class _Bar:
    def __init__(self, total: int) -> None:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

        self.progress = Progress(
            TextColumn("[bold]bench"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TextColumn("{task.description}"),
            transient=False,
        )
        self.task = self.progress.add_task("", total=total)
        self.progress.start()

    def advance(self, task: Mapping[str, Any]) -> None:
        self.progress.update(
            self.task, advance=1, description=f"{task['experiment']} {task['solver']} #{task['repeat']}"
        )

    def stop(self) -> None:
        self.progress.stop()


def _progress(total: int) -> _Bar:
    return _Bar(total)

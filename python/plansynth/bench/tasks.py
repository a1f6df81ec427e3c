"""A task: one run of a sweep (instance x solver x repeat) as a plain, picklable dict.

:func:`make_tasks` crosses instances, solvers and repeats; :func:`wall_limit` is the
wall-clock limit of a task's child process (its solver budget plus a grace period),
which the runner enforces and which a run may read to share out what is left of it.
Both the runner (:mod:`plansynth.bench.runner`) and the run inside the child
(:mod:`plansynth.bench.execute`) use this module; it uses neither.

>>> from plansynth.bench.families import grid_family
>>> tasks = make_tasks(grid_family("depth", [1]), ["native", "cvc5"], repeat=2, timeout=5)
>>> [(t["instance"]["name"], t["solver"], t["repeat"]) for t in tasks][:3]
[('depth-1', 'native', 0), ('depth-1', 'native', 1), ('depth-1', 'cvc5', 0)]
>>> wall_limit(tasks[0]), wall_limit({"timeout": 100}), wall_limit({"timeout": 5, "grace": 1})
(10.0, 120.0, 6.0)
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from plansynth.bench.families.instance import Instance

__all__ = ["make_tasks", "grace", "wall_limit", "tasks_to_json", "DEFAULT_MEMORY_MB"]

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
                out.append(
                    {
                        "instance": inst.to_dict(),
                        "experiment": inst.key,
                        "solver": solver,
                        "repeat": r,
                        "timeout": float(timeout),
                        "memory_mb": memory_mb,
                        "seed": seed,
                        "options": dict((options or {}).get(solver, {})),
                    }
                )
    return out


def grace(timeout: float) -> float:
    """Extra wall-clock time a child gets beyond its solver budget before it is killed."""
    return max(5.0, 0.2 * timeout)


def wall_limit(task: Mapping[str, Any]) -> float:
    """The child's wall-clock limit for ``task``: its budget plus the task's grace (default
    :func:`grace`)."""
    extra = task.get("grace")
    return float(task["timeout"]) + (grace(float(task["timeout"])) if extra is None else float(extra))


def tasks_to_json(tasks: Sequence[Mapping[str, Any]]) -> str:
    return json.dumps(list(tasks), indent=1)

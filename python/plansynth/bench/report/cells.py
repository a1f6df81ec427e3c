"""A report cell: the repeats of one (instance, solver) summarised, and how it reads.

:func:`summarise` groups a database's runs by (experiment, planner) into :class:`Cell`
values: median time of the solved repeats, the limit, the statuses, and the attributes
the tables show. :func:`fmt` writes a time as the tables do; :func:`instances_of` and
:func:`planners_of` list a family's instances and a half's planners in table order.

>>> fmt(0.0123), fmt(1234.5), fmt(None)
('0.0123', '1234', '-')
>>> c = Cell(runs=2, solved=0, median=None, worst=None, limit=60.0, statuses={"unknown": 2},
...          extra={"median_any": 60.0})
>>> c.text(), c.used_its_limit
('> 60 (2 unknown)', True)
"""

from __future__ import annotations

import statistics
from collections import defaultdict
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["Cell", "summarise", "fmt", "status_summary", "param_value", "instances_of", "planners_of"]


@dataclass(frozen=True)
class Cell:
    """Aggregate of the repeats of one (instance, solver)."""

    runs: int
    solved: int
    median: float | None  # median time of the solved repeats
    worst: float | None
    limit: float | None
    statuses: dict[str, int]
    depth: int | None = None
    steps: int | None = None
    horizon: int | None = None
    extra: dict[str, Any] | None = None

    @property
    def all_solved(self) -> bool:
        return self.runs > 0 and self.solved == self.runs

    def text(self) -> str:
        if self.solved == 0:
            if set(self.statuses) <= {"unrealizable", "infeasible"}:
                return f"{fmt(self.median_any)} ({next(iter(self.statuses))})"
            if self.out_of_time:
                lim = f"> {fmt(self.limit)}" if self.limit else "-"
                t = self.median_any
                if t is not None and self.limit and not self.used_its_limit:
                    return f"no answer ({status_summary(self.statuses)} after {fmt(t)} s of {fmt(self.limit)})"
                return f"{lim} ({status_summary(self.statuses)})"
            return status_summary(self.statuses)
        s = fmt(self.median)
        if (self.extra or {}).get("samples_only"):
            s += " (samples only: a segment crosses an obstacle)"
        if self.solved < self.runs:
            s += f" ({self.solved}/{self.runs} solved; {status_summary(self.statuses)})"
        return s

    @property
    def out_of_time(self) -> bool:
        """No answer because time ran out (not a crash or an invalid plan)."""
        return self.solved == 0 and set(self.statuses) <= {"unknown", "timeout"}

    @property
    def used_its_limit(self) -> bool:
        """No answer within (nearly) the whole limit: the limit is then a lower bound of
        the time it would need. A run that gave up well before it (an iteration limit of
        the solver, say) bounds nothing."""
        t = self.median_any
        return self.out_of_time and bool(self.limit) and (t is None or t >= 0.9 * self.limit)

    @property
    def median_any(self) -> float | None:
        return (self.extra or {}).get("median_any")

    def decided_time(self) -> float | None:
        """Median time when every repeat gave a definite answer (solved or proved)."""
        if self.runs and set(self.statuses) <= {"solved", "unrealizable", "infeasible"}:
            return self.median if self.solved else self.median_any
        return None


def fmt(x: float | None) -> str:
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    if x >= 1000:
        return f"{x:.0f}"
    if x >= 0.01:
        return f"{x:.3g}"
    return f"{x:.1e}"


def status_summary(statuses: Mapping[str, int]) -> str:
    return ", ".join(f"{n} {s}" for s, n in sorted(statuses.items()))


def summarise(runs: Sequence[Mapping[str, Any]]) -> dict[tuple[str, str], Cell]:
    """(experiment, planner) -> :class:`Cell`."""
    groups: dict[tuple[str, str], list[Mapping[str, Any]]] = defaultdict(list)
    for r in runs:
        groups[(r["experiment"], r["planner"])].append(r)
    out = {}
    for key, rs in groups.items():
        solved = [r for r in rs if r["solved"]]
        times = [float(r["time"]) for r in solved if r["time"] is not None]
        all_times = [float(r["time"]) for r in rs if r["time"] is not None]
        statuses: dict[str, int] = defaultdict(int)
        for r in rs:
            statuses[r["status"]] += 1
        first = solved[0] if solved else rs[0]
        out[key] = Cell(
            runs=len(rs),
            solved=len(solved),
            median=statistics.median(times) if times else None,
            worst=max(times) if times else None,
            limit=max(((r.get("attributes") or {}).get("timelimit") or r["timelimit"] or 0) for r in rs) or None,
            statuses=dict(statuses),
            depth=first.get("depth"),
            steps=first.get("steps"),
            horizon=first.get("horizon"),
            extra={
                "median_any": statistics.median(all_times) if all_times else None,
                "family": rs[0]["family"],
                "instance": rs[0]["instance"],
                "setup": rs[0]["setup"],
                "lp_calls": first.get("lp_calls"),
                "sat_calls": first.get("sat_calls"),
                "timings": (first.get("attributes") or {}).get("timings", {}),
                "expected": (rs[0]["setup"] or {}).get("expected"),
                "samples_only": any(r.get("segment_safe") == 0 for r in solved),
                "program": (first.get("attributes") or {}).get("program"),
                # the limit beside the time: one cold LP over the final region sequence (median)
                "oracle_lp": _median_attr(solved, "oracle_lp", "seconds"),
                "duration": _median_attr(solved, "duration"),
                "guarantee": (first.get("attributes") or {}).get("guarantee"),
                # the planner's own time: the run's time less the validator's (median)
                "planner_median": _median_planner(solved),
                # runs through the CLI (bench.execute._grid_cli): wall clock of the whole process
                "cli_wall": _median_attr(rs, "cli_wall"),
                "budget_kept": [
                    bool((r.get("attributes") or {}).get("budget_kept"))
                    for r in rs
                    if "budget_kept" in (r.get("attributes") or {})
                ],
                "depth_minimal": (first.get("attributes") or {}).get("depth_minimal"),
                # the lazy planner's minimality claim: proved? for what? how many probes?
                "minimal": {
                    k: ((first.get("attributes") or {}).get("counters") or {}).get(k)
                    for k in ("minimal", "minimal_relative_to", "minimal_probes")
                },
                "regions": first.get("regions"),
                "counters": (first.get("attributes") or {}).get("counters") or {},
                # the robust family (bench.execute.robust): sampled runs, the largest box with a plan
                "robust": (first.get("attributes") or {}).get("robust"),
            },
        )
    return out


def _median_attr(runs: Sequence[Mapping[str, Any]], key: str, sub: str | None = None) -> float | None:
    """Median of ``attributes[key]`` (or ``attributes[key][sub]``) over ``runs``, when recorded."""
    vals = []
    for r in runs:
        v = (r.get("attributes") or {}).get(key)
        if sub is not None:
            v = v.get(sub) if isinstance(v, Mapping) else None
        if isinstance(v, (int, float)):
            vals.append(float(v))
    return statistics.median(vals) if vals else None


def _median_planner(runs: Sequence[Mapping[str, Any]]) -> float | None:
    vals = []
    for r in runs:
        v = ((r.get("attributes") or {}).get("timings") or {}).get("validate")
        if r.get("time") is not None and isinstance(v, (int, float)):
            vals.append(float(r["time"]) - float(v))
    return statistics.median(vals) if vals else None


def param_value(cell_or_setup: Mapping[str, Any]) -> float:
    params = cell_or_setup.get("params") or {}
    for k in ("d", "L", "N", "S", "cars", "height", "n", "seed", "m", "map"):
        if k in params:
            return float(params[k])
    return 0.0


def instances_of(cells: Mapping[tuple[str, str], Cell], family: str) -> list[tuple[str, dict[str, Any]]]:
    seen: dict[str, dict[str, Any]] = {}
    for (exp, _), c in cells.items():
        if c.extra and c.extra["family"] == family:
            seen.setdefault(exp, c.extra["setup"])
    return sorted(
        seen.items(),
        key=lambda kv: (param_value(kv[1]), kv[1].get("params", {}).get("k", 0), kv[1].get("params", {}).get("c", 0)),
    )


def planners_of(cells: Mapping[tuple[str, str], Cell], kind_prefix: str, order: Sequence[str]) -> list[str]:
    ps = {p for (exp, p) in cells if exp.startswith(kind_prefix)}
    return [p for p in order if p in ps] + sorted(ps - set(order))

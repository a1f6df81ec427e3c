"""The answer of a reach-avoid planner and the record of how it was found.

A :class:`ReachResult` carries the status (``found`` / ``infeasible`` / ``unknown``,
spec "Result file"), the trajectory and region sequence when one was found, and the
record of the run as a grid result keeps it: ``solver`` (the planner's registered
name), ``solver_version`` (its solvers' versions), ``options``, ``seconds``,
``counters``, with per-phase timings and the independent validator's report
(STYLE.md, points 1 and 3). :func:`plansynth.reach.solve` records the name, the version
and the options value of the planner that ran.

>>> ReachStatus.FOUND.value
'found'
>>> bool(ReachStatus.UNKNOWN)
Traceback (most recent call last):
...
TypeError: a ReachStatus has no truth value; compare it with ReachStatus.FOUND etc.
"""

from __future__ import annotations

import enum
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from plansynth.io import write_output
from plansynth.jsonable import jsonable as _jsonable
from plansynth.reach.trajectory import Trajectory, trajectory_to_lists
from plansynth.reach.validate import ValidationReport

__all__ = ["ReachStatus", "ReachResult", "solver_versions"]


class ReachStatus(str, enum.Enum):
    """``found``: a validated trajectory; ``infeasible``: proved, no trajectory of any
    horizon up to the result's ``horizon``; ``unknown``: a budget ran out (or a found
    trajectory failed validation). ``unknown`` is never ``false``: no truthiness."""

    FOUND = "found"
    INFEASIBLE = "infeasible"
    UNKNOWN = "unknown"

    def __bool__(self) -> bool:
        raise TypeError("a ReachStatus has no truth value; compare it with ReachStatus.FOUND etc.")

    def __str__(self) -> str:
        return self.value


def solver_versions() -> dict[str, str]:
    """Versions of plansynth and of the solvers the reach planners call."""
    from plansynth.registry import distribution_version

    dists = ("plansynth", "highspy", "python-sat", "numpy", "shapely", "drake")
    return {dist: distribution_version(dist) or "not installed" for dist in dists}


@dataclass(frozen=True, eq=False)
class ReachResult:
    """One planner run on one problem.

    ``horizon``: the number of steps N of the trajectory when ``found``; for
    ``infeasible``, the largest horizon up to which every horizon was refuted; for
    ``unknown``, the horizon being searched when the budget ran out (or None).
    ``regions``: the region sequence r_0..r_N (indices into the abstraction) for the
    region-based planners. ``segment_safe``: the validator's finding that every segment
    between consecutive samples avoids the obstacles (None without a trajectory);
    ``guarantee``: what the planner enforced by construction, ``"segments"`` or
    ``"samples"`` (the paper's guarantee) or ``"curve"`` (a continuous-time curve, not a
    trajectory of the exact discrete dynamics: ``gcs``, see
    :data:`plansynth.reach.planners.gcs.GUARANTEE`; then ``curve`` holds its dense sampling at
    ``curve_times`` and ``curve_validation`` the validator's report on it). ``validated``: the validator accepted the
    trajectory (None when there is none); ``validation``: its report.
    """

    status: ReachStatus
    solver: str
    seconds: float
    trajectory: Trajectory | None = None
    regions: tuple[int, ...] | None = None
    segment_safe: bool | None = None
    horizon: int | None = None
    counters: dict[str, Any] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)
    validated: bool | None = None
    validation: ValidationReport | None = None
    message: str = ""
    guarantee: str | None = None
    # planners that return a continuous-time curve (``guarantee="curve"``, e.g. gcs): its
    # dense sampling, the sample times (seconds) and the validator's report on it
    curve: Trajectory | None = None
    curve_times: tuple[float, ...] | None = None
    curve_validation: ValidationReport | None = None
    mission: dict[str, Any] | None = None  # LTL missions: semantics, loop_start, the checker's verdict
    # under a disturbance (plansynth.reach.robust): the feedback law and its gain, what a
    # found plan guarantees, the margins used and the robust check's report
    robust: dict[str, Any] | None = None
    solver_version: str = ""  # the planner's solvers and their versions (Planner.version())

    @property
    def planner(self) -> str:
        """The planner's name (``solver``; the spec's result key)."""
        return self.solver

    def to_json_dict(self) -> dict[str, Any]:
        """The result file of the spec (keys status, planner, seconds, states, inputs,
        regions, segment_safe) plus the record of the run (``solver`` and
        ``solver_version`` as in a grid result; ``versions``: every library's)."""
        states, inputs = (None, None) if self.trajectory is None else trajectory_to_lists(self.trajectory)
        return {
            "status": self.status.value,
            "planner": self.solver,
            "solver": self.solver,
            "solver_version": self.solver_version,
            "seconds": self.seconds,
            "states": states,
            "inputs": inputs,
            "regions": None if self.regions is None else [int(r) for r in self.regions],
            "segment_safe": self.segment_safe,
            "guarantee": self.guarantee,
            "horizon": self.horizon,
            "validated": self.validated,
            "validation": None if self.validation is None else self.validation.to_json_dict(),
            "counters": _jsonable(self.counters),
            "timings": _jsonable(self.timings),
            "options": _jsonable(self.options),
            "message": self.message,
            "curve_validation": None if self.curve_validation is None else self.curve_validation.to_json_dict(),
            "versions": solver_versions(),
            **({} if self.mission is None else {"mission": _jsonable(self.mission)}),
            **({} if self.robust is None else {"robust": _jsonable(self.robust)}),
        }

    def write(self, path: str | Path) -> Path:
        """Write :meth:`to_json_dict` to ``path`` (indented JSON; the name grid results use)."""
        return write_output(path, json.dumps(self.to_json_dict(), indent=1) + "\n")  # atomic; OutputUnwritable

    write_json = write  # the earlier name, kept for callers outside plansynth

"""The answer of a team planner and its result file.

A :class:`TeamResult` is a :class:`~plansynth.reach.result.ReachResult` for a team: the
status (``found`` / ``infeasible`` / ``unknown``, never truthy), one trajectory and
region sequence per robot, and the record of the run (planner, versions, options,
seconds, counters, timings, the team validator's report). Its file has the reach
result's keys, with ``robots`` (each robot's name, states, inputs and regions) in place
of ``states``, ``inputs`` and ``regions``; :func:`team_trajectories_from_dict` reads
them back.

>>> from plansynth.reach.result import ReachStatus
>>> r = TeamResult(ReachStatus.INFEASIBLE, "lazy-smt-team", 0.1, horizon=30)
>>> d = r.to_json_dict(); d["status"], d["robots"], d["horizon"]
('infeasible', None, 30)
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.io import Fields, load_document, write_output
from plansynth.jsonable import jsonable
from plansynth.reach.result import ReachStatus, solver_versions
from plansynth.reach.trajectory import Trajectory, trajectory_from_dict, trajectory_to_lists

__all__ = ["TeamResult", "team_trajectories_from_dict", "load_team_trajectories"]


@dataclass(frozen=True, eq=False)
class TeamResult:
    """One team planner run. ``trajectories[r]``/``regions[r]``: robot r's (problem
    order); ``horizon`` as in :class:`~plansynth.reach.result.ReachResult`; ``names``:
    the robots' names (for the file)."""

    status: ReachStatus
    solver: str
    seconds: float
    trajectories: tuple[Trajectory, ...] | None = None
    regions: tuple[tuple[int, ...], ...] | None = None
    horizon: int | None = None
    counters: dict[str, Any] = field(default_factory=dict)
    timings: dict[str, float] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)
    validated: bool | None = None
    validation: Any = None
    message: str = ""
    guarantee: str | None = None
    segment_safe: bool | None = None
    solver_version: str = ""
    names: tuple[str, ...] = ()
    # under disturbances (plansynth.reach.team.robust): the law, the guarantee, each
    # disturbed robot's gain and margins, and the worst-case team check's report
    robust: dict[str, Any] | None = None
    # (what code written for single-robot results reads)
    curve: None = None
    curve_validation: None = None
    mission: None = None

    @property
    def planner(self) -> str:
        return self.solver

    @property
    def trajectory(self) -> Trajectory | None:
        """The joint trajectory: every robot's states side by side (None without a plan)."""
        if self.trajectories is None:
            return None
        X = np.hstack([t.states for t in self.trajectories])
        U = np.hstack([t.inputs for t in self.trajectories])
        return Trajectory(states=X, inputs=U)

    def to_json_dict(self) -> dict[str, Any]:
        robots = None
        if self.trajectories is not None:
            robots = []
            for r, t in enumerate(self.trajectories):
                states, inputs = trajectory_to_lists(t)
                robots.append(
                    {
                        "name": self.names[r] if r < len(self.names) else f"r{r}",
                        "states": states,
                        "inputs": inputs,
                        "regions": None if self.regions is None else [int(i) for i in self.regions[r]],
                    }
                )
        return {
            "status": self.status.value,
            "planner": self.solver,
            "solver": self.solver,
            "solver_version": self.solver_version,
            "seconds": self.seconds,
            "robots": robots,
            "segment_safe": self.segment_safe,
            "guarantee": self.guarantee,
            "horizon": self.horizon,
            "validated": self.validated,
            "validation": None if self.validation is None else self.validation.to_json_dict(),
            "counters": jsonable(self.counters),
            "timings": jsonable(self.timings),
            "options": jsonable(self.options),
            "message": self.message,
            "versions": solver_versions(),
            **({} if self.robust is None else {"robust": jsonable(self.robust)}),
        }

    def write(self, path: str | Path) -> Path:
        return write_output(path, json.dumps(self.to_json_dict(), indent=1) + "\n")


def team_trajectories_from_dict(
    doc: Any, source: str | None, names: Sequence[str]
) -> tuple[list[Trajectory], list | None]:
    """The robots' trajectories (and region sequences, when every robot has one) of a
    team result document, in the order of ``names`` (the problem's robots)."""
    f = Fields(doc, source, "")
    robots = f.require("robots")
    if robots is None:
        raise InvalidProblem(source, "robots", f"no trajectories in this result (status {doc.get('status', '?')!r})")
    if not isinstance(robots, list):
        raise InvalidProblem(source, "robots", "expected a list of robots")
    by_name = {}
    for k, entry in enumerate(robots):
        g = Fields(entry, source, f"robots[{k}]")
        name = g.optional("name", names[k] if k < len(names) else f"r{k}")
        by_name[str(name)] = (k, entry)
    missing = [n for n in names if n not in by_name]
    if missing or len(robots) != len(names):
        raise InvalidProblem(
            source,
            "robots",
            f"the result has robots {sorted(by_name)}, the problem {list(names)}",
        )
    trajectories, regions = [], []
    for n in names:
        k, entry = by_name[n]
        trajectories.append(trajectory_from_dict(entry, f"{source}: robots[{k}]" if source else None))
        raw = entry.get("regions")
        regions.append(
            raw if isinstance(raw, list) and all(isinstance(i, int) and not isinstance(i, bool) for i in raw) else None
        )
    return trajectories, (regions if all(r is not None for r in regions) else None)


def load_team_trajectories(path: str | Path, names: Sequence[str]) -> tuple[list[Trajectory], list | None]:
    doc, name = load_document(path)
    return team_trajectories_from_dict(doc, name, names)

"""The benchmark instance: one problem of a family as a plain, frozen value.

An :class:`Instance` names its family and the parameters that rebuild it, so a task can
carry it to a child process as a dict (:meth:`Instance.to_dict`,
:func:`instance_from_task`) and the child rebuilds the problem there
(:meth:`Instance.build`) from the problems as code (:mod:`.grid_problems`,
:mod:`.reach_problems`). Which instances a family has is the catalogue's business
(:mod:`.grid`, :mod:`.reach`).

>>> i = Instance("grid", "depth", "depth-1", {"d": 1})
>>> i.key, instance_from_task({"instance": i.to_dict()}) == i
('grid/depth/depth-1', True)
>>> i.build().robot.goal
(5, 0)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from plansynth.bench.families.grid_problems import GRID_PROBLEMS
from plansynth.bench.families.reach_problems import REACH_PROBLEMS

__all__ = ["Instance", "instance_from_task"]


@dataclass(frozen=True)
class Instance:
    """One benchmark problem: ``kind`` is "grid" or "reach"; ``params`` rebuild it.

    ``expected`` is the answer known by construction (``realizable``/``unrealizable``
    for grid, ``found`` for reach problems with a known solution), else None.
    ``paper_seconds`` is the time the paper reports for it, when it does.
    """

    kind: str
    family: str
    name: str
    params: Mapping[str, Any] = field(default_factory=dict)
    expected: str | None = None
    paper_seconds: float | None = None

    @property
    def key(self) -> str:
        return f"{self.kind}/{self.family}/{self.name}"

    def to_dict(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "family": self.family,
            "name": self.name,
            "params": dict(self.params),
            "expected": self.expected,
            "paper_seconds": self.paper_seconds,
        }

    def document(self) -> dict[str, Any]:
        """The problem as a spec document (grid-problem.md / reach-problem.md)."""
        if self.kind == "grid":
            return GRID_PROBLEMS[self.family](**self.params)
        from plansynth.reach.fileformat import reach_problem_to_dict

        return reach_problem_to_dict(self.build())

    def build(self) -> Any:
        """The problem object (GridProblem or ReachProblem)."""
        if self.kind == "grid":
            from plansynth.grid.problem import grid_problem_from_dict

            return grid_problem_from_dict(self.document(), source=f"<bench {self.key}>", name=self.name)
        return REACH_PROBLEMS[self.family](**self.params)


def instance_from_task(task: Mapping[str, Any]) -> Instance:
    """Rebuild an :class:`Instance` from the dict a task carries (``Instance.to_dict``)."""
    d = task["instance"]
    return Instance(d["kind"], d["family"], d["name"], dict(d["params"]), d.get("expected"), d.get("paper_seconds"))

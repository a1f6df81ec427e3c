"""The status of a result document, checked for the half whose page shows it.

>>> result_status({"status": "found"}, "r.json", "reach")
'found'
>>> result_status({"status": "found"}, "r.json", "grid")
Traceback (most recent call last):
...
plansynth.errors.InvalidProblem: r.json: status: expected one of realizable/unrealizable/unknown, got 'found' (a reach result: give it with a reach problem)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from plansynth.errors import InvalidProblem
from plansynth.io import show

#: The statuses of each half's result files (specs: grid-problem.md and reach-problem.md).
STATUSES: dict[str, tuple[str, ...]] = {
    "grid": ("realizable", "unrealizable", "unknown"),
    "reach": ("found", "infeasible", "unknown"),
}


def result_status(doc: Any, source: str, half: str) -> str:
    """``doc["status"]`` when ``doc`` is a result object of ``half``; else an
    :class:`InvalidProblem` naming ``source``, which says when the result is the other half's."""
    if not isinstance(doc, Mapping):
        raise InvalidProblem(source, "<document>", f"expected a JSON object (a result of plansynth {half} solve -o)")
    status = doc.get("status")
    if status not in STATUSES[half]:
        other = next(h for h in STATUSES if h != half)
        hint = f" (a {other} result: give it with a {other} problem)" if status in STATUSES[other][:2] else ""
        raise InvalidProblem(source, "status", f"expected one of {'/'.join(STATUSES[half])}, got {show(status)}{hint}")
    return status

"""The small family of named errors plansynth raises (STYLE.md, point 2).

"Unrealizable" and "infeasible" are answers carried by results, never exceptions.
"""

from __future__ import annotations


class PlansynthError(Exception):
    """Base class of every error plansynth raises on purpose."""


class InvalidProblem(PlansynthError):
    """A problem (file or value) that breaks the format or the semantics of the spec.

    The message always names the file (or ``<value>`` for an in-memory problem), the
    field (a dotted path such as ``obstacles[1].moves``) and the reason.

    >>> e = InvalidProblem("p.yaml", "robot.start", "outside the 5x7 grid")
    >>> str(e)
    'p.yaml: robot.start: outside the 5x7 grid'
    >>> (e.file, e.field, e.reason)
    ('p.yaml', 'robot.start', 'outside the 5x7 grid')
    """

    def __init__(self, file: str | None, field: str, reason: str) -> None:
        self.file = file or "<value>"
        self.field = field
        self.reason = reason
        super().__init__(f"{self.file}: {field}: {reason}")


class SolverUnavailable(PlansynthError):
    """A backend cannot run here; the message says what to install or configure."""

    def __init__(self, solver: str, remedy: str) -> None:
        self.solver = solver
        self.remedy = remedy
        super().__init__(f"solver {solver!r} is unavailable: {remedy}")


class OutputUnwritable(PlansynthError):
    """An output file (result, .sl, picture, export, report) that cannot be written:
    the message names the path and the reason. The CLI checks every output path before
    it starts work and exits 2 with this message.

    >>> str(OutputUnwritable("/nonexistent/r.json", "folder does not exist"))
    'cannot write /nonexistent/r.json: folder does not exist'
    """

    def __init__(self, path: str, reason: str) -> None:
        self.path = str(path)
        self.reason = reason
        super().__init__(f"cannot write {self.path}: {reason}")

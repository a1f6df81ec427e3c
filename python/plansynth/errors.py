"""The small family of named errors plansynth raises (STYLE.md, point 2).

"Unrealizable" and "infeasible" are answers carried by results, never exceptions.
"""

from __future__ import annotations

from collections.abc import Iterable


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


class UnknownSolver(SolverUnavailable, ValueError):
    """A backend or planner name that its registry does not know; lists the names it knows.

    A :class:`SolverUnavailable` (nothing can run under that name) and a ``ValueError``
    (the name is a bad argument).

    >>> e = UnknownSolver("planner", "rrtx", ["lazy-smt", "rrt"])
    >>> str(e)
    "solver 'rrtx' is unavailable: unknown planner; choose one of: lazy-smt, rrt"
    >>> e.known
    ('lazy-smt', 'rrt')
    """

    def __init__(self, kind: str, name: str, known: Iterable[str]) -> None:
        self.kind = kind
        self.known = tuple(known)
        super().__init__(name, f"unknown {kind}; choose one of: {', '.join(self.known)}")


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


class InvalidOption(PlansynthError, ValueError):
    """An option the chosen solver or planner does not take, or a value it cannot use:
    never silently dropped. Names the solver, the option and the reason (with the
    options it does take).

    >>> str(InvalidOption("milp", "counterexample", "not an option of this planner (its options: max_horizon)"))
    "milp: option 'counterexample': not an option of this planner (its options: max_horizon)"
    """

    def __init__(self, solver: str, option: str, reason: str) -> None:
        self.solver = solver
        self.option = option
        self.reason = reason
        super().__init__(f"{solver}: option {option!r}: {reason}")

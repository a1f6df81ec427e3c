"""Answers of grid solvers: the status enum, per-length outcomes, the result file, and
the small Protocol every backend implements (STYLE.md, points 1, 3 and 5).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any, Protocol

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem
from plansynth.grid.problem import MAX_STEPS, GridProblem
from plansynth.grid.programs import ProgramSyntaxError, Term, depth, parse_program
from plansynth.io import parse_document, read_text, show, write_output
from plansynth.registry import Registry


class GridStatus(str, Enum):
    """Answer for one path length or a whole search (spec: Result file).

    There is deliberately no truthiness: ``unknown`` must never be read as ``false``.
    """

    REALIZABLE = "realizable"
    UNREALIZABLE = "unrealizable"
    UNKNOWN = "unknown"

    def __bool__(self) -> bool:
        raise TypeError("GridStatus has no truth value; compare with GridStatus.REALIZABLE etc.")


@dataclass(frozen=True)
class LengthOutcome:
    """What a backend says about one path length l.

    ``program`` is given iff ``status`` is realizable. ``counters`` are backend-specific
    (for example states explored or candidate programs tried); ``witness`` may carry
    evidence of unrealizability (an obstacle strategy) for backends that produce one.
    """

    status: GridStatus
    steps: int | None
    program: Term | None = None
    seconds: float = 0.0
    counters: dict[str, Any] = field(default_factory=dict)
    message: str = ""
    witness: Any = None
    artefact: str | None = None  # e.g. the path of the .sl file sent to a solver


class GridBackend(Protocol):
    """A solver for one path length. Backends are chosen by name (:func:`get_backend`)."""

    name: str

    def version(self) -> str: ...

    def solve_length(
        self, problem: GridProblem, steps: int | None, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        """Decide whether a controller of the grammar (bounded by ``depth_bound``, if
        given) achieves ``problem``'s objective (at path length ``steps`` for ``exact``
        and ``reach``; ``steps`` is None for ``safety`` and ``recurrence``), within
        ``budget``."""
        ...


#: The grid backends by name (:mod:`plansynth.registry`): a built-in's module, and so its
#: solver's library, is imported only when that backend is asked for. A new built-in
#: backend is one line here; plugins use :func:`register_backend`.
BACKENDS: Registry[Callable[..., GridBackend]] = Registry(
    "grid solver",
    {
        "native": "plansynth.grid.backends.native:NativeBackend",
        "cvc5": "plansynth.grid.backends.cvc5:Cvc5Backend",
        "external": "plansynth.grid.backends.external:ExternalBackend",
    },
)


def register_backend(name: str, factory: Callable[..., GridBackend]) -> None:
    """Make a backend available by name. ``factory(**options)`` builds it."""
    BACKENDS.register(name, factory, replace_existing=True)


def backend_names() -> list[str]:
    """Every name :func:`get_backend` accepts, built-in or registered (nothing is imported).

    >>> {"native", "cvc5", "external"} <= set(backend_names())
    True
    """
    return sorted(BACKENDS.names())


def backend_factory(name: str) -> Callable[..., GridBackend]:
    """The factory of the backend called ``name``, importing its module on first use.

    Raises :class:`~plansynth.errors.UnknownSolver` (a ``SolverUnavailable``) listing the
    known names when there is none.
    """
    return BACKENDS.get(name)


def get_backend(name: str, **options: Any) -> GridBackend:
    """The backend called ``name``; no silent fallback to another one."""
    return backend_factory(name)(**options)


@dataclass(frozen=True)
class GridResult:
    """The answer of a whole solve, written as the spec's result JSON.

    ``attempts`` records each path length tried, in order, with its status and time.
    ``verified`` is True only when the independent verifier accepted ``program``.
    """

    status: GridStatus
    steps: int | None
    program: Term | None
    solver: str
    seconds: float
    verified: bool | None
    depth_bound: int | None = None
    attempts: tuple[LengthOutcome, ...] = ()
    solver_version: str = ""
    options: dict[str, Any] = field(default_factory=dict)
    problem: str = ""
    message: str = ""
    #: for ``unrealizable``: the backend that decided every length exactly ("native",
    #: which certifies the claims of the SyGuS backends, see :mod:`plansynth.grid.solve`)
    certified_by: str | None = None
    #: the problem's objective (written to the file when it is not the paper's ``exact``)
    objective: str = "exact"

    @property
    def depth(self) -> int | None:
        return None if self.program is None else depth(self.program)

    @property
    def depth_minimal(self) -> str | None:
        """``proved`` or ``not proved`` when the backend says (the native engine), else None."""
        if self.program is None or not self.attempts:
            return None
        return self.attempts[-1].counters.get("depth_minimal")

    def to_json_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "status": self.status.value,
            "steps": self.steps,
            "program": None if self.program is None else str(self.program),
            "depth": self.depth,
            "depth_minimal": self.depth_minimal,
            "solver": self.solver,
            "seconds": round(self.seconds, 6),
            "verified": self.verified,
            "depth_bound": self.depth_bound,
            "solver_version": self.solver_version,
            "options": self.options,
            "problem": self.problem,
            "message": self.message,
            "certified_by": self.certified_by,
            **({"objective": self.objective} if self.objective != "exact" else {}),
            "attempts": [
                {
                    "steps": a.steps,
                    "status": a.status.value,
                    "seconds": round(a.seconds, 6),
                    "counters": a.counters,
                    **({"message": a.message} if a.message else {}),
                }
                for a in self.attempts
            ],
        }
        return d

    def write(self, path: str | Path) -> None:
        write_output(path, json.dumps(self.to_json_dict(), indent=2) + "\n")  # atomic; OutputUnwritable


@dataclass(frozen=True)
class StoredResult:
    """The fields of a result file that other commands need (verify, animate)."""

    status: GridStatus
    steps: int | None
    program: Term | None
    raw: dict[str, Any]


def load_result(path: str | Path) -> StoredResult:
    """Read a result JSON (spec: Result file), checking the fields we use."""
    text, name = read_text(path)  # the limits of every file plansynth reads (plansynth.io)
    raw = parse_document(text, name, json_syntax=True, kind="JSON")
    if not isinstance(raw, dict):
        raise InvalidProblem(name, "<document>", "expected a JSON object")
    try:
        status = GridStatus(raw.get("status"))
    except ValueError:
        raise InvalidProblem(
            name, "status", f"expected one of realizable/unrealizable/unknown, got {show(raw.get('status'))}"
        ) from None
    steps = raw.get("steps")
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= MAX_STEPS):
        raise InvalidProblem(name, "steps", f"expected an integer in 1..{MAX_STEPS}, got {show(steps)}")
    program = None
    if raw.get("program") is not None:
        if not isinstance(raw["program"], str):
            raise InvalidProblem(name, "program", f"expected the program as a string, got {show(raw['program'])}")
        try:
            program = parse_program(raw["program"])
        except ProgramSyntaxError as exc:
            raise InvalidProblem(name, "program", str(exc)) from exc
    return StoredResult(status, steps, program, raw)

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
from plansynth.errors import InvalidProblem, SolverUnavailable
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import ProgramSyntaxError, Term, depth, parse_program


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
    steps: int
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
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        """Decide whether a controller of the grammar (bounded by ``depth_bound``, if
        given) wins ``problem`` at exactly ``steps`` steps, within ``budget``."""
        ...


_BACKENDS: dict[str, Callable[..., GridBackend]] = {}


def register_backend(name: str, factory: Callable[..., GridBackend]) -> None:
    """Make a backend available by name. ``factory(**options)`` builds it."""
    _BACKENDS[name] = factory


def backend_names() -> list[str]:
    _load_builtin_backends()
    return sorted(_BACKENDS)


def get_backend(name: str, **options: Any) -> GridBackend:
    """The backend called ``name``; no silent fallback to another one."""
    _load_builtin_backends()
    if name not in _BACKENDS:
        raise SolverUnavailable(name, f"unknown grid solver; choose one of: {', '.join(sorted(_BACKENDS))}")
    return _BACKENDS[name](**options)


def _load_builtin_backends() -> None:
    # Importing a backend module registers it. Modules are imported lazily so that a
    # missing optional dependency only matters when that backend is asked for.
    import importlib

    for module in ("plansynth.grid.backends.cvc5", "plansynth.grid.backends.external", "plansynth.grid.backends.native"):
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name != module:  # the backend exists but a dependency is missing
                raise


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
        Path(path).write_text(json.dumps(self.to_json_dict(), indent=2) + "\n", encoding="utf-8")


@dataclass(frozen=True)
class StoredResult:
    """The fields of a result file that other commands need (verify, animate)."""

    status: GridStatus
    steps: int | None
    program: Term | None
    raw: dict[str, Any]


def load_result(path: str | Path) -> StoredResult:
    """Read a result JSON (spec: Result file), checking the fields we use."""
    name = str(path)
    try:
        raw = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InvalidProblem(name, "<file>", f"cannot read: {exc.strerror or exc}") from exc
    except json.JSONDecodeError as exc:
        raise InvalidProblem(name, "<file>", f"not valid JSON: {exc}") from exc
    if not isinstance(raw, dict):
        raise InvalidProblem(name, "<document>", "expected a JSON object")
    try:
        status = GridStatus(raw.get("status"))
    except ValueError:
        raise InvalidProblem(name, "status", f"expected one of realizable/unrealizable/unknown, got {raw.get('status')!r}") from None
    steps = raw.get("steps")
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or steps < 1):
        raise InvalidProblem(name, "steps", f"expected a positive integer, got {steps!r}")
    program = None
    if raw.get("program") is not None:
        try:
            program = parse_program(str(raw["program"]))
        except ProgramSyntaxError as exc:
            raise InvalidProblem(name, "program", str(exc)) from exc
    return StoredResult(status, steps, program, raw)

"""Backend ``native``: the exact engine of :mod:`plansynth.grid.native` (the default).

Options (keyword arguments, or ``KEY=VALUE`` strings in ``options`` as the CLI's
``plansynth grid solve -O minimize=true`` passes them): ``minimize`` (search program depths 1, 4, 5, ... over every winning strategy
and report the smallest, proved minimal when the condition enumeration is complete),
``condition_depth`` (deepest condition enumerated, default 4), ``max_tree_depth``,
``max_configs`` (an explicit cap on joint obstacle configurations; by default the game
is bounded by the budget: its time, and its ``memory_mb`` or 4096 MB),
``use_rust`` (None: the compiled core when built; False: the pure-Python references),
``effort`` (seconds spent making the first verified program smaller with tree SAT; default 0.3 s or
10% of the budget, whichever is smaller; 0 returns the first program), ``simplify``.
"""

from __future__ import annotations

from typing import Any

from plansynth.budget import Budget
from plansynth.errors import PlansynthError
from plansynth.grid.native.engine import Engine
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import LengthOutcome, register_backend


class InvalidOption(PlansynthError, TypeError):
    """An option the native backend does not have (or not written KEY=VALUE)."""


class NativeBackend:
    """The :class:`~plansynth.grid.result.GridBackend` of the native engine."""

    name = "native"

    def __init__(self, options: list[str] | tuple[str, ...] = (), **kwargs: Any) -> None:
        # ``options`` are KEY=VALUE strings, as `plansynth grid solve -O minimize=true` gives them.
        options_ = dict(kwargs)
        for item in options:
            key, sep, value = item.partition("=")
            if not sep:
                raise InvalidOption(f"native solver option {item!r} is not KEY=VALUE")
            options_[key.strip().replace("-", "_")] = _parse(value.strip())
        options = options_
        unknown = set(options) - {"minimize", "condition_depth", "max_tree_depth", "max_configs", "use_rust", "improve", "conflicts", "attempt_seconds", "max_clauses", "tree_conditions", "improve_seconds", "improve_states", "quick", "effort", "simplify", "exact_states"}
        if unknown:
            raise InvalidOption(f"unknown native solver option(s): {', '.join(sorted(unknown))}")
        self.options = dict(options)
        self._engine = Engine(**options)

    def version(self) -> str:
        from plansynth import __version__ as py_version
        from plansynth.grid.native import fast

        core = fast.core_version() if fast.available() else "pure-python"
        return f"plansynth {py_version} (core {core})"

    def solve_length(self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None) -> LengthOutcome:
        return self._engine.solve_length(problem, steps, budget, depth_bound=depth_bound)


def _parse(value: str) -> Any:
    low = value.lower()
    if low in ("true", "yes", "on"):
        return True
    if low in ("false", "no", "off"):
        return False
    if low in ("none", "null"):
        return None
    for cast in (int, float):
        try:
            return cast(value)
        except ValueError:
            pass
    return value


register_backend("native", NativeBackend)

"""Backend ``native``: the exact engine of :mod:`plansynth.grid.native` (the default).

Options: ``minimize`` (search program depths 1, 4, 5, ... over every winning strategy
and report the smallest, proved minimal when the condition enumeration is complete),
``condition_depth`` (deepest condition enumerated, default 4), ``max_tree_depth``,
``max_configs`` (joint obstacle configurations explored before answering unknown),
``use_rust`` (None: the compiled core when built; False: the pure-Python references).
"""

from __future__ import annotations

from typing import Any

from plansynth.budget import Budget
from plansynth.grid.native.engine import Engine
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import LengthOutcome, register_backend


class NativeBackend:
    """The :class:`~plansynth.grid.result.GridBackend` of the native engine."""

    name = "native"

    def __init__(self, **options: Any) -> None:
        unknown = set(options) - {"minimize", "condition_depth", "max_tree_depth", "max_configs", "use_rust", "improve", "conflicts", "attempt_seconds", "max_clauses", "tree_conditions", "improve_seconds"}
        if unknown:
            raise TypeError(f"unknown native solver option(s): {', '.join(sorted(unknown))}")
        self.options = dict(options)
        self._engine = Engine(**options)

    def version(self) -> str:
        from plansynth import __version__ as py_version
        from plansynth.grid.native import fast

        core = fast.core_version() if fast.available() else "pure-python"
        return f"plansynth {py_version} (core {core})"

    def solve_length(self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None) -> LengthOutcome:
        return self._engine.solve_length(problem, steps, budget, depth_bound=depth_bound)


register_backend("native", NativeBackend)

"""Backend ``native``: the exact engine of :mod:`plansynth.grid.native` (the default).

Its options are one frozen :class:`~plansynth.grid.native.options.NativeOptions`, given
as that value (``options=NativeOptions(...)``, as the CLI and bench build it once), as
``KEY=VALUE`` strings (``plansynth grid solve -O minimize=true``) or as keywords; every
option is listed, with what it does, in :data:`~plansynth.grid.native.options.OPTION_DOCS`
(and in the README's native-engine section). An unknown option or a bad value is
:class:`~plansynth.grid.native.options.InvalidOption`, never dropped.
"""

from __future__ import annotations

from typing import Any

from plansynth.budget import Budget
from plansynth.grid.native.engine import Engine
from plansynth.grid.native.options import InvalidOption, NativeOptions
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import LengthOutcome

__all__ = ["NativeBackend", "InvalidOption"]


class NativeBackend:
    """The :class:`~plansynth.grid.result.GridBackend` of the native engine."""

    name = "native"

    def __init__(self, options: NativeOptions | list[str] | tuple[str, ...] = (), **kwargs: Any) -> None:
        if isinstance(options, NativeOptions):
            if kwargs:
                raise InvalidOption(
                    "native", "options", "give the native options as one NativeOptions or as keywords, not both"
                )
            self.options = options
        else:
            self.options = NativeOptions.parse(options, **kwargs)
        self._engine = Engine(self.options)

    def version(self) -> str:
        from plansynth import __version__ as py_version
        from plansynth.grid.native import fast

        core = fast.core_version() if fast.available() else "pure-python"
        return f"plansynth {py_version} (core {core})"

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        return self._engine.solve_length(problem, steps, budget, depth_bound=depth_bound)

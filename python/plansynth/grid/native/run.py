"""One solve of one length, as the engine's parts see it: the options (read only), what
the budget gives (its seconds, the memory the game may use) and the counters the
outcome reports, with the seconds of each phase (STYLE.md, point 1: what a run did is in
the result, never on the engine)."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from plansynth.budget import DEFAULT_MEMORY_MB, Budget, Clock
from plansynth.grid.native import fast
from plansynth.grid.native.conditions import Enumeration, _enumerate, check_enumeration_fits, condition_limit
from plansynth.grid.native.options import NativeOptions
from plansynth.grid.problem import GridProblem

__all__ = ["RunState", "conditions_upto"]


def conditions_upto(
    states: Sequence[Sequence[int]],
    variables: Sequence[str],
    max_constant: int,
    max_depth: int,
    *,
    limit: int | None = None,
    use_rust: bool | None = None,
) -> Enumeration:
    """Conditions with a completeness flag: the compiled core when available (and
    ``use_rust`` is not False), else the pure-Python reference; both give the same."""
    if use_rust is not False and fast.available():
        return fast.enumerate_conditions(states, variables, max_constant, max_depth, limit)
    return _enumerate(states, variables, max_constant, max_depth, limit)


class RunState:
    """The state of one run: ``o`` (the options), ``budget_seconds``, ``memory_mb`` (the
    joint game is explored until it would outgrow this, default
    :data:`~plansynth.budget.DEFAULT_MEMORY_MB`, or the time runs out; ``max_configs``
    adds an explicit cap) and ``counters``."""

    def __init__(self, options: NativeOptions) -> None:
        self.o = options
        self.counters: dict[str, Any] = {}
        self.budget_seconds: float | None = None
        self.memory_mb = DEFAULT_MEMORY_MB
        self._t_phase = time.perf_counter()

    def start(self, budget: Budget, t0: float) -> None:
        """Begin a run at ``t0`` under ``budget``: fresh counters."""
        self.counters = {"phase_seconds": {}}
        self._t_phase = t0
        self.budget_seconds = budget.seconds
        self.memory_mb = budget.memory_mb or DEFAULT_MEMORY_MB

    def phase(self, name: str) -> None:
        """Close the current phase: add its seconds to ``phase_seconds[name]``."""
        now = time.perf_counter()
        ph = self.counters.setdefault("phase_seconds", {})
        ph[name] = round(ph.get(name, 0.0) + now - self._t_phase, 6)
        self._t_phase = now

    def conditions(
        self,
        states: Sequence[tuple[int, ...]],
        variables,
        problem: GridProblem,
        max_depth: int,
        clock: Clock | None = None,
    ) -> Enumeration:
        """The conditions over ``states`` up to ``max_depth`` (refused when they do not
        fit what is left of the budget), counted in ``counters["conditions"]``."""
        if clock is not None:
            self.check_conditions_fit(len(states), len(variables), problem, clock)
        e = conditions_upto(
            states,
            variables,
            problem.max_constant,
            max_depth,
            limit=condition_limit(len(states)),
            use_rust=self.o.use_rust,
        )
        self.counters["conditions"] = len(e.conditions)
        return e

    def check_conditions_fit(self, n_states: int, n_vars: int, problem: GridProblem, clock: Clock) -> None:
        """:func:`~plansynth.grid.native.conditions.check_enumeration_fits` under this
        run's memory."""
        check_enumeration_fits(n_states, n_vars, problem.max_constant, clock, self.memory_mb)

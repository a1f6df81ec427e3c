"""Budgeted SAT calls (CaDiCaL through PySAT) for the stationary strategy and the
decision-tree encodings: solved in conflict slices so the clock is read in between,
with an optional allowance of conflicts or seconds per call (:class:`ConflictLimit`)."""

from __future__ import annotations

import time
from typing import Any

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.limits import check_clock

__all__ = ["SAT_SOLVER", "ConflictLimit", "solve_clauses", "solve_sliced"]

SAT_SOLVER = "cadical195"


class ConflictLimit(BudgetExhausted):
    """The SAT call used up its own allowance of conflicts or seconds, not the budget
    (the caller may try something else).

    >>> str(ConflictLimit("SAT solving", "conflicts", "more than 2000 conflicts"))
    'more than 2000 conflicts'
    """


def solve_clauses(
    clauses: list[list[int]],
    clock: Clock | None,
    phases: list[int] | None = None,
    max_conflicts: int | None = None,
    max_seconds: float | None = None,
) -> list[int] | None:
    """Solve with CaDiCaL; :class:`~plansynth.budget.BudgetExhausted` when the clock runs
    out, :class:`ConflictLimit` after ``max_conflicts`` conflicts or ``max_seconds``
    seconds of this call."""
    from pysat.solvers import Solver  # here: a game decided without SAT never loads it

    with Solver(name=SAT_SOLVER, bootstrap_with=clauses) as s:
        if phases:
            s.set_phases(phases)
        return solve_sliced(s, clock, max_conflicts, max_seconds)


def solve_sliced(
    solver: Any, clock: Clock | None, max_conflicts: int | None = None, max_seconds: float | None = None
) -> list[int] | None:
    """One (possibly incremental) CaDiCaL call: a model, or None when unsatisfiable.

    CaDiCaL cannot be interrupted from another thread through PySAT, but it honours
    conflict budgets: solve in slices and look at the clock in between.
    """
    t0 = time.perf_counter()
    used = 0
    while True:
        check_clock(clock, "SAT solving")
        if max_conflicts is not None and used >= max_conflicts:
            raise ConflictLimit("SAT solving", "conflicts", f"more than {max_conflicts} conflicts")
        if max_seconds is not None and time.perf_counter() - t0 > max_seconds:
            raise ConflictLimit("SAT solving", "time", f"more than {max_seconds:.2f} s")
        solver.conf_budget(2_000)
        used += 2_000
        answer = solver.solve_limited()
        if answer is not None:
            return solver.get_model() if answer else None

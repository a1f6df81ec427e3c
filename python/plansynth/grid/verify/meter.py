"""The budget of one verification (STYLE.md, point 4), read cheaply from the search's
inner loops: a work counter in front of the shared :class:`~plansynth.budget.Clock`."""

from __future__ import annotations

import time
from dataclasses import replace

from plansynth.budget import DEFAULT_MEMORY_MB, Budget, BudgetExhausted
from plansynth.grid.verify.verdict import Verdict, VerifyStatus

__all__ = ["Meter"]


class Meter:
    """The budget of one verification: time and memory (``memory_mb``, default
    :data:`~plansynth.budget.DEFAULT_MEMORY_MB`), checked every :data:`CHECK_WORK` units
    of work (cells handled), so that neither overshoots by more than a few milliseconds
    or megabytes. ``phase`` names what the search is doing, for the verdict.

    >>> meter = Meter(Budget(seconds=1e-9))
    >>> meter.phase = "the layered search"
    >>> try:
    ...     meter.check()
    ... except BudgetExhausted as exc:
    ...     print(exc.phase, "|", meter.reason(exc))
    the layered search | time (1e-09 s)
    """

    #: Work between two checks, in units of about a microsecond: a cell handled in Python
    #: is 1, a call of the semantics :data:`SEMANTICS_CALL`.
    CHECK_WORK = 1 << 14
    SEMANTICS_CALL = 8

    def __init__(self, budget: Budget | None) -> None:
        limited = None if budget is None else replace(budget, memory_mb=budget.memory_mb or DEFAULT_MEMORY_MB)
        self.clock = None if limited is None else limited.clock()
        self.work = 0
        self.phase = "setting up"

    def tick(self, work: int = 1) -> None:
        """Count ``work`` units; every :data:`CHECK_WORK` of them, :meth:`check`."""
        if self.clock is None:
            return
        self.work += work
        if self.work >= self.CHECK_WORK:
            self.work = 0
            self.check()

    def check(self) -> None:
        """Raise :class:`~plansynth.budget.BudgetExhausted` naming :attr:`phase` once the
        time or the memory is used up."""
        if self.clock is not None:
            self.clock.check(self.phase)

    def reason(self, exc: BudgetExhausted) -> str:
        """What ran out, with its figures: ``time (1 s)`` or ``memory (it grew by ...)``."""
        assert self.clock is not None, "only a budgeted meter runs out"
        budget = self.clock.budget
        if exc.resource == "memory":
            return f"memory (it grew by {self.clock.memory_used() >> 20} MB, over the budget of {budget.memory_mb} MB)"
        return f"{exc.resource} ({budget.seconds:g} s)" if exc.resource == "time" else exc.resource

    def ran_out(self, exc: BudgetExhausted | MemoryError, steps: int | None, explored: int, t0: float) -> Verdict:
        """The ``unknown`` verdict of a check that ``exc`` stopped (the budget's exception,
        or a ``MemoryError``), started at ``t0``: the phase it stopped in and what ran out."""
        if isinstance(exc, BudgetExhausted):
            phase, why = exc.phase, self.reason(exc)
        else:
            phase, why = self.phase, "out of memory"
        return Verdict(
            VerifyStatus.UNKNOWN,
            steps,
            None,
            explored,
            time.perf_counter() - t0,
            phase,
            f"the verifier's budget ran out in {phase}: {why}",
        )

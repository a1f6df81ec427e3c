"""Explicit solver budgets (STYLE.md, point 4).

Every solve takes a :class:`Budget`. A budget that runs out makes the answer
``unknown``, naming the phase it was in; it never produces an empty answer or a hang.

Long phases without a main loop of their own (the convex decomposition, the
time-window bounds, building a MILP) run inside ``with clock.phase(name):`` and call
:func:`checkpoint` in their inner loops; once the clock's time is up, the checkpoint
raises :class:`BudgetExhausted` naming the phase, and the planner answers ``unknown``.

>>> clock = Budget(seconds=1e-9).clock()
>>> with clock.phase("the convex decomposition"):
...     checkpoint()
Traceback (most recent call last):
...
plansynth.budget.BudgetExhausted: budget ran out in the convex decomposition
>>> checkpoint()   # outside a phase: never raises
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

__all__ = ["Budget", "Clock", "BudgetExhausted", "checkpoint"]


class BudgetExhausted(Exception):
    """The time budget ran out in ``phase`` (an answer, ``unknown``, not an error)."""

    def __init__(self, phase: str) -> None:
        self.phase = phase
        super().__init__(f"budget ran out in {phase}")


_ACTIVE: ContextVar["tuple[Clock, str] | None"] = ContextVar("plansynth_budget_phase", default=None)


def checkpoint() -> None:
    """Raise :class:`BudgetExhausted` if the clock of the enclosing
    :meth:`Clock.phase` is out of time (cheap: call it in inner loops)."""
    active = _ACTIVE.get()
    if active is not None and active[0].out_of_time():
        raise BudgetExhausted(active[1])


@dataclass(frozen=True)
class Budget:
    """Limits on one solve.

    ``seconds`` is wall-clock time; ``iterations`` counts the solver's own main-loop
    iterations (for example SAT/LP rounds of the lazy SMT loop, or path lengths tried).
    ``None`` means unlimited.

    >>> Budget(seconds=2.0).clock().remaining() <= 2.0
    True
    """

    seconds: float | None = None
    iterations: int | None = None
    memory_mb: int | None = None

    def __post_init__(self) -> None:
        if self.seconds is not None and not self.seconds > 0:
            raise ValueError(f"budget seconds must be positive, got {self.seconds}")
        if self.iterations is not None and self.iterations < 0:
            raise ValueError(f"budget iterations must be >= 0, got {self.iterations}")

    def clock(self) -> "Clock":
        """Start counting this budget now."""
        return Clock(self)


class Clock:
    """A running budget: how much time and how many iterations are left."""

    def __init__(self, budget: Budget) -> None:
        self.budget = budget
        self.start = time.perf_counter()
        self.iterations = 0

    def elapsed(self) -> float:
        return time.perf_counter() - self.start

    def remaining(self) -> float:
        """Seconds left (``math.inf`` when the budget has no time limit)."""
        if self.budget.seconds is None:
            return math.inf
        return max(0.0, self.budget.seconds - self.elapsed())

    def out_of_time(self) -> bool:
        """True once the time (not the iterations) has run out."""
        return self.budget.seconds is not None and self.elapsed() >= self.budget.seconds

    @contextmanager
    def phase(self, name: str) -> Iterator["Clock"]:
        """Within this block, :func:`checkpoint` raises :class:`BudgetExhausted`
        naming ``name`` once this clock is out of time."""
        token = _ACTIVE.set((self, name))
        try:
            yield self
        finally:
            _ACTIVE.reset(token)

    def tick(self) -> None:
        """Count one main-loop iteration."""
        self.iterations += 1

    def exhausted(self) -> bool:
        """True once time or iterations have run out."""
        if self.budget.seconds is not None and self.elapsed() >= self.budget.seconds:
            return True
        if self.budget.iterations is not None and self.iterations >= self.budget.iterations:
            return True
        return False

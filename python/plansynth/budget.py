"""Explicit solver budgets (STYLE.md, point 4).

Every solve takes a :class:`Budget`. A budget that runs out makes the answer
``unknown``; it never produces an empty answer or a hang.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass


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

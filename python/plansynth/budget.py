"""Explicit solver budgets (STYLE.md, point 4): one :class:`Budget`, one :class:`Clock`
and one exception family for both halves and every backend.

Every solve takes a :class:`Budget`: wall-clock seconds, main-loop iterations and the
memory the solve may add to the process. A budget that runs out makes the answer
``unknown``, naming the phase it was in and the resource that ran out; it never
produces an empty answer or a hang.

Long phases without a main loop of their own (the convex decomposition, the
time-window bounds, building a MILP) run inside ``with clock.phase(name):`` and call
:func:`checkpoint` in their inner loops; once the clock's time (or memory) is up, the
checkpoint raises :class:`BudgetExhausted` naming the phase, and the planner answers
``unknown``. Loops over horizons or path lengths use :meth:`Clock.steps`, and a part of
the solve that gets what is left of the budget gets :meth:`Clock.left`.

Every "the budget ran out" exception is a :class:`BudgetExhausted`: the LP solver's
(:class:`~plansynth.reach.lazy.conplan.runs.LpBudgetExhausted`), the native engine's,
the verifier's, and the compiled core's (raised from Rust as this class).

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
import os
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from typing import TypeVar

__all__ = ["Budget", "Clock", "BudgetExhausted", "checkpoint", "rss_bytes", "DEFAULT_MEMORY_MB"]

#: Memory (MB) a solve or a verification may add to the process when its budget gives
#: none and the part that runs needs a limit to stay safe (the native engine's game, the
#: grid verifier's sets).
DEFAULT_MEMORY_MB = 4096

#: Seconds between two readings of the process's memory by a clock (a reading costs a
#: few microseconds; checkpoints run in inner loops).
MEMORY_CHECK_SECONDS = 0.005

T = TypeVar("T")


class BudgetExhausted(Exception):
    """The budget ran out in ``phase`` (an answer, ``unknown``, not an error).

    ``resource`` is what ran out: ``"time"``, ``"memory"``, ``"iterations"`` or a
    solver's own limit (``"conflicts"``, ``"configurations"``).

    >>> str(BudgetExhausted("the MILP", "memory"))
    'budget ran out in the MILP (memory)'
    """

    def __init__(self, phase: str = "the solve", resource: str = "time", detail: str = "") -> None:
        self.phase = phase
        self.resource = resource
        self.detail = detail
        shown = f" ({resource})" if resource != "time" else ""
        super().__init__(detail or f"budget ran out in {phase}{shown}")


_ACTIVE: ContextVar[tuple[Clock, str] | None] = ContextVar("plansynth_budget_phase", default=None)


def checkpoint() -> None:
    """Raise :class:`BudgetExhausted` if the clock of the enclosing
    :meth:`Clock.phase` is out of time or memory (cheap: call it in inner loops)."""
    active = _ACTIVE.get()
    if active is not None:
        active[0].check(active[1])


def rss_bytes() -> int:
    """The process's resident set now (Linux ``/proc/self/statm``; else its peak)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * _PAGE
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


try:
    _PAGE = os.sysconf("SC_PAGE_SIZE")
except (ValueError, OSError, AttributeError):  # pragma: no cover
    _PAGE = 4096


@dataclass(frozen=True)
class Budget:
    """Limits on one solve.

    ``seconds`` is wall-clock time; ``iterations`` counts the solver's own main-loop
    iterations (for example SAT/LP rounds of the lazy SMT loop, or path lengths tried);
    ``memory_mb`` is the memory the solve may add to the process (its resident set
    above what it was when the clock started). ``None`` means unlimited.

    >>> Budget(seconds=2.0).clock().remaining() <= 2.0
    True
    >>> Budget(seconds=0)
    Traceback (most recent call last):
    ...
    ValueError: budget seconds must be positive, got 0
    """

    seconds: float | None = None
    iterations: int | None = None
    memory_mb: int | None = None

    def __post_init__(self) -> None:
        if self.seconds is not None and not self.seconds > 0:
            raise ValueError(f"budget seconds must be positive, got {self.seconds}")
        if self.iterations is not None and self.iterations < 0:
            raise ValueError(f"budget iterations must be >= 0, got {self.iterations}")
        if self.memory_mb is not None and not self.memory_mb > 0:
            raise ValueError(f"budget memory_mb must be positive, got {self.memory_mb}")

    def clock(self) -> Clock:
        """Start counting this budget now."""
        return Clock(self)


class Clock:
    """A running budget: how much time, memory and how many iterations are left."""

    def __init__(self, budget: Budget) -> None:
        self.budget = budget
        self.start = time.perf_counter()
        self.iterations = 0
        self._memory_limit = None if budget.memory_mb is None else int(budget.memory_mb) << 20
        self._memory_base = rss_bytes() if self._memory_limit is not None else 0
        self._memory_read = self.start
        self._memory_over = False

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

    def memory_used(self) -> int:
        """Bytes the process's resident set has grown by since the clock started."""
        return rss_bytes() - self._memory_base

    def out_of_memory(self) -> bool:
        """True once the process has grown past the budget's ``memory_mb`` (read at most
        every :data:`MEMORY_CHECK_SECONDS`)."""
        if self._memory_limit is None or self._memory_over:
            return self._memory_over
        now = time.perf_counter()
        if now - self._memory_read >= MEMORY_CHECK_SECONDS:
            self._memory_read = now
            self._memory_over = self.memory_used() > self._memory_limit
        return self._memory_over

    def check(self, phase: str) -> None:
        """Raise :class:`BudgetExhausted` naming ``phase`` once time or memory is up."""
        if self.out_of_time():
            raise BudgetExhausted(phase, "time")
        if self.out_of_memory():
            raise BudgetExhausted(
                phase,
                "memory",
                f"budget ran out in {phase} (memory: the process grew by "
                f"{self.memory_used() >> 20} MB, over {self.budget.memory_mb} MB)",
            )

    @contextmanager
    def phase(self, name: str) -> Iterator[Clock]:
        """Within this block, :func:`checkpoint` raises :class:`BudgetExhausted`
        naming ``name`` once this clock is out of time or memory."""
        token = _ACTIVE.set((self, name))
        try:
            yield self
        finally:
            _ACTIVE.reset(token)

    def tick(self) -> None:
        """Count one main-loop iteration."""
        self.iterations += 1

    def exhausted(self) -> bool:
        """True once time, memory or iterations have run out."""
        if self.out_of_time() or self.out_of_memory():
            return True
        return self.budget.iterations is not None and self.iterations >= self.budget.iterations

    def left(self, *, floor: float = 1e-3) -> Budget:
        """What is left of the budget, as a budget for a part of the solve: the
        seconds remaining (at least ``floor``) and the same memory limit."""
        remaining = self.remaining()
        return Budget(seconds=None if math.isinf(remaining) else max(remaining, floor), memory_mb=self.budget.memory_mb)

    def steps(
        self, values: Iterable[T], *, progress: Callable[[T, int], None] | None = None, what: str = "step"
    ) -> Iterator[T]:
        """The main loop over ``values`` (horizons, path lengths) under this budget:
        before each value, ``progress(value, iterations so far)`` is called, the budget
        is checked (:class:`BudgetExhausted` naming ``what`` and the value once time,
        memory or iterations are out) and one iteration is counted, so that the
        iteration the loop leaves by ``break`` or ``return`` counts too.

        >>> clock = Budget(iterations=2).clock()
        >>> seen = []
        >>> try:
        ...     for L in clock.steps(range(5, 9), what="horizon"):
        ...         seen.append(L)
        ... except BudgetExhausted as exc:
        ...     print(seen, exc)
        [5, 6] budget ran out before horizon 7 (iterations)
        """
        for value in values:
            if progress is not None:
                progress(value, self.iterations)
            if self.exhausted():
                resource = "time" if self.out_of_time() else "memory" if self.out_of_memory() else "iterations"
                raise BudgetExhausted(
                    f"before {what} {value}",
                    resource,
                    f"budget ran out before {what} {value}" + ("" if resource == "time" else f" ({resource})"),
                )
            self.tick()
            yield value

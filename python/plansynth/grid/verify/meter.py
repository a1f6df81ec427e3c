"""The budget of one verification, read cheaply from the search's inner loops."""

from __future__ import annotations

from plansynth.budget import Budget

__all__ = ["Meter", "OutOfBudget", "DEFAULT_MEMORY_MB"]

#: Memory (MB) a budgeted verification may add to the process when its budget gives none
#: (the native engine's default too).
DEFAULT_MEMORY_MB = 4096


class OutOfBudget(Exception):
    def __init__(self, phase: str, reason: str) -> None:
        self.phase = phase
        self.reason = reason
        super().__init__(f"{phase}: {reason}")


def _rss_bytes() -> int:
    """The process's resident set now (Linux ``/proc/self/statm``; else its peak)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[1]) * _PAGE
    except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


try:
    import os as _os

    _PAGE = _os.sysconf("SC_PAGE_SIZE")
except (ValueError, OSError, AttributeError):  # pragma: no cover
    _PAGE = 4096


class Meter:
    """The budget of one verification: time and memory, checked every :data:`CHECK_WORK`
    units of work (cells handled), so that neither overshoots by more than a few
    milliseconds or megabytes."""

    #: Work between two checks, in units of about a microsecond: a cell handled in Python
    #: is 1, a call of the semantics :data:`SEMANTICS_CALL`.
    CHECK_WORK = 1 << 14
    SEMANTICS_CALL = 8

    def __init__(self, budget: Budget | None) -> None:
        self.clock = None if budget is None else budget.clock()
        mb = None if budget is None else (budget.memory_mb or DEFAULT_MEMORY_MB)
        self.limit = None if mb is None else mb << 20
        self.base = _rss_bytes() if self.limit is not None else 0
        self.work = 0
        self.phase = "setting up"

    def tick(self, work: int = 1) -> None:
        if self.clock is None:
            return
        self.work += work
        if self.work >= self.CHECK_WORK:
            self.work = 0
            self.check()

    def check(self) -> None:
        if self.clock is None:
            return
        if self.clock.out_of_time():
            raise OutOfBudget(self.phase, f"time ({self.clock.budget.seconds:g} s)")
        if self.limit is not None:
            used = _rss_bytes() - self.base
            if used > self.limit:
                raise OutOfBudget(self.phase, f"memory (it grew by {used >> 20} MB, over the budget of "
                                  f"{self.limit >> 20} MB)")

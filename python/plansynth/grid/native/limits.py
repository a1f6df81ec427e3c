"""How the native engine stops when a limit is reached: the shared
:class:`~plansynth.budget.BudgetExhausted` (STYLE.md, point 4), naming the phase, the
resource that ran out and what was being done. The backend turns it into ``unknown``.

>>> from plansynth.budget import Budget
>>> try:
...     check_clock(Budget(seconds=1e-9).clock(), "solving the game", " at step 3")
... except BudgetExhausted as exc:
...     print(exc.phase, "|", exc.resource, "|", exc)
solving the game | time | solving the game at step 3: out of time
"""

from __future__ import annotations

from plansynth.budget import BudgetExhausted, Clock

__all__ = ["check_clock"]


def check_clock(clock: Clock | None, phase: str, where: str = "") -> None:
    """Raise :class:`BudgetExhausted` once ``clock`` has run out (time, memory or
    iterations), saying ``{phase}{where}: out of {resource}``; no clock never runs out."""
    if clock is None or not clock.exhausted():
        return
    resource = "time" if clock.out_of_time() else "memory" if clock.out_of_memory() else "iterations"
    raise BudgetExhausted(phase, resource, f"{phase}{where}: out of {resource}")

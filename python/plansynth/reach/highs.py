"""The one way plansynth makes a HiGHS instance (LPs of CON-PLAN, Shoukry et al.,
CDC 2016, Section V; the MILP baselines).

HiGHS runs every solve on a task scheduler shared by all the instances that run in a
thread, started by the first ``run()`` with that instance's ``threads`` option. From then on an instance whose ``threads`` differs
(other than 0, "whatever is running") refuses to run: HiGHS 1.16 logs "Option 'threads'
is set to 1 but the scheduler has already been initialized to use 2 threads" and
``run()`` returns an error with model status "Not Set". So a single default instance
run before the others made every later LP of CON-PLAN fail, depending on which code ran
first in the process.

:func:`new_highs` is therefore the only constructor the package uses: every instance
is silent and has ``threads`` = :data:`THREADS` (1: the LPs are small, a benchmark run
uses one core, and a single-threaded scheduler has no worker threads, so forked child
processes inherit nothing half-started). On its first call in a process it resets the
scheduler (``Highs.resetGlobalScheduler``), so that one started by other code with
another thread count before plansynth (a default ``Highs()`` of the caller, say) is
replaced at plansynth's next run rather than refusing it. Code that creates its own
instances later should leave ``threads`` at 0 or use this function.

>>> h = new_highs(presolve="off")
>>> o = h.getOptions()
>>> o.threads, o.output_flag, o.presolve
(1, False, 'off')
"""

from __future__ import annotations

from typing import Any

import highspy

__all__ = ["THREADS", "new_highs", "reset_scheduler"]

#: The ``threads`` option of every HiGHS instance plansynth makes.
THREADS = 1

_scheduler_reset = False


def reset_scheduler() -> None:
    """Drop the HiGHS scheduler of this thread so that the next ``run()`` starts one
    with :data:`THREADS` threads. Not while any HiGHS instance is solving."""
    global _scheduler_reset
    reset = getattr(highspy.Highs, "resetGlobalScheduler", None)  # absent from older highspy
    if reset is not None:
        reset(True)
    _scheduler_reset = True


def new_highs(**options: Any) -> highspy.Highs:
    """A silent HiGHS instance with ``threads`` = :data:`THREADS` and ``options`` set
    (option name -> value, e.g. ``time_limit=2.0``, ``presolve="off"``)."""
    if not _scheduler_reset:
        reset_scheduler()
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("threads", THREADS)
    for name, value in options.items():
        h.setOptionValue(name, value)
    return h

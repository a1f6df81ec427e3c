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

HiGHS 1.16 prints its banner ("Running HiGHS 1.16.0 ...") to the C library's standard
output when the first instance of a process is constructed, before any option can be
set (the maintainers' advice, ERGO-Code/HiGHS#1702, to set ``output_flag`` first, no
longer suffices), so a command's stdout (a table, or JSON a script parses) began with
two lines of licence text. :func:`new_highs` therefore constructs the process's first
instance with file descriptor 1 pointed at the null device (the C buffer flushed before
it is restored); later instances print nothing.

>>> h = new_highs(presolve="off")
>>> o = h.getOptions()
>>> o.threads, o.output_flag, o.presolve
(1, False, 'off')
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import highspy
import numpy as np

__all__ = ["THREADS", "new_highs", "reset_scheduler", "csc_lp", "pass_csc", "Rows"]

#: The ``threads`` option of every HiGHS instance plansynth makes.
THREADS = 1

_scheduler_reset = False
_banner_done = False


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
    h = highspy.Highs() if _banner_done else _first_highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("threads", THREADS)
    for name, value in options.items():
        h.setOptionValue(name, value)
    return h


def _first_highs() -> highspy.Highs:
    """The process's first instance, its banner sent to the null device (see above)."""
    global _banner_done
    import ctypes
    import os
    import sys

    sys.stdout.flush()
    libc = ctypes.CDLL(None)
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        h = highspy.Highs()
        libc.fflush(None)
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)
    _banner_done = True
    return h


def csc_lp(
    n_col: int,
    n_row: int,
    R: np.ndarray,
    C: np.ndarray,
    V: np.ndarray,
    cost: np.ndarray,
    col_lo: np.ndarray,
    col_hi: np.ndarray,
    row_lo: np.ndarray,
    row_hi: np.ndarray,
    integrality: list[Any] | None = None,
) -> highspy.HighsLp:
    """A HiGHS LP (a MILP with ``integrality``) with the column-wise matrix of the COO
    entries (R, C, V): the one assembly of CON-PLAN, the region MILP and the mission LP."""
    starts, index, value = _csc(n_col, n_row, R, C, V)
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = n_col, n_row
    lp.col_cost_ = cost
    lp.col_lower_, lp.col_upper_ = col_lo, col_hi
    lp.row_lower_, lp.row_upper_ = row_lo, row_hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = starts
    lp.a_matrix_.index_ = index
    lp.a_matrix_.value_ = value
    if integrality is not None:
        lp.integrality_ = integrality
    return lp


def _csc(n_col: int, n_row: int, R: np.ndarray, C: np.ndarray, V: np.ndarray) -> tuple[np.ndarray, ...]:
    """The column starts, row indices and values of the COO entries (R, C, V)."""
    # by column, then row (one stable sort of a single key: np.lexsort((R, C))'s order, in half the time)
    order = np.argsort(np.asarray(C, np.int64) * max(n_row, 1) + R, kind="stable")
    starts = np.zeros(n_col + 1, dtype=np.int32)
    np.cumsum(np.bincount(C, minlength=n_col), out=starts[1:])
    return starts, np.asarray(R)[order].astype(np.int32), np.asarray(V, float)[order]


def pass_csc(
    h: highspy.Highs,
    n_col: int,
    n_row: int,
    R: np.ndarray,
    C: np.ndarray,
    V: np.ndarray,
    cost: np.ndarray,
    col_lo: np.ndarray,
    col_hi: np.ndarray,
    row_lo: np.ndarray,
    row_hi: np.ndarray,
) -> None:
    """Load the LP of :func:`csc_lp` into ``h`` (a minimisation, its previous model,
    basis and solution dropped) from the arrays themselves: :func:`csc_lp`'s
    ``HighsLp`` copies each array into HiGHS element by element through Python
    (a fifth of a small team's run went there), ``passModel``'s array form by pointer."""
    starts, index, value = _csc(n_col, n_row, R, C, V)
    f64 = np.float64
    h.passModel(
        int(n_col),
        int(n_row),
        int(len(value)),
        int(highspy.MatrixFormat.kColwise),
        int(highspy.ObjSense.kMinimize),
        0.0,
        np.ascontiguousarray(cost, f64),
        np.ascontiguousarray(col_lo, f64),
        np.ascontiguousarray(col_hi, f64),
        np.ascontiguousarray(row_lo, f64),
        np.ascontiguousarray(row_hi, f64),
        starts,
        index,
        np.ascontiguousarray(value, f64),
        np.zeros(n_col, np.int32),  # (every column continuous)
    )


class Rows:
    """Row blocks of an LP in COO form, appended in order: ``add(rows, cols, values, lo,
    hi)`` adds ``len(lo)`` rows (``rows`` numbered from 0 within the block); ``on_add``
    runs before each block (a budget checkpoint).

    >>> r = Rows()
    >>> r.add(np.array([0, 0]), np.array([0, 1]), np.array([1.0, -1.0]), np.zeros(1), np.zeros(1))
    >>> r.add(np.array([0]), np.array([1]), np.array([2.0]), np.full(1, -np.inf), np.ones(1))
    >>> r.n_row, [a.tolist() for a in r.coo()], [a.tolist() for a in r.bounds()]
    (2, [[0, 0, 1], [0, 1, 1], [1.0, -1.0, 2.0]], [[0.0, -inf], [0.0, 1.0]])
    """

    def __init__(self, on_add: Callable[[], None] | None = None) -> None:
        self.n_row = 0
        self._on_add = on_add
        self._r: list[np.ndarray] = []
        self._c: list[np.ndarray] = []
        self._v: list[np.ndarray] = []
        self._lo: list[np.ndarray] = []
        self._hi: list[np.ndarray] = []

    def add(self, rows: Any, cols: Any, values: Any, lo: Any, hi: Any) -> None:
        if self._on_add is not None:
            self._on_add()
        self._r.append(self.n_row + np.asarray(rows))
        self._c.append(np.asarray(cols))
        self._v.append(np.asarray(values, float))
        self._lo.append(np.asarray(lo, float))
        self._hi.append(np.asarray(hi, float))
        self.n_row += len(lo)

    def coo(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(row, column, value) of every entry so far."""
        if not self._r:
            return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
        return (
            np.concatenate(self._r).astype(np.int64),
            np.concatenate(self._c).astype(np.int64),
            np.concatenate(self._v),
        )

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) of every row so far."""
        if not self._lo:
            return np.zeros(0), np.zeros(0)
        return np.concatenate(self._lo), np.concatenate(self._hi)

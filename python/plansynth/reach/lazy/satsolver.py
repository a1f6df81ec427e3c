"""The SAT side DIS-PLAN and the mission's DIS-PLAN share (Shoukry et al., CDC 2016,
Section IV, Algorithm 1): the solver (CaDiCaL through PySAT), the outcome of one call,
the store of counterexample clauses, and the slices of conflicts a call runs in so that
the budget is checked while CaDiCaL searches.

python-sat's CaDiCaL 1.9.5 refuses interrupt() and prop_budget() but honours
conf_budget() with solve_limited(): :class:`Slices` runs a call in slices of conflicts,
the clock checked between slices. The slice adapts so that one takes about
:data:`SLICE_SECONDS` (conflicts get dearer as the formula grows); the learned clauses
survive from slice to slice, so the answer is exactly the one an unlimited solve() would
give.

>>> from pysat.solvers import Solver
>>> s = Solver(name=SAT_SOLVER, bootstrap_with=[[1, 2], [-1]])
>>> Slices().solve(s, [])
<SatOutcome.SAT: 'sat'>
>>> Slices().solve(s, [-2])
<SatOutcome.UNSAT: 'unsat'>
>>> s.delete()
"""

from __future__ import annotations

import enum
import time
from collections.abc import Sequence

from plansynth.budget import Clock

__all__ = [
    "SAT_SOLVER",
    "CONFLICTS_PER_SLICE",
    "MIN_CONFLICTS_PER_SLICE",
    "MAX_CONFLICTS_PER_SLICE",
    "SLICE_SECONDS",
    "SatOutcome",
    "LearnedClauses",
    "Slices",
]

SAT_SOLVER = "cadical195"
CONFLICTS_PER_SLICE = 2_000  # the first slice
MIN_CONFLICTS_PER_SLICE = 100
MAX_CONFLICTS_PER_SLICE = 1_000_000
SLICE_SECONDS = 0.1


class SatOutcome(str, enum.Enum):
    SAT = "sat"
    UNSAT = "unsat"
    INTERRUPTED = "interrupted"

    def __bool__(self) -> bool:
        raise TypeError("a SatOutcome has no truth value")


class LearnedClauses:
    """Counterexample clauses added once each (a conflict and its shifted copies often
    coincide): the store DIS-PLAN and the mission DIS-PLAN
    (:class:`plansynth.reach.mission.bmc.MissionDisPlan`) share. Needs ``_add(clause)``."""

    _learned: set[tuple[int, ...]]
    clauses: int

    def _add(self, clause: list[int]) -> None:
        raise NotImplementedError

    def _learn_clause(self, clause: list[int]) -> None:
        """Add ``clause`` unless it was added before; count it in ``clauses``."""
        key = tuple(sorted(clause))
        if key in self._learned:
            return
        self._learned.add(key)
        self._add(clause)
        self.clauses += 1


class Slices:
    """One SAT call after another in slices of conflicts (see the module docstring);
    the slice's size carries over from call to call. Counter: ``slices``."""

    def __init__(self) -> None:
        self.size = CONFLICTS_PER_SLICE
        self.slices = 0

    def solve(self, solver, assumptions: Sequence[int], clock: Clock | None = None) -> SatOutcome:
        """SAT or UNSAT under ``assumptions``, or INTERRUPTED when ``clock`` runs out
        (checked before each slice)."""
        while True:
            if clock is not None and clock.exhausted():
                return SatOutcome.INTERRUPTED
            solver.conf_budget(self.size)
            t0 = time.perf_counter()
            answer = solver.solve_limited(assumptions=assumptions)
            took = time.perf_counter() - t0
            self.slices += 1
            if answer is None:
                if took < SLICE_SECONDS / 2:
                    self.size = min(MAX_CONFLICTS_PER_SLICE, self.size * 2)
                elif took > SLICE_SECONDS:
                    self.size = max(MIN_CONFLICTS_PER_SLICE, int(self.size * SLICE_SECONDS / took))
                continue
            return SatOutcome.SAT if answer else SatOutcome.UNSAT

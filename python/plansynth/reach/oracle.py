"""The limit beside every time: one cold LP over the final region sequence.

If an oracle handed the planner the region sequence r_0..r_N of its answer, the plan
would cost one linear program: CON-PLAN's feasibility LP for that sequence (Shoukry et
al., CDC 2016, Section IV, Problem 4.1, here with the segment-safe constraints when the
planner kept segments in the regions), built and solved from scratch. Its time is the
floor under any search over region sequences; a planner's total divided by it shows
the search's overhead. The LP is built and run by
:class:`~plansynth.reach.lazy.conplan.ConPlan` on a fresh HiGHS instance (no warm start,
no basis), and its time counts the model's construction (``passModel``) and the solve.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.solve import solve
>>> r = solve(maze(1))
>>> lim = oracle_lp(maze(1), r.regions)
>>> lim.feasible, lim.seconds > 0
(True, True)
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import highspy

from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.problem import ReachProblem

__all__ = ["OracleLP", "oracle_lp"]


@dataclass(frozen=True)
class OracleLP:
    """``seconds``: building and solving the one cold LP; ``feasible``: its answer."""

    seconds: float
    build_seconds: float
    solve_seconds: float
    feasible: bool
    horizon: int


def oracle_lp(problem: ReachProblem, regions: Sequence[int], *, abstraction: Abstraction | None = None,
              segment_safe: bool = True) -> OracleLP:
    """Time one cold CON-PLAN LP over ``regions`` (indices into ``abstract(problem)``)."""
    a = abstraction if abstraction is not None else abstract(problem)
    cp = ConPlan(problem, a, segment_safe=segment_safe)
    regs = [int(r) for r in regions]
    t0 = time.perf_counter()
    lay = cp.layout(0, len(regs) - 1)
    cp._pass_cold(lay, dict(enumerate(regs)), goal=True, anchored_start=True)
    t1 = time.perf_counter()
    cp.cold.run()
    t2 = time.perf_counter()
    feasible = cp.cold.getModelStatus() == highspy.HighsModelStatus.kOptimal
    return OracleLP(seconds=t2 - t0, build_seconds=t1 - t0, solve_seconds=t2 - t1, feasible=bool(feasible),
                    horizon=len(regs) - 1)

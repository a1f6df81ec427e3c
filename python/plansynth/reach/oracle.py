"""The limit beside every time: one cold LP over the final region sequence.

If an oracle handed the planner the region sequence r_0..r_N of its answer, the plan
would cost one linear program: CON-PLAN's feasibility LP for that sequence (Shoukry et
al., CDC 2016, Section IV, Problem 4.1, here with the segment-safe constraints when the
planner kept segments in the regions), built and solved from scratch. Its time is the
floor under any search over region sequences; a planner's total divided by it shows
the search's overhead. The LP is built and solved as
:class:`~plansynth.reach.lazy.conplan.ConPlan` solves a plan LP that has no basis to
start from, in a fresh ConPlan: split into independent blocks (one per axis) beyond
:data:`~plansynth.reach.lazy.conplan.layout.LONG_CHAIN_STATES` states, by the
interior-point method first from
:data:`~plansynth.reach.lazy.conplan.runs.INTERIOR_STATES` on (the parts on two
threads at once, as the planner runs them), and without the
simplex iteration cap the planner puts on long chains (so the limit is a solved LP: with
the cap, an order-25 chain's cold simplex stopped at 5,000 iterations, short of an
answer). Its time counts the model's construction (``passModel``) and the solve.

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

from plansynth.budget import Budget
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.conplan.runs import LpBudgetExhausted, LpFailure
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


def oracle_lp(
    problem: ReachProblem,
    regions: Sequence[int],
    *,
    abstraction: Abstraction | None = None,
    segment_safe: bool = True,
    seconds: float | None = None,
) -> OracleLP | None:
    """Time one cold CON-PLAN LP over ``regions`` (indices into ``abstract(problem)``);
    None when it does not finish within ``seconds``, computing the abstraction included
    (a dense n = 50 LP can take a minute), or HiGHS cannot solve it (a measurement: the
    run it measures keeps its answer)."""
    clock = None if seconds is None else Budget(seconds=seconds).clock()
    a = abstraction if abstraction is not None else abstract(problem)
    if clock is not None and clock.exhausted():
        return None
    cp = ConPlan(problem, a, segment_safe=segment_safe, clock=clock)
    regs = [int(r) for r in regions]
    N = len(regs) - 1
    plan = dict(enumerate(regs))
    slot = cp.slot
    t0 = time.perf_counter()
    lay = cp.layout(0, N)  # (exactly the plan's states: no spare frame)
    cp._load(slot, lay, plan, cp.bounds(lay, plan, goal=True, anchored_start=True, slack=False))
    t1 = time.perf_counter()
    for h in [p.highs for p in slot.parts] if slot.parts is not None else [slot.highs]:
        h.setOptionValue("simplex_iteration_limit", 2**31 - 1)
    try:
        col = cp._run_slot(slot, "plan")
    except (LpBudgetExhausted, LpFailure):
        return None
    t2 = time.perf_counter()
    return OracleLP(seconds=t2 - t0, build_seconds=t1 - t0, solve_seconds=t2 - t1, feasible=col is not None, horizon=N)

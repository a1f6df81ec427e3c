"""The segment theory's point LP (:mod:`plansynth.reach.lazy.pointlp`) within a budget."""

from __future__ import annotations

from plansynth.reach.abstraction import abstract
from plansynth.reach.families import maze
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.lazy.pointlp import PointLP


def test_the_point_lps_time_limit_is_relative_to_its_run_time() -> None:
    """HiGHS compares ``time_limit`` with the instance's run time summed over its runs, so
    the segment theory's point LP, run again and again, sets it past that sum: with the
    seconds left as an absolute limit, an instance that had run longer than them in all
    stopped at once ("budget ran out") though each solve takes milliseconds."""

    class Left:  # a clock with a fixed number of seconds left
        seconds = 1.0

        def remaining(self) -> float:
            return self.seconds

    p = maze(1)
    a = abstract(p)
    plan = plan_lazy(p).regions
    clock = Left()
    lp = PointLP(p, a, clock)  # type: ignore[arg-type]

    def solved() -> bool:  # (a new model each time: a cold solve)
        lp.load(dict(enumerate(plan)), {}, 0, len(plan) - 1, start=True, goal=True)
        return lp.run() is not None

    while lp.highs.getRunTime() < 0.05:
        assert solved()
    clock.seconds = 0.5 * lp.highs.getRunTime()  # less than the instance has run, more than a solve
    for _ in range(3):
        assert solved()

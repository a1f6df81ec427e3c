"""The lazy SMT planner's options as one frozen value (Shoukry et al., CDC 2016,
Algorithm 1, and the refinements beyond the paper).

:class:`LazyOptions` is built once (by the CLI, by bench, or by a caller) and passed
to :func:`plansynth.reach.lazy.loop.plan_lazy`, which records it in the result.
:meth:`LazyOptions.paper` is the loop as published; :data:`CONFIGURATIONS` holds the
named configurations that :func:`plansynth.reach.solve` knows as planners
(``lazy-smt-paper`` and the others), as values. Nothing heavy is imported here, so the
CLI can check options before any solver loads.

>>> LazyOptions.paper().counterexample, LazyOptions.paper().horizon_search
('zeroprefix', 'linear')
>>> LazyOptions(counterexample="nosuch")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt: option 'counterexample': unknown counterexample strategy 'nosuch' (known: farkas, zeroprefix, trivial, iis)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

from plansynth.errors import InvalidOption

__all__ = ["LazyOptions", "CONFIGURATIONS", "COUNTEREXAMPLES", "HORIZON_SEARCHES", "SLACK_WEIGHTS", "WINDOW_GROWTH",
           "LARGE_WINDOW_GROWTH", "LARGE_REGIONS", "window_growth_for"]

#: CON-PLAN's counterexample strategies (``farkas`` is ``trivial`` shrunk by its Farkas
#: certificate; see :mod:`plansynth.reach.lazy.conplan`).
COUNTEREXAMPLES = ("farkas", "zeroprefix", "trivial", "iis")
HORIZON_SEARCHES = ("window", "linear", "minimal")
#: The window search's growth (``window_growth=None``): each window this fraction longer
#: than its start, or, on an abstraction of more than LARGE_REGIONS regions, twice as
#: long. There the region-hop and displacement bounds ignore turning, the first feasible
#: horizon lies far above them (the GCS paper's 50 x 50 maze: box bound 286, nothing
#: found below 357 in minutes), and refuting one window costs more than a longer plan.
WINDOW_GROWTH = 0.25
LARGE_WINDOW_GROWTH = 1.0
LARGE_REGIONS = 200


def window_growth_for(growth: float | None, regions: int) -> float:
    """The window growth used: ``growth`` when given, else by the abstraction's size.

    >>> window_growth_for(None, 10), window_growth_for(None, 1571), window_growth_for(0.5, 1571)
    (0.25, 1.0, 0.5)
    """
    if growth is not None:
        return float(growth)
    return LARGE_WINDOW_GROWTH if regions > LARGE_REGIONS else WINDOW_GROWTH
SLACK_WEIGHTS = ("geometric", "uniform")


@dataclass(frozen=True)
class LazyOptions:
    """How the lazy loop runs; the defaults are plansynth's loop, :meth:`paper` the
    paper's. See :func:`plansynth.reach.lazy.loop.plan_lazy` for each option.

    ``max_horizon`` (None: the problem's) and ``segment_safe`` are the options every
    planner shares; the others tune the loop.
    """

    max_horizon: int | None = None
    counterexample: str = "farkas"
    segment_safe: bool = True
    generalize: bool = True
    minimize: bool = True
    slack_weights: str = "geometric"
    cardinality: str = "auto"
    lower_bound: bool = True
    horizon_search: str = "window"
    window_growth: float | None = None  # None: WINDOW_GROWTH, or LARGE_WINDOW_GROWTH on large abstractions
    transit: bool = True
    guided: bool = True
    widen: bool = False
    wait_shifts: bool = True
    prove: bool = False  # segment-safe: prove claims by the relaxation MILP (lazy/relaxation.py)
    reach_sets: bool = True  # horizon_search="minimal": the per-axis reachable sets first (lazy/axisreach.py)

    def __post_init__(self) -> None:
        def bad(option: str, reason: str) -> InvalidOption:
            return InvalidOption("lazy-smt", option, reason)

        if self.counterexample not in COUNTEREXAMPLES:
            raise bad("counterexample", f"unknown counterexample strategy {self.counterexample!r} "
                                        f"(known: {', '.join(COUNTEREXAMPLES)})")
        if self.horizon_search not in HORIZON_SEARCHES:
            raise bad("horizon_search", f"unknown horizon search {self.horizon_search!r} "
                                        f"(known: {', '.join(HORIZON_SEARCHES)})")
        if self.slack_weights not in SLACK_WEIGHTS:
            raise bad("slack_weights", f"unknown slack weights {self.slack_weights!r} (known: {', '.join(SLACK_WEIGHTS)})")
        if self.window_growth is not None and not (
                isinstance(self.window_growth, (int, float)) and math.isfinite(self.window_growth)
                and self.window_growth > 0):
            raise bad("window_growth", f"window_growth must be positive, got {self.window_growth}")
        if self.max_horizon is not None and not (isinstance(self.max_horizon, int) and self.max_horizon >= 0):
            raise bad("max_horizon", f"expected a horizon >= 0, got {self.max_horizon!r}")

    @classmethod
    def paper(cls, **values: Any) -> "LazyOptions":
        """The paper's loop and counterexamples: the refinements beyond the paper off,
        except the abstraction, segment safety and the (sound) horizon lower bound,
        which both modes share."""
        return cls(counterexample="zeroprefix", generalize=False, slack_weights="uniform", horizon_search="linear",
                   transit=False, guided=False, widen=False, wait_shifts=False, **values)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The option names, in the order of the fields."""
        return tuple(f.name for f in fields(cls))

    def record(self, max_horizon: int, budget: Any) -> dict[str, Any]:
        """The options as the result records them (``max_horizon`` resolved, the budget)."""
        return {
            "counterexample": self.counterexample,
            "segment_safe": self.segment_safe,
            "generalize": self.generalize,
            "minimize": self.minimize,
            "slack_weights": self.slack_weights,
            "cardinality": self.cardinality,
            "max_horizon": max_horizon,
            "lower_bound": self.lower_bound,
            "horizon_search": self.horizon_search,
            "transit": self.transit,
            "guided": self.guided,
            "widen": self.widen,
            "wait_shifts": self.wait_shifts,
            "window_growth": self.window_growth,
            "prove": self.prove,
            "reach_sets": self.reach_sets,
            "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
        }


#: The named configurations of the lazy planner, each a planner of its own name: our
#: loop (``lazy-smt``), the paper's loop and counterexamples with ZEROPREFIX and with the
#: trivial counterexample (the comparison of Section V), our loop with the paper's
#: ZEROPREFIX counterexample (Farkas-shrunk) instead of the default, and our loop with
#: ``horizon_search="minimal"`` (the bench's proved-minimal column).
CONFIGURATIONS: dict[str, LazyOptions] = {
    "lazy-smt": LazyOptions(),
    "lazy-smt-paper": LazyOptions.paper(),
    "lazy-smt-paper-trivial": replace(LazyOptions.paper(), counterexample="trivial"),
    "lazy-smt-zeroprefix": LazyOptions(counterexample="zeroprefix"),
    # our loop, its horizon proved minimal (windows, re-timing, probes; issue 13, item 3)
    "lazy-smt-minimal": LazyOptions(horizon_search="minimal"),
}

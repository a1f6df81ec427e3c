"""The lazy SMT planner's options as one frozen value (Shoukry et al., CDC 2016,
Algorithm 1, and the refinements beyond the paper).

:class:`LazyOptions` is built once (by the CLI, by bench, or by a caller) and passed
to :func:`plansynth.reach.lazy.planner.plan_lazy`, which records it in the result.
:meth:`LazyOptions.paper` is the loop as published; :data:`CONFIGURATIONS` holds the
named configurations that :func:`plansynth.reach.solve` knows as planners
(``lazy-smt-paper`` and the others), as values. Nothing heavy is imported here, so the
CLI can check options before any solver loads.

>>> LazyOptions.paper().counterexample, LazyOptions.paper().horizon_search
('zeroprefix', 'linear')
>>> LazyOptions(counterexample="nosuch")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt: option 'counterexample': unknown value 'nosuch' (known: farkas, zeroprefix, trivial, iis)
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Any

from plansynth.options import check_fields, option

__all__ = [
    "LazyOptions",
    "CONFIGURATIONS",
    "COUNTEREXAMPLES",
    "HORIZON_SEARCHES",
    "EXACT_MODES",
    "SLACK_WEIGHTS",
    "CARDINALITIES",
    "WINDOW_GROWTH",
    "LARGE_WINDOW_GROWTH",
    "LARGE_REGIONS",
    "window_growth_for",
]

#: CON-PLAN's counterexample strategies (``farkas`` is ``trivial`` shrunk by its Farkas
#: certificate; see :mod:`plansynth.reach.lazy.conplan`).
COUNTEREXAMPLES = ("farkas", "zeroprefix", "trivial", "iis")
HORIZON_SEARCHES = ("window", "linear", "minimal")
#: ``exact_segments``: exact segment transitions where a claim is asked (``auto``), always
#: or never (see :mod:`plansynth.reach.lazy.exactmode`).
EXACT_MODES = ("auto", True, False)
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


#: The help lines of the options several planners take (the lazy planner's for a mission,
#: the MILPs' and the baselines' say the same).
MAX_HORIZON_DOC = "largest horizon tried (none: the problem's max_horizon)"
SEGMENT_SAFE_DOC = (
    "keep each segment between samples in one convex region (false: the samples only, the paper's guarantee)"
)
TRANSIT_DOC = "refute plans with impossible transit times between regions before CON-PLAN"
WAIT_SHIFTS_DOC = "robot at rest at its start: counterexamples anchored at the start also hold shifted earlier"

#: ZEROPREFIX's slack objectives (see :mod:`plansynth.reach.lazy.conplan`).
SLACK_WEIGHTS = ("geometric", "uniform")
#: DIS-PLAN's exactly-one encodings (:class:`~plansynth.reach.lazy.displan.DisPlan`).
CARDINALITIES = ("auto", "pairwise", "seqcounter", "ladder", "totalizer", "paths")


@dataclass(frozen=True)
class LazyOptions:
    """How the lazy loop runs; the defaults are plansynth's loop, :meth:`paper` the
    paper's. Each field's help line is what ``plansynth reach solve --help`` lists for
    ``-O KEY=VALUE``; :func:`plansynth.reach.lazy.planner.plan_lazy` reads them.

    ``max_horizon`` (None: the problem's) and ``segment_safe`` are the options every
    planner shares; the others tune the loop.
    """

    max_horizon: int | None = option(None, MAX_HORIZON_DOC, minimum=0)
    counterexample: str = option(
        "farkas",
        "how CON-PLAN explains an infeasible plan (Section V): farkas (one LP "
        "over the whole plan, shrunk by its Farkas certificate), zeroprefix (the "
        "paper's ZEROPREFIX), trivial (the whole plan) or iis (HiGHS's IIS)",
        choices=COUNTEREXAMPLES,
    )
    segment_safe: bool = option(True, SEGMENT_SAFE_DOC)
    generalize: bool = option(
        True, "shrink counterexamples to their Farkas certificate's literals and reuse them at every time shift"
    )
    minimize: bool = option(
        True, "with generalize: also drop every region literal a counterexample does not need (deletion filter)"
    )
    slack_weights: str = option(
        "geometric",
        "zeroprefix's slack LP objective: geometric (violations pushed later) or uniform (the paper's plain sum)",
        choices=SLACK_WEIGHTS,
    )
    cardinality: str = option(
        "auto",
        "DIS-PLAN's exactly-one encoding: auto (pairwise up to 8 regions, paths beyond "
        "200), pairwise, seqcounter, ladder, totalizer or paths",
        choices=CARDINALITIES,
    )
    lower_bound: bool = option(
        True, "start at the horizon lower bound, with time windows per region (false: from horizon 0)"
    )
    horizon_search: str = option(
        "window",
        "window (goal at some step of a growing window), linear (one horizon at a "
        "time, the paper: the horizon found is minimal) or minimal (windows, then "
        "every shorter horizon refuted)",
        choices=HORIZON_SEARCHES,
    )
    window_growth: float | None = option(
        None,
        "window search: each window this fraction longer than its start "
        "(none: 0.25, and 1.0 on abstractions of more than 200 regions)",
        positive=True,
    )
    transit: bool = option(True, TRANSIT_DOC)
    guided: bool = option(True, "make DIS-PLAN's decisions follow an evenly timed route")
    timed_route: bool = option(
        True,
        "window and minimal searches: first check the shortest route timed by an LP and repaired where "
        "CON-PLAN finds it too tight, before DIS-PLAN is built",
    )
    shorten: float = option(
        1.0,
        "window search, abstractions of more than 200 regions: shorten the timed route's plan "
        "(fewer steps per region; steps crossing box regions' faces anywhere, skipping thin "
        "boxes), by LPs, for at most this many times the seconds the plan took to find (at "
        "least 1 s; 0: off)",
        minimum=0,
    )
    widen: bool = option(False, "also widen LP counterexamples in time (more LPs, fewer iterations)")
    wait_shifts: bool = option(True, WAIT_SHIFTS_DOC)
    prove: bool = option(
        False,
        "segment-safe: prove the minimal horizon (or infeasibility) for the problem by a MILP "
        "relaxation of segment safety (small instances; within the budget)",
    )
    reach_sets: bool = option(
        True,
        "horizon_search=minimal: refute shorter horizons by per-axis reachable sets "
        "first, where the dynamics separate by axis",
    )
    exact_segments: bool | str = option(
        "auto",
        "segment-safe: let a step cross several regions (DIS-PLAN also places points along "
        "each segment, more where a segment of a solution cuts an obstacle), so that "
        "infeasible and a minimal horizon hold for the problem: true, false (one region per "
        "step: claims through the decomposition) or auto (exact where a claim is asked: prove, "
        "horizon_search minimal or linear, and after every horizon up to max_horizon is "
        "refuted through the decomposition)",
        choices=EXACT_MODES,
    )

    def __post_init__(self) -> None:
        check_fields(self, "lazy-smt")

    @classmethod
    def paper(cls, **values: Any) -> LazyOptions:
        """The paper's loop and counterexamples: the refinements beyond the paper off,
        except the abstraction, segment safety and the (sound) horizon lower bound,
        which both modes share; one region per step (the paper's abstraction, not exact
        segment transitions), so its claims are through the decomposition."""
        values.setdefault("exact_segments", False)
        return cls(
            counterexample="zeroprefix",
            generalize=False,
            slack_weights="uniform",
            horizon_search="linear",
            transit=False,
            guided=False,
            timed_route=False,
            widen=False,
            wait_shifts=False,
            **values,
        )

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
            "timed_route": self.timed_route,
            "shorten": self.shorten,
            "widen": self.widen,
            "wait_shifts": self.wait_shifts,
            "window_growth": self.window_growth,
            "prove": self.prove,
            "reach_sets": self.reach_sets,
            "exact_segments": self.exact_segments,
            "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
        }


#: The named configurations of the lazy planner, each a planner of its own name: ours
#: (``lazy-smt``: the timed route, then our loop), our loop alone (``lazy-smt-window``:
#: the window search without the timed route), the paper's loop and counterexamples with
#: ZEROPREFIX and with the trivial counterexample (the comparison of Section V), our loop
#: with the paper's ZEROPREFIX counterexample (Farkas-shrunk) instead of the default
#: (a loop too: counterexamples are what it compares), and ours with
#: ``horizon_search="minimal"`` (the bench's proved-minimal column).
CONFIGURATIONS: dict[str, LazyOptions] = {
    "lazy-smt": LazyOptions(),
    "lazy-smt-window": LazyOptions(timed_route=False),
    "lazy-smt-paper": LazyOptions.paper(),
    "lazy-smt-paper-trivial": replace(LazyOptions.paper(), counterexample="trivial"),
    "lazy-smt-zeroprefix": LazyOptions(counterexample="zeroprefix", timed_route=False),
    # our loop, its horizon proved minimal (windows, re-timing, probes) through the
    # decomposition: the bench's minimal column, fast at scale; ``prove`` (``--prove``)
    # asks for the claim about the problem
    "lazy-smt-minimal": LazyOptions(horizon_search="minimal", exact_segments=False),
}

"""The options of the region MILP and the baselines as frozen values (STYLE.md, points 1
and 5), declared with :func:`plansynth.options.option` so that each option has its help
line (``plansynth reach solve --help`` lists them for ``-O KEY=VALUE``) and its checks.

Nothing heavy is imported here: the CLI reads these without loading a solver. The
planners that take them: :mod:`plansynth.reach.planners.milp` (``milp``),
:mod:`~plansynth.reach.planners.milp_bigm` (``milp-bigm``),
:mod:`~plansynth.reach.planners.ompl` (``rrt``, ``est``, ``kpiece``),
:mod:`~plansynth.reach.planners.gcs` (``gcs``) and :mod:`~plansynth.reach.planners.fpp` (``fpp``).

>>> GcsOptions(variant="bogus")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: gcs: option 'variant': unknown value 'bogus' (known: like-for-like, surrogate, convex)
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.errors import InvalidOption
from plansynth.options import check_fields, option
from plansynth.reach.lazy.options import MAX_HORIZON_DOC as _MAX_HORIZON
from plansynth.reach.lazy.options import SEGMENT_SAFE_DOC as _SEGMENT_SAFE

__all__ = [
    "MilpOptions",
    "BigMOptions",
    "OmplOptions",
    "GcsOptions",
    "FppOptions",
    "GCS_VARIANTS",
    "GCS_SETS",
    "BIGM_OBJECTIVES",
]

#: The GCS formulations (see :mod:`plansynth.reach.planners.gcs`).
GCS_VARIANTS = ("like-for-like", "surrogate", "convex")
#: The convex sets GCS plans through (see :mod:`plansynth.reach.planners.gcs`): overlapping
#: ones (auto: boxes for box worlds, IRIS regions for polygons), or the lazy planner's
#: disjoint decomposition.
GCS_SETS = ("auto", "boxes", "iris", "decomposition")
#: The big-M MILP's objectives.
BIGM_OBJECTIVES = ("feasibility", "l1")


@dataclass(frozen=True)
class MilpOptions:
    """The options of the region MILP (see :func:`~plansynth.reach.planners.milp.plan_milp`)."""

    max_horizon: int | None = option(None, _MAX_HORIZON, minimum=0)
    start_horizon: int | None = option(
        None,
        "first horizon tried (none: the region-graph distance; above it, a found horizon is not claimed minimal)",
        minimum=0,
    )
    segment_safe: bool = option(True, _SEGMENT_SAFE)

    def __post_init__(self) -> None:
        check_fields(self, "milp")


@dataclass(frozen=True)
class BigMOptions:
    """The options of the big-M MILP (see :func:`~plansynth.reach.planners.milp_bigm.plan_milp_bigm`)."""

    horizon: int | None = option(
        None,
        "the only horizon tried (none: horizons growing from a lower bound to the problem's max_horizon)",
        minimum=1,
    )
    objective: str = option("feasibility", "feasibility, or l1 (the sum of |u|)", choices=BIGM_OBJECTIVES)
    growth: float = option(1.5, "each horizon tried this factor above the last", minimum=1.0, positive=True)
    segment_safe: bool = option(True, _SEGMENT_SAFE)

    def __post_init__(self) -> None:
        check_fields(self, "milp-bigm")


@dataclass(frozen=True)
class OmplOptions:
    """The options of the OMPL planners (see :func:`~plansynth.reach.planners.ompl.plan_rrt`)."""

    seed: int = option(0, "OMPL's random seed (a run is reproducible up to timing)", minimum=0)
    goal_bias: float | None = option(None, "probability of sampling the goal (none: OMPL's default)", minimum=0.0)
    segment_safe: bool = option(
        True, "reject an edge whose straight segment enters an obstacle (false: the samples only)"
    )

    def __post_init__(self) -> None:
        check_fields(self, "ompl")
        if self.goal_bias is not None and self.goal_bias > 1:
            raise InvalidOption("ompl", "goal_bias", f"a probability is at most 1, got {self.goal_bias}")


@dataclass(frozen=True)
class GcsOptions:
    """The options of the GCS planner (see :func:`~plansynth.reach.planners.gcs.plan_gcs`)."""

    variant: str = option(
        "like-for-like",
        "like-for-like (velocity continuity, |v| and |a| bounds, start at rest), "
        "surrogate (velocity continuity as Drake's convex surrogate) or convex "
        "(continuity of the curve only)",
        choices=GCS_VARIANTS,
    )
    order: int = option(5, "the Bezier curves' order", minimum=1)
    time_unit: float = option(10.0, "seconds per unit of Drake's curve time", positive=True)
    max_rounded_paths: int | None = option(
        None, "paths the rounding tries (none: 5, or 1 beyond 200 regions)", minimum=1
    )
    sets: str = option(
        "auto",
        "the convex sets: auto (maximal free boxes for box obstacles, IRIS regions for polygons; "
        "overlapping), boxes, iris, or decomposition (the lazy planner's disjoint regions)",
        choices=GCS_SETS,
    )
    segment_safe: bool = option(True, "(the whole curve is kept in the regions whatever this says)")
    max_horizon: int | None = option(None, "(GCS has no horizon; taken as every planner's)", minimum=0)

    def __post_init__(self) -> None:
        check_fields(self, "gcs")


@dataclass(frozen=True)
class FppOptions:
    """The options of the FPP planner (see :func:`~plansynth.reach.planners.fpp.plan_fpp`)."""

    derivative: int = option(
        3, "the derivative whose squared L2 norm FPP minimises (its examples: 3, the jerk)", minimum=1
    )
    segment_safe: bool = option(True, "(the whole curve is kept in the boxes whatever this says)")
    max_horizon: int | None = option(None, "(FPP has no horizon; taken as every planner's)", minimum=0)

    def __post_init__(self) -> None:
        check_fields(self, "fpp")

"""The options of the mission planners as frozen values (STYLE.md, points 1 and 5).

:class:`MissionOptions` is what ``lazy-smt`` (and ``lazy-smt-minimal``) take for a
problem with a mission: the lazy loop with DIS-PLAN replaced by the BMC encoding of the
mission (:mod:`plansynth.reach.mission.planner`); :class:`MilpLtlOptions` is what the
MILP baselines ``milp-ltl`` and ``milp-ltl-oneshot`` take
(:mod:`plansynth.reach.mission.milp`). Each field's help line is what ``plansynth reach
solve --help`` lists for ``-O KEY=VALUE``. Nothing heavy is imported here.

How the mission reads a plan is the problem's, not a planner's option: its reading
(segment or sample: ``--reading``, which ``--no-segment-safe`` selects too), the end of
a finite plan (``--end``) and the margins (``--margin``, ``--obstacle-margin``), so that
every planner and the checker read it alike.

>>> MissionOptions().semantics, MilpLtlOptions(one_shot=True).one_shot
('any', True)
>>> MissionOptions(semantics="periodic")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt: option 'semantics': unknown value 'periodic' (known: any, finite, lasso)
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.options import check_fields, option
from plansynth.reach.lazy.options import EXACT_MODES, MAX_HORIZON_DOC, TRANSIT_DOC, WAIT_SHIFTS_DOC

__all__ = ["MissionOptions", "MilpLtlOptions", "SEMANTICS"]

#: The plans a mission planner looks for: ``finite`` (ending at rest, the robot staying at
#: its last state, or free, as the problem's ``end`` says), ``lasso`` (x_L = x_k: it
#: repeats x_k..x_L forever) or ``any`` of the two.
SEMANTICS = ("any", "finite", "lasso")


@dataclass(frozen=True)
class _BoundedMission:
    """The options both mission planners take: the horizons and plans they search."""

    max_horizon: int | None = option(None, MAX_HORIZON_DOC, minimum=0)
    semantics: str = option(
        "any",
        "the plans looked for: any (finite or lasso, finite first), finite (ending as the problem's end says: at rest or free) or lasso",
        choices=SEMANTICS,
    )
    lower_bound: bool = option(
        True, "each region impossible before its earliest step from the displacement-box relaxation"
    )
    horizon_bound: bool = option(True, "start at the product graph's proved lower bound on the horizon (false: from 0)")


@dataclass(frozen=True)
class MissionOptions(_BoundedMission):
    """How the lazy loop plans a mission (see :func:`~plansynth.reach.mission.planner.plan_mission`)."""

    transit: bool = option(True, TRANSIT_DOC)
    wait_shifts: bool = option(True, WAIT_SHIFTS_DOC)
    loop_first: bool = option(
        True,
        "check a lasso's loop alone (any x_k with x_L = x_k) before CON-PLAN sees the "
        "plan: a refuted loop is refuted at every horizon and rotation",
    )
    exact_segments: bool | str = option(
        "auto",
        "segment reading: let a step cross several regions and labels (DIS-PLAN also places "
        "points along each segment, the letters read along them), so that infeasible and a "
        "minimal horizon hold for the problem (convex labels): true, false or auto (after "
        "every horizon is refuted through the decomposition)",
        choices=EXACT_MODES,
    )

    def __post_init__(self) -> None:
        check_fields(self, "lazy-smt")


@dataclass(frozen=True)
class MilpLtlOptions(_BoundedMission):
    """The options of the mission MILP (see :func:`~plansynth.reach.mission.milp.plan_milp_ltl`)."""

    one_shot: bool = option(
        False,
        "one MILP at max_horizon only (Wolff et al.'s fixed horizon: a plan of exactly "
        "that many steps, not the shortest)",
    )

    def __post_init__(self) -> None:
        check_fields(self, "milp-ltl")

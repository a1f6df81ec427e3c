"""The options of the team planners as frozen values, declared with
:func:`plansynth.options.option` (light: the CLI lists them without loading a solver).

``lazy-smt-team`` (:mod:`plansynth.reach.team.lazy`) takes :class:`TeamLazyOptions`,
``milp-team`` (:mod:`plansynth.reach.team.milp`) :class:`TeamMilpOptions`, and
``prioritized`` (:mod:`plansynth.reach.team.prioritized`) :class:`PrioritizedOptions`.

>>> TeamLazyOptions(horizon_search="binary")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt-team: option 'horizon_search': unknown value 'binary' (known: linear, defer)
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.options import check_fields, option

__all__ = [
    "TeamLazyOptions",
    "TeamMilpOptions",
    "PrioritizedOptions",
    "TEAM_SEARCHES",
    "TEAM_OBJECTIVES",
    "TEAM_INCUMBENTS",
]

#: How the joint lazy planner walks the horizons.
TEAM_SEARCHES = ("linear", "defer")
#: Where the joint lazy planner's first incumbent comes from (the option is not called seed:
#: the benchmarks pass a random seed to planners with an option of that name).
TEAM_INCUMBENTS = ("auto", "prioritized", "none")
#: What the joint LPs minimise.
TEAM_OBJECTIVES = ("none", "effort")

_MAX_HORIZON = "largest joint horizon tried (none: the problem's max_horizon)"


@dataclass(frozen=True)
class TeamLazyOptions:
    """The options of the joint lazy SMT planner (see :func:`~plansynth.reach.team.lazy.plan_team_lazy`)."""

    max_horizon: int | None = option(None, _MAX_HORIZON, minimum=0)
    horizon_search: str = option(
        "defer",
        "linear (every horizon refuted before the next: the horizon found is minimal through the encoding) "
        "or defer (a horizon set aside after defer_after refuted plans, tried again when no later one succeeds)",
        choices=TEAM_SEARCHES,
    )
    defer_after: int = option(30, "refuted plans after which horizon_search=defer moves to the next horizon", minimum=1)
    objective: str = option(
        "none", "none (any trajectory) or effort (the sum of |u| over every robot and step)", choices=TEAM_OBJECTIVES
    )
    guided: bool = option(True, "DIS-PLAN's decisions follow each robot's route at constant speed")
    incumbent: str = option(
        "auto",
        "prioritized (a plan of prioritized planning first: an incumbent the search tries the horizons below, "
        "then its own, first), none, or auto (prioritized for teams of 4 robots or more whose robots times "
        "first horizon is at least 100)",
        choices=TEAM_INCUMBENTS,
    )
    transit: bool = option(
        True, "each robot's region sequence first checked by the single-robot transit layer (legs too fast to make)"
    )

    def __post_init__(self) -> None:
        check_fields(self, "lazy-smt-team")


@dataclass(frozen=True)
class TeamMilpOptions:
    """The options of the joint big-M MILP (see :func:`~plansynth.reach.team.milp.plan_team_milp`)."""

    max_horizon: int | None = option(None, _MAX_HORIZON, minimum=0)
    horizon: int | None = option(
        None, "the only horizon tried (none: from the lower bound up to max_horizon)", minimum=0
    )

    def __post_init__(self) -> None:
        check_fields(self, "milp-team")


@dataclass(frozen=True)
class PrioritizedOptions:
    """The options of prioritized planning (see :func:`~plansynth.reach.team.prioritized.plan_prioritized`)."""

    max_horizon: int | None = option(None, _MAX_HORIZON, minimum=0)

    def __post_init__(self) -> None:
        check_fields(self, "prioritized")

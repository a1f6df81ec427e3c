"""The lazy SMT planner (Shoukry et al., CDC 2016, Algorithm 1) and its named
configurations as :class:`~plansynth.reach.planners.Planner` values.

``lazy-smt`` is :func:`plansynth.reach.lazy.planner.plan_lazy` with
:class:`~plansynth.reach.lazy.options.LazyOptions` (every option settable), and for a
problem with an LTL mission :func:`plansynth.reach.mission.planner.plan_mission` with
:class:`~plansynth.reach.mission.options.MissionOptions`: the same lazy loop
(:func:`plansynth.reach.lazy.loop.lazy_loop`) over the mission's BMC encoding.
``lazy-smt-window`` (the window search alone, without the timed route),
``lazy-smt-paper``, ``lazy-smt-paper-trivial``, ``lazy-smt-zeroprefix`` and
``lazy-smt-minimal`` (its horizon proved minimal) are the values of
:data:`~plansynth.reach.lazy.options.CONFIGURATIONS`, of which only the options every
planner shares (``max_horizon``, ``segment_safe``) may be set: the others are what names
them. ``lazy-smt-minimal`` plans missions as ``lazy-smt`` does (a mission's horizons are
tried one at a time, so the one found is minimal through the decomposition anyway);
the others, named by their counterexample strategies, plan none (a mission's CON-PLAN
does not vary them).

This module is light: the planners' code loads on their first solve.

>>> LAZY_SMT_PAPER.configure(counterexample="trivial")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt-paper: option 'counterexample': not an option of this planner (a named configuration: its other options are fixed); its options: max_horizon, segment_safe
>>> LAZY_SMT.configure(mission=True, semantics="lasso").semantics
'lasso'
"""

from __future__ import annotations

from typing import Any

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.reach.lazy.options import CONFIGURATIONS
from plansynth.reach.mission.options import MissionOptions
from plansynth.reach.planners import SHARED_OPTIONS, OptionsPlanner

__all__ = [
    "LAZY_SMT",
    "LAZY_SMT_WINDOW",
    "LAZY_SMT_PAPER",
    "LAZY_SMT_PAPER_TRIVIAL",
    "LAZY_SMT_ZEROPREFIX",
    "LAZY_SMT_MINIMAL",
    "CONFIGURED",
    "run",
]

#: the solvers the lazy planner calls: CaDiCaL (DIS-PLAN) and HiGHS (CON-PLAN)
PACKAGES = ("python-sat", "highspy")
#: the named configurations that plan missions too (see the module docstring)
PLAN_MISSIONS = ("lazy-smt", "lazy-smt-minimal")


def run(problem: Any, budget: Budget, options: Any, progress: Any, abstraction: Any = None) -> Any:
    """Plan ``problem``: its mission with :func:`~plansynth.reach.mission.planner.plan_mission`,
    else :func:`~plansynth.reach.lazy.planner.plan_lazy`."""
    if isinstance(options, MissionOptions):
        if abstraction is not None:
            raise InvalidOption("lazy-smt", "abstraction", "a mission plans over its label-refined regions")
        from plansynth.reach.mission.planner import plan_mission

        return plan_mission(problem, budget, options, progress)
    from plansynth.reach.lazy.planner import plan_lazy

    return plan_lazy(problem, budget, options, progress, abstraction=abstraction)


def _planner(name: str) -> OptionsPlanner:
    return OptionsPlanner(
        name,
        CONFIGURATIONS[name],
        run,
        PACKAGES,
        settable=None if name == "lazy-smt" else SHARED_OPTIONS,
        takes_abstraction=True,
        mission_defaults=MissionOptions() if name in PLAN_MISSIONS else None,
        disturbances="tightened",
    )


LAZY_SMT = _planner("lazy-smt")
LAZY_SMT_WINDOW = _planner("lazy-smt-window")
LAZY_SMT_PAPER = _planner("lazy-smt-paper")
LAZY_SMT_PAPER_TRIVIAL = _planner("lazy-smt-paper-trivial")
LAZY_SMT_ZEROPREFIX = _planner("lazy-smt-zeroprefix")
LAZY_SMT_MINIMAL = _planner("lazy-smt-minimal")
#: every configuration of the lazy planner by name
CONFIGURED = {
    p.name: p
    for p in (LAZY_SMT, LAZY_SMT_WINDOW, LAZY_SMT_PAPER, LAZY_SMT_PAPER_TRIVIAL, LAZY_SMT_ZEROPREFIX, LAZY_SMT_MINIMAL)
}

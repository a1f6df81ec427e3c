"""The lazy SMT planner (Shoukry et al., CDC 2016, Algorithm 1) and its named
configurations as :class:`~plansynth.reach.planners.Planner` values.

``lazy-smt`` is :func:`plansynth.reach.lazy.loop.plan_lazy` with
:class:`~plansynth.reach.lazy.options.LazyOptions` (every option settable);
``lazy-smt-paper``, ``lazy-smt-paper-trivial``, ``lazy-smt-zeroprefix`` and
``lazy-smt-minimal`` (its horizon proved minimal) are the
values of :data:`~plansynth.reach.lazy.options.CONFIGURATIONS`, of which only the
options every planner shares (``max_horizon``, ``segment_safe``) may be set: the
others are what names them.

>>> LAZY_SMT_PAPER.configure(counterexample="trivial")
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: lazy-smt-paper: option 'counterexample': not an option of this planner (a named configuration: its other options are fixed); its options: max_horizon, segment_safe
"""

from __future__ import annotations

from typing import Any

from plansynth.budget import Budget
from plansynth.reach.lazy.options import CONFIGURATIONS, LazyOptions
from plansynth.reach.planners import SHARED_OPTIONS, OptionsPlanner

__all__ = ["LAZY_SMT", "LAZY_SMT_PAPER", "LAZY_SMT_PAPER_TRIVIAL", "LAZY_SMT_ZEROPREFIX", "LAZY_SMT_MINIMAL", "CONFIGURED"]


def _run(problem: Any, budget: Budget, options: LazyOptions, progress: Any, abstraction: Any = None) -> Any:
    from plansynth.reach.lazy.loop import plan_lazy

    return plan_lazy(problem, budget, options, progress=progress, abstraction=abstraction)


def _planner(name: str) -> OptionsPlanner:
    return OptionsPlanner(name, CONFIGURATIONS[name], _run, "python-sat",
                          settable=None if name == "lazy-smt" else SHARED_OPTIONS, takes_abstraction=True)


LAZY_SMT = _planner("lazy-smt")
LAZY_SMT_PAPER = _planner("lazy-smt-paper")
LAZY_SMT_PAPER_TRIVIAL = _planner("lazy-smt-paper-trivial")
LAZY_SMT_ZEROPREFIX = _planner("lazy-smt-zeroprefix")
LAZY_SMT_MINIMAL = _planner("lazy-smt-minimal")
#: every configuration of the lazy planner by name
CONFIGURED = {p.name: p for p in (LAZY_SMT, LAZY_SMT_PAPER, LAZY_SMT_PAPER_TRIVIAL, LAZY_SMT_ZEROPREFIX,
                                  LAZY_SMT_MINIMAL)}

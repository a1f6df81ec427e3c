"""Reach-avoid and mission planners behind one protocol, chosen by name (STYLE.md, point 5).

A :class:`Planner` has a ``name``, a ``version()`` (its solver packages and their
versions), its options (one frozen value per kind of problem it plans: ``defaults`` for
a reach-avoid problem, ``mission_defaults`` for a problem with an LTL mission; None
for a kind it does not plan) and ``solve(problem, budget, options)``, which returns an
*unvalidated* result: :func:`plansynth.reach.solve` is the one place that validates.
:meth:`Planner.configure` builds the options value once from names and values; an
option the planner does not take is an error (:class:`~plansynth.errors.InvalidOption`),
never dropped. The options values are declared with :func:`plansynth.options.option`
in light modules (:mod:`plansynth.reach.lazy.options`,
:mod:`plansynth.reach.mission.options`, :mod:`plansynth.reach.planners.options`), so
listing every planner's options loads no solver.

One registry names every planner (:data:`PLANNERS`). A built-in planner is an
:class:`OptionsPlanner` whose ``run`` is ``"module:function"``, imported on its first
solve, so every name works whatever was imported before, and a planner's libraries load
only when it plans. The planners and their modules:

``lazy-smt`` ...      :mod:`~plansynth.reach.planners.lazy_smt`: the lazy SMT planner
                      (:mod:`plansynth.reach.lazy`) and its named configurations, each a
                      value of its options; with a mission, the same loop over the
                      mission's BMC encoding (:mod:`plansynth.reach.mission`);
``milp``              the region MILP, one per horizon (the cross-check oracle);
``milp-bigm``         the one-shot big-M MILP over the obstacles (LTL OPT stand-in);
``rrt``, ``est``, ``kpiece``  OMPL's kinodynamic planners;
``gcs``               Drake's Graphs of Convex Sets (``gcs-decomposition``: over our regions);
``fpp``               fast path planning through safe boxes (``fastpathplanning``);
``milp-ltl``, ``milp-ltl-oneshot``  the mission MILP baseline
                      (:mod:`plansynth.reach.mission.milp`);
``lazy-smt-team``, ``milp-team``, ``prioritized``  teams of robots
                      (:mod:`~plansynth.reach.planners.team`, :mod:`plansynth.reach.team`).
``nominal-check``     under a disturbance, the nominal plan followed by the robust
                      check (:mod:`plansynth.reach.robust.baseline`).

Under a disturbance (``robot.disturbance``) :func:`plansynth.reach.solve` hands a
planner the problem tightened by the feedback's tube (:mod:`plansynth.reach.robust`);
the planners that plan it say so (``disturbances``, :func:`robust_planners`), the others
refuse the problem. A team whose robots carry disturbances is planned tightened by
``lazy-smt-team`` and ``milp-team`` (:mod:`plansynth.reach.team.robust`); ``prioritized``
refuses it.

The baselines' entries are in :mod:`~plansynth.reach.planners.baselines`. Plugins
register with :func:`register_planner` (a :class:`Planner`, or a plain function
``f(problem, budget, **options)``). There is no fallback from one planner to another:
an unknown name is an error (:class:`~plansynth.errors.UnknownSolver`, listing the
names).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any, Protocol

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.options import changed
from plansynth.options import configure as configure_value
from plansynth.registry import Registry, package_version

__all__ = [
    "Planner",
    "OptionsPlanner",
    "planners",
    "robust_planners",
    "get_planner",
    "register_planner",
    "package_version",
    "SHARED_OPTIONS",
    "mission_planners",
]

#: The options every built-in planner takes (the lazy planner's named configurations
#: take only these: their other options are what names them).
SHARED_OPTIONS = ("max_horizon", "segment_safe")

ProgressFn = Callable[[int, int], None]  # (horizon, iterations so far)


class Planner(Protocol):
    """A planner: problem, budget and options in, unvalidated result out."""

    name: str
    defaults: Any  # the options value for a reach-avoid problem (a frozen dataclass; None: missions only)
    mission_defaults: Any  # ... for a problem with an LTL mission (None: it plans none)

    def version(self) -> str:
        """The planner's solvers and their versions, e.g. ``"highspy 1.16.0"``."""
        ...

    def option_names(self, *, mission: bool | None = None) -> tuple[str, ...]:
        """The options :meth:`configure` may set, for a problem with a mission or not."""
        ...

    def configure(self, base: Any = None, *, mission: bool | None = None, **values: Any) -> Any:
        """The options value: ``base`` (default: the defaults of the kind of problem,
        ``mission`` or not) with ``values`` set."""
        ...

    def solve(
        self,
        problem: Any,
        budget: Budget,
        options: Any = None,
        *,
        progress: ProgressFn | None = None,
        abstraction: Any = None,
    ) -> Any:
        """Plan ``problem`` within ``budget`` (a ``ReachResult``, not yet validated);
        ``abstraction``: a decomposition computed before (an input, not an option)."""
        ...


_RUNS: dict[str, Callable[..., Any]] = {}


def _load(run: Callable[..., Any] | str) -> Callable[..., Any]:
    """``run`` itself, or the function ``"module:function"`` names (imported once)."""
    if not isinstance(run, str):
        return run
    if run not in _RUNS:
        module, _, attribute = run.partition(":")
        _RUNS[run] = getattr(importlib.import_module(module), attribute)
    return _RUNS[run]


@dataclass(frozen=True)
class OptionsPlanner:
    """A :class:`Planner` given by its options values and a function that plans.

    ``run(problem, budget, options, progress, **inputs)`` plans (a function, or
    ``"module:function"``, imported on the first solve) and reads what it needs from the
    frozen ``options``; ``settable`` names the options :meth:`configure` may set (None:
    every field); ``packages`` are the distributions whose versions are the planner's.
    """

    name: str
    defaults: Any
    run: Callable[..., Any] | str
    packages: tuple[str, ...]
    settable: tuple[str, ...] | None = None
    takes_abstraction: bool = False  # ``run`` takes ``abstraction=`` (the planners over the decomposition)
    mission_defaults: Any = None
    # how it plans a problem with a disturbance (plansynth.reach.robust): "tightened" (the
    # tightened problem, the tube's step-wise margins of ``problem.tube`` applied to its
    # bounds), "nominal" (the problem without it: the robust check alone decides), or ""
    # (it does not)
    disturbances: str = ""

    def version(self) -> str:
        return ", ".join(package_version(p) for p in self.packages)

    def _mission(self, mission: bool | None, base: Any = None) -> bool:
        """Which options: a mission's (``mission``; else the kind of ``base``; else the
        only kind this planner plans, reach-avoid first)."""
        if mission is not None:
            return mission
        if base is not None and self.mission_defaults is not None:
            return type(base) is type(self.mission_defaults)
        return self.defaults is None

    def defaults_for(self, mission: bool) -> Any:
        """The default options for a problem with a mission (``mission``) or without;
        a kind this planner does not plan is :class:`~plansynth.errors.InvalidOption`."""
        value = self.mission_defaults if mission else self.defaults
        if value is None:
            why = (
                f"does not plan LTL missions (mission planners: {', '.join(mission_planners())})"
                if mission
                else "plans LTL missions, and this problem has none (plan it with a reach-avoid planner)"
            )
            raise InvalidOption(self.name, "planner", why)
        return value

    def option_names(self, *, mission: bool | None = None) -> tuple[str, ...]:
        names = tuple(f.name for f in fields(self.defaults_for(self._mission(mission))))
        return names if self.settable is None else tuple(n for n in names if n in self.settable)

    def configure(self, base: Any = None, *, mission: bool | None = None, **values: Any) -> Any:
        mission = self._mission(mission, base)
        default = self.defaults_for(mission)
        if base is None:
            base = default
        elif type(base) is not type(default):
            other = self.mission_defaults if not mission else self.defaults
            if other is None or type(base) is not type(other):
                raise InvalidOption(
                    self.name, "options", f"expected {type(default).__name__}, got {type(base).__name__}"
                )
            # the options of the other kind of problem (lazy-smt's reach-avoid options
            # for a problem with a mission): those set away from their defaults carry over
            values = {**changed(base, other), **values}
            base = default
        allowed = self.option_names(mission=mission)
        for key in values:
            if key not in allowed:
                where = " for a problem with a mission" if mission and self.defaults is not None else ""
                fixed = (
                    " (a named configuration: its other options are fixed)"
                    if self.settable is not None and key in {f.name for f in fields(base)}
                    else ""
                )
                raise InvalidOption(
                    self.name,
                    key,
                    f"not an option of this planner{where}{fixed}; its options: {', '.join(allowed) or 'none'}",
                )
        return configure_value(self.name, base, values)

    def solve(
        self,
        problem: Any,
        budget: Budget = Budget(),
        options: Any = None,
        *,
        progress: ProgressFn | None = None,
        abstraction: Any = None,
    ) -> Any:
        opts = self.configure(options, mission=getattr(problem, "mission", None) is not None)
        run = _load(self.run)
        if abstraction is None:
            return run(problem, budget, opts, progress)
        if not self.takes_abstraction:
            raise InvalidOption(self.name, "abstraction", "this planner makes no use of a decomposition")
        return run(problem, budget, opts, progress, abstraction=abstraction)

    def __call__(self, problem: Any, budget: Budget = Budget(), **values: Any) -> Any:
        """``planner(problem, budget, **options)``: :meth:`configure` then :meth:`solve`
        (unvalidated, as :meth:`solve`)."""
        progress = values.pop("progress", None)
        abstraction = values.pop("abstraction", None)
        opts = self.configure(mission=getattr(problem, "mission", None) is not None, **values)
        return self.solve(problem, budget, opts, progress=progress, abstraction=abstraction)


#: Every planner :func:`plansynth.reach.solve` knows, in the order :func:`planners`
#: lists them (:mod:`plansynth.registry`): a name maps to ``"module:attribute"`` (loaded
#: on first use) or to a planner itself. A new built-in planner is one line here;
#: plugins use :func:`register_planner`. The baselines' libraries (OMPL, Drake) come
#: with the ``baselines`` extra.
PLANNERS: Registry[Planner | Callable[..., Any]] = Registry(
    "planner",
    {
        "lazy-smt": "plansynth.reach.planners.lazy_smt:LAZY_SMT",
        "lazy-smt-window": "plansynth.reach.planners.lazy_smt:LAZY_SMT_WINDOW",  # without the timed route
        "milp": "plansynth.reach.planners.baselines:MILP",
        "lazy-smt-paper": "plansynth.reach.planners.lazy_smt:LAZY_SMT_PAPER",
        "lazy-smt-paper-trivial": "plansynth.reach.planners.lazy_smt:LAZY_SMT_PAPER_TRIVIAL",
        "lazy-smt-zeroprefix": "plansynth.reach.planners.lazy_smt:LAZY_SMT_ZEROPREFIX",
        "lazy-smt-minimal": "plansynth.reach.planners.lazy_smt:LAZY_SMT_MINIMAL",  # horizon proved minimal
        "milp-bigm": "plansynth.reach.planners.baselines:MILP_BIGM",
        "rrt": "plansynth.reach.planners.baselines:RRT",
        "est": "plansynth.reach.planners.baselines:EST",
        "kpiece": "plansynth.reach.planners.baselines:KPIECE",
        "gcs": "plansynth.reach.planners.baselines:GCS",  # Drake's Graphs of Convex Sets
        "gcs-decomposition": "plansynth.reach.planners.baselines:GCS_DECOMPOSITION",  # over our regions
        "fpp": "plansynth.reach.planners.baselines:FPP",  # fast path planning through safe boxes
        "milp-ltl": "plansynth.reach.planners.baselines:MILP_LTL",  # LTL missions: one big-M MILP per horizon
        "milp-ltl-oneshot": "plansynth.reach.planners.baselines:MILP_LTL_ONESHOT",  # one MILP at the max horizon
        "lazy-smt-team": "plansynth.reach.planners.team:LAZY_SMT_TEAM",  # teams: the joint lazy SMT planner
        "milp-team": "plansynth.reach.planners.team:MILP_TEAM",  # teams: the joint big-M MILP
        "prioritized": "plansynth.reach.planners.team:PRIORITIZED",  # teams: one robot after the other
        # under disturbances: the nominal plan, then the robust check (plansynth.reach.robust.baseline)
        "nominal-check": "plansynth.reach.planners.baselines:NOMINAL_CHECK",
    },
    extras={name: "baselines" for name in ("rrt", "est", "kpiece", "gcs", "gcs-decomposition", "fpp")},
)


def register_planner(name: str, planner: Planner | Callable[..., Any], *, replace_existing: bool = False) -> None:
    """Make ``planner`` available to :func:`plansynth.reach.solve` as ``name``."""
    PLANNERS.register(name, planner, replace_existing=replace_existing)


def planners() -> tuple[str, ...]:
    """The names :func:`plansynth.reach.solve` accepts (nothing is imported to list them).

    >>> planners()
    ('lazy-smt', 'lazy-smt-window', 'milp', 'lazy-smt-paper', 'lazy-smt-paper-trivial', 'lazy-smt-zeroprefix', 'lazy-smt-minimal', 'milp-bigm', 'rrt', 'est', 'kpiece', 'gcs', 'gcs-decomposition', 'fpp', 'milp-ltl', 'milp-ltl-oneshot', 'lazy-smt-team', 'milp-team', 'prioritized', 'nominal-check')
    """
    return PLANNERS.names()


def mission_planners() -> tuple[str, ...]:
    """The names of the planners that plan LTL missions (loads every planner's entry;
    the built-in ones are light).

    >>> mission_planners()
    ('lazy-smt', 'lazy-smt-minimal', 'milp-ltl', 'milp-ltl-oneshot')
    """
    return tuple(n for n in planners() if getattr(get_planner(n), "mission_defaults", None) is not None)


def robust_planners() -> tuple[str, ...]:
    """The names of the planners that plan under disturbances (a problem's
    ``robot.disturbance``; loads every planner's entry, the built-in ones are light).

    >>> robust_planners()
    ('lazy-smt', 'lazy-smt-window', 'milp', 'lazy-smt-paper', 'lazy-smt-paper-trivial', 'lazy-smt-zeroprefix', 'lazy-smt-minimal', 'milp-bigm', 'milp-ltl', 'milp-ltl-oneshot', 'nominal-check')
    """
    return tuple(n for n in planners() if getattr(get_planner(n), "disturbances", ""))


def get_planner(name: str) -> Planner | Callable[..., Any]:
    """The planner called ``name``, importing its module on first use.

    An unknown name raises :class:`~plansynth.errors.UnknownSolver` (a ``ValueError``
    and a ``SolverUnavailable``) that lists every known name; a baseline whose library
    is not installed raises :class:`~plansynth.errors.SolverUnavailable` naming the extra.

    >>> get_planner("milp").name, get_planner("milp").version().split()[0]
    ('milp', 'highspy')
    >>> get_planner("rrtx")
    Traceback (most recent call last):
    ...
    plansynth.errors.UnknownSolver: solver 'rrtx' is unavailable: unknown planner; choose one of: lazy-smt, lazy-smt-window, milp, lazy-smt-paper, lazy-smt-paper-trivial, lazy-smt-zeroprefix, lazy-smt-minimal, milp-bigm, rrt, est, kpiece, gcs, gcs-decomposition, fpp, milp-ltl, milp-ltl-oneshot, lazy-smt-team, milp-team, prioritized, nominal-check
    """
    return PLANNERS.get(name)

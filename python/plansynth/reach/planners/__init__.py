"""Reach-avoid planners behind one protocol, chosen by name (STYLE.md, point 5).

A :class:`Planner` has a ``name``, a ``version()``, its default options (one frozen
value: :class:`~plansynth.reach.lazy.options.LazyOptions` for the lazy SMT planner,
a small dataclass beside each baseline) and ``solve(problem, budget, options)``, which
returns an *unvalidated* result: :func:`plansynth.reach.solve` is the one place that
validates. :meth:`Planner.configure` builds the options value once from names and
values; an option the planner does not take is an error
(:class:`~plansynth.errors.InvalidOption`), never dropped.

One registry names every planner (:data:`PLANNERS`); each entry is ``"module:attribute"``,
imported on first use (:func:`get_planner`), so every name works whatever was imported
before, and a planner's libraries load only when it is asked for. Modules:

``lazy_smt``   the lazy SMT planner (:mod:`plansynth.reach.lazy`) and its named
               configurations (``lazy-smt-paper`` ...), each a value of its options;
``milp``       the region MILP, one per horizon (the cross-check oracle);
``milp_bigm``  the one-shot big-M MILP over the obstacles (LTL OPT stand-in);
``ompl``       OMPL's kinodynamic RRT, EST and KPIECE;
``gcs``        Drake's Graphs of Convex Sets.

The LTL mission baseline ``milp-ltl`` lives with the missions
(:mod:`plansynth.reach.mission.milp`). Plugins register with :func:`register_planner`
(a :class:`Planner`, or a plain function ``f(problem, budget, **options)``). There is
no fallback from one planner to another: an unknown name is an error
(:class:`~plansynth.errors.UnknownSolver`, listing the names).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields, is_dataclass, replace
from typing import Any, Protocol

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.registry import Registry, package_version

__all__ = ["Planner", "OptionsPlanner", "planners", "get_planner", "register_planner", "package_version",
           "SHARED_OPTIONS"]

#: The options every built-in planner takes (the lazy planner's named configurations
#: take only these: their other options are what names them).
SHARED_OPTIONS = ("max_horizon", "segment_safe")

ProgressFn = Callable[[int, int], None]  # (horizon, iterations so far)


class Planner(Protocol):
    """A reach-avoid planner: problem, budget and options in, unvalidated result out."""

    name: str
    defaults: Any  # the default options value (a frozen dataclass)

    def version(self) -> str:
        """The planner's solver and its version, e.g. ``"highspy 1.16.0"``."""
        ...

    def configure(self, base: Any = None, **values: Any) -> Any:
        """The options value: ``base`` (default :attr:`defaults`) with ``values`` set."""
        ...

    def solve(self, problem: Any, budget: Budget, options: Any = None, *,
              progress: ProgressFn | None = None, abstraction: Any = None) -> Any:
        """Plan ``problem`` within ``budget`` (a ``ReachResult``, not yet validated);
        ``abstraction``: a decomposition computed before (an input, not an option)."""
        ...


@dataclass(frozen=True)
class OptionsPlanner:
    """A :class:`Planner` given by a function and the dataclass of its options.

    ``run(problem, budget, options, progress)`` plans; ``settable`` names the options
    :meth:`configure` may set (None: every field of ``defaults``); ``package`` is the
    distribution whose version is the planner's.
    """

    name: str
    defaults: Any
    run: Callable[..., Any]
    package: str
    settable: tuple[str, ...] | None = None
    takes_abstraction: bool = False  # ``run`` takes ``abstraction=`` (the planners over the decomposition)

    def version(self) -> str:
        return package_version(self.package)

    def option_names(self) -> tuple[str, ...]:
        names = tuple(f.name for f in fields(self.defaults))
        return names if self.settable is None else tuple(n for n in names if n in self.settable)

    def configure(self, base: Any = None, **values: Any) -> Any:
        opts = self.defaults if base is None else base
        if type(opts) is not type(self.defaults):
            raise InvalidOption(self.name, "options", f"expected {type(self.defaults).__name__}, got {type(opts).__name__}")
        allowed = self.option_names()
        for key in values:
            if key not in allowed:
                fixed = " (a named configuration: its other options are fixed)" if self.settable is not None else ""
                raise InvalidOption(self.name, key, f"not an option of this planner{fixed}; "
                                                    f"its options: {', '.join(allowed) or 'none'}")
        return replace(opts, **values) if values else opts

    def solve(self, problem: Any, budget: Budget = Budget(), options: Any = None, *,
              progress: ProgressFn | None = None, abstraction: Any = None) -> Any:
        if abstraction is None:
            return self.run(problem, budget, self.configure(options), progress)
        if not self.takes_abstraction:
            raise InvalidOption(self.name, "abstraction", "this planner makes no use of a decomposition")
        return self.run(problem, budget, self.configure(options), progress, abstraction=abstraction)

    def __call__(self, problem: Any, budget: Budget = Budget(), **values: Any) -> Any:
        """``planner(problem, budget, **options)``: :meth:`configure` then :meth:`solve`."""
        progress = values.pop("progress", None)
        abstraction = values.pop("abstraction", None)
        return self.solve(problem, budget, self.configure(**values), progress=progress, abstraction=abstraction)


def keyword_runner(function: Callable[..., Any], *, progress: bool) -> Callable[..., Any]:
    """A ``run`` for :class:`OptionsPlanner` that calls ``function(problem, budget,
    **fields of the options)`` (and ``progress=`` when the function takes it)."""

    def run(problem: Any, budget: Budget, options: Any, on_progress: ProgressFn | None, **inputs: Any) -> Any:
        kwargs = {f.name: getattr(options, f.name) for f in fields(options)} if is_dataclass(options) else {}
        if progress:
            kwargs["progress"] = on_progress
        return function(problem, budget, **kwargs, **inputs)

    run.__name__ = function.__name__
    return run


#: Every planner :func:`plansynth.reach.solve` knows, in the order :func:`planners`
#: lists them (:mod:`plansynth.registry`): a name maps to ``"module:attribute"`` (loaded
#: on first use) or to a planner itself. A new built-in planner is one line here;
#: plugins use :func:`register_planner`. The baselines' libraries (OMPL, Drake) come
#: with the ``baselines`` extra.
PLANNERS: Registry[Planner | Callable[..., Any]] = Registry("planner", {
    "lazy-smt": "plansynth.reach.planners.lazy_smt:LAZY_SMT",
    "milp": "plansynth.reach.planners.milp:MILP",
    "lazy-smt-paper": "plansynth.reach.planners.lazy_smt:LAZY_SMT_PAPER",
    "lazy-smt-paper-trivial": "plansynth.reach.planners.lazy_smt:LAZY_SMT_PAPER_TRIVIAL",
    "lazy-smt-zeroprefix": "plansynth.reach.planners.lazy_smt:LAZY_SMT_ZEROPREFIX",
    "lazy-smt-minimal": "plansynth.reach.planners.lazy_smt:LAZY_SMT_MINIMAL",  # horizon proved minimal
    "milp-bigm": "plansynth.reach.planners.milp_bigm:MILP_BIGM",
    "rrt": "plansynth.reach.planners.ompl:RRT",
    "est": "plansynth.reach.planners.ompl:EST",
    "kpiece": "plansynth.reach.planners.ompl:KPIECE",
    "gcs": "plansynth.reach.planners.gcs:GCS",  # Drake's Graphs of Convex Sets
    "milp-ltl": "plansynth.reach.mission.milp:MILP_LTL",  # LTL missions: one big-M MILP per horizon
    "milp-ltl-oneshot": "plansynth.reach.mission.milp:MILP_LTL_ONESHOT",  # one MILP at the max horizon
}, extras={name: "baselines" for name in ("rrt", "est", "kpiece", "gcs")})


def register_planner(name: str, planner: Planner | Callable[..., Any], *, replace_existing: bool = False) -> None:
    """Make ``planner`` available to :func:`plansynth.reach.solve` as ``name``."""
    PLANNERS.register(name, planner, replace_existing=replace_existing)


def planners() -> tuple[str, ...]:
    """The names :func:`plansynth.reach.solve` accepts (nothing is imported to list them).

    >>> planners()
    ('lazy-smt', 'milp', 'lazy-smt-paper', 'lazy-smt-paper-trivial', 'lazy-smt-zeroprefix', 'lazy-smt-minimal', 'milp-bigm', 'rrt', 'est', 'kpiece', 'gcs', 'milp-ltl', 'milp-ltl-oneshot')
    """
    return PLANNERS.names()


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
    plansynth.errors.UnknownSolver: solver 'rrtx' is unavailable: unknown planner; choose one of: lazy-smt, milp, lazy-smt-paper, lazy-smt-paper-trivial, lazy-smt-zeroprefix, lazy-smt-minimal, milp-bigm, rrt, est, kpiece, gcs, milp-ltl, milp-ltl-oneshot
    """
    return PLANNERS.get(name)

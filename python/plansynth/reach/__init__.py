"""Reach-avoid planning with linear dynamics (Shoukry et al., "Scalable Motion
Planning Using Lazy SMT-Based Solving", CDC 2016).

>>> from plansynth.reach import load, solve
>>> r = solve(load("examples/reach/maze-1.yaml"))
>>> r.status.value, r.horizon, r.validated
('found', 58, True)

The same kinds of names as :mod:`plansynth.grid`:

* problems: :class:`ReachProblem` (:func:`load`, spec reach-problem.md);
* the abstraction: :func:`abstract` (Section III);
* planners: :func:`solve` with a planner chosen by name (:func:`planners`):
  ``"lazy-smt"`` (Algorithm 1: DIS-PLAN over SAT, CON-PLAN over LP; its options one
  :class:`LazyOptions` value), ``"milp"`` (one MILP per horizon, the cross-check oracle)
  and the baselines; :func:`configure` builds a planner's options value;
* answers: :class:`ReachResult` with :class:`ReachStatus` (``write()`` writes the
  spec's result JSON), every trajectory checked by the independent :func:`validate`.

``plansynth.reach.solve`` is the function here; the module of that name is
:mod:`plansynth.reach.solve` for ``from plansynth.reach.solve import ...`` (so with
``validate`` and ``planners``).

Nothing is imported until a name is used (PEP 562): ``import plansynth.reach``, or
importing one of its modules (the CLI's option parsing, say), loads neither numpy,
shapely, python-sat nor highspy; ``from plansynth.reach import solve`` loads what
solving needs.
"""

import sys
import types
from importlib import import_module
from typing import Any

#: Each public name and the module that defines it (imported on first use).
_DEFINED_IN = {
    "Abstraction": "plansynth.reach.abstraction",
    "Region": "plansynth.reach.abstraction",
    "abstract": "plansynth.reach.abstraction",
    "maze": "plansynth.reach.families",
    "random_workspace": "plansynth.reach.families",
    "TheoryChecker": "plansynth.reach.lazy.loop",
    "plan_lazy": "plansynth.reach.lazy.loop",
    "LazyOptions": "plansynth.reach.lazy.options",
    "plan_milp": "plansynth.reach.planners.milp",
    "LinearDynamics": "plansynth.reach.dynamics",
    "load_reach_problem": "plansynth.reach.fileformat",
    "Box": "plansynth.reach.geometry",
    "Polygon": "plansynth.reach.geometry",
    "ReachProblem": "plansynth.reach.problem",
    "ReachResult": "plansynth.reach.result",
    "ReachStatus": "plansynth.reach.result",
    "Planner": "plansynth.reach.solve",
    "configure": "plansynth.reach.solve",
    "get_planner": "plansynth.reach.solve",
    "planners": "plansynth.reach.solve",
    "register_planner": "plansynth.reach.solve",
    "solve": "plansynth.reach.solve",
    "Trajectory": "plansynth.reach.trajectory",
    "load_trajectory": "plansynth.reach.trajectory",
    "ValidationReport": "plansynth.reach.validate",
    "validate": "plansynth.reach.validate",
}
#: Other names for a public name.
_ALIASES = {"load": "load_reach_problem"}

__all__ = sorted([*_DEFINED_IN, *_ALIASES])


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first use and kept here."""
    target = _ALIASES.get(name, name)
    if target not in _DEFINED_IN:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(_DEFINED_IN[target]), target)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})


class _Package(types.ModuleType):
    """This package, whose functions ``solve``, ``validate`` and ``planners`` share their
    names with modules of the package: importing such a module binds it as an attribute
    here (the import system does), which must not hide the function of that name."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _DEFINED_IN and isinstance(value, types.ModuleType) and value.__name__ == f"{__name__}.{name}":
            return  # the function keeps the name; __getattr__ loads it on first use
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

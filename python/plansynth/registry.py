"""Solvers chosen by name, loaded on first use (STYLE.md, point 5).

One :class:`Registry` holds the grid backends (:mod:`plansynth.grid.result`) and one the
reach planners (:mod:`plansynth.reach.planners`). A built-in entry is a
``"module:attribute"`` string, imported only when that name is asked for, so listing
the names loads nothing and a solver's libraries load only with it; plugins register an
object directly. There is no fallback from one name to another: an unknown name is
:class:`~plansynth.errors.UnknownSolver` (listing the names), a built-in whose library is
missing is :class:`~plansynth.errors.SolverUnavailable` naming what to install.

>>> r = Registry("widget", {"json": "json:dumps"}, extras={"json": "the standard library"})
>>> r.names()
('json',)
>>> r.get("json")([1])
'[1]'
>>> r.register("mine", len)
>>> r.names(), r.get("mine") is len
(('json', 'mine'), True)
>>> r.get("nosuch")
Traceback (most recent call last):
...
plansynth.errors.UnknownSolver: solver 'nosuch' is unavailable: unknown widget; choose one of: json, mine
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Generic, TypeVar

from plansynth.errors import SolverUnavailable, UnknownSolver

__all__ = ["Registry", "distribution_version", "extra_remedy", "package_version"]

T = TypeVar("T")


class Registry(Generic[T]):
    """Names to solvers of one kind, in the order they were added.

    ``builtins`` maps a name to ``"module:attribute"`` (loaded on first :meth:`get`) or
    to the object itself. ``extras`` maps a name to the optional dependency group that
    provides its libraries (``"baselines"``): when its module cannot be imported, the
    :class:`~plansynth.errors.SolverUnavailable` says ``pip install plansynth[extra]``.
    """

    def __init__(
        self, kind: str, builtins: Mapping[str, str | T] = (), *, extras: Mapping[str, str] | None = None
    ) -> None:
        self.kind = kind
        self._entries: dict[str, str | T] = dict(builtins)
        self._extras = dict(extras or {})

    def names(self) -> tuple[str, ...]:
        """Every name :meth:`get` accepts, in order (nothing is imported)."""
        return tuple(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def register(self, name: str, solver: T, *, replace_existing: bool = False) -> None:
        """Make ``solver`` available as ``name``; a name already taken is a
        ``ValueError`` unless ``replace_existing``."""
        if name in self._entries and not replace_existing:
            raise ValueError(f"a {self.kind} named {name!r} is already registered")
        self._entries[name] = solver

    def unregister(self, name: str) -> None:
        """Forget ``name`` (a plugin, or a test's stand-in)."""
        self._entries.pop(name, None)

    def get(self, name: str) -> T:
        """The solver called ``name``, importing its module on first use."""
        entry = self._entries.get(name)
        if entry is None:
            raise UnknownSolver(self.kind, name, self.names())
        if isinstance(entry, str):
            module, _, attribute = entry.partition(":")
            try:
                entry = getattr(importlib.import_module(module), attribute)
            except ModuleNotFoundError as exc:  # the solver exists, a library it needs does not
                raise SolverUnavailable(name, self._remedy(name, exc.name)) from exc
            self._entries[name] = entry
        return entry  # type: ignore[return-value]

    def _remedy(self, name: str, module: str | None) -> str:
        extra = self._extras.get(name)
        if extra is not None:
            return (
                f"it needs the Python module {module!r}, which comes with plansynth's {extra!r} extra: "
                f"pip install 'plansynth[{extra}]'"
            )
        return f"it needs the Python module {module!r}; install it"

    def extra(self, name: str) -> str | None:
        """The optional dependency group ``name`` needs, if any."""
        return self._extras.get(name)


def extra_remedy(module: str | None, extra: str) -> str:
    """What to install when ``module`` of the optional dependency group ``extra`` is missing.

    >>> extra_remedy("pydrake", "baselines")
    "it needs the Python module 'pydrake', which comes with plansynth's 'baselines' extra: pip install 'plansynth[baselines]'"
    """
    return (
        f"it needs the Python module {module!r}, which comes with plansynth's {extra!r} extra: "
        f"pip install 'plansynth[{extra}]'"
    )


def distribution_version(package: str) -> str | None:
    """The installed version of the distribution ``package``, or None.

    Read from the name of its ``.dist-info`` folder on ``sys.path`` (the standard's
    ``{name}-{version}.dist-info``, the name normalised with underscores), which costs a
    few directory reads; :mod:`importlib.metadata` (tens of milliseconds to import) is
    the fallback for other layouts. Every solve records its solvers' versions, so this
    is on the start-up path of every command.

    >>> distribution_version("plansynth") is not None, distribution_version("plansynth-no-such-package")
    (True, None)
    """
    import os
    import re
    import sys

    wanted = re.sub(r"[-_.]+", "_", package).lower()
    for folder in sys.path:
        try:
            names = os.listdir(folder or ".")
        except OSError:
            continue
        for name in names:
            if name.endswith(".dist-info"):
                dist, _, version = name[: -len(".dist-info")].partition("-")
                if version and re.sub(r"[-_.]+", "_", dist).lower() == wanted:
                    return version
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(package)
    except PackageNotFoundError:
        return None


def package_version(package: str) -> str:
    """``"package version"``, or the package name alone when it is not installed.

    >>> package_version("plansynth-no-such-package")
    'plansynth-no-such-package'
    """
    found = distribution_version(package)
    return package if found is None else f"{package} {found}"

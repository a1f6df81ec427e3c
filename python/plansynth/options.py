"""Solver options as one frozen value, set by name (STYLE.md, points 1, 2 and 5).

Every backend and planner keeps its options in one frozen dataclass whose fields are
declared with :func:`option`: a default and one line saying what it does. Everything
else follows from those fields, the same way for every solver:

* :func:`parse_assignments` reads the CLI's ``-O KEY=VALUE`` (``true``/``false``,
  ``none``, numbers, else text; dashes in keys are underscores);
* :func:`configure` sets values on a base value: an option the solver does not take is
  :class:`~plansynth.errors.InvalidOption` naming the options it does take, never dropped;
* :func:`check_fields` (called by each value's ``__post_init__``) checks every field
  against its annotation, its ``choices`` and its ``minimum``;
* :func:`describe` lists name, default and help for ``--help`` and the reference docs.

>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Opts:
...     depth: int = option(3, "deepest tree tried", minimum=1)
...     mode: str = option("fast", "how hard to try", choices=("fast", "slow"))
...     def __post_init__(self) -> None:
...         check_fields(self, "demo")
>>> configure("demo", Opts(), parse_assignments(["depth=5", "mode=slow"]))
Opts(depth=5, mode='slow')
>>> configure("demo", Opts(), {"dept": 5})
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: demo: option 'dept': not an option of this solver; its options: depth, mode
>>> Opts(depth=0)
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: demo: option 'depth': 0 is below its minimum 1
>>> [(name, default) for name, default, _ in describe(Opts)]
[('depth', 3), ('mode', 'fast')]
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping
from typing import Any, TypeVar

from plansynth.errors import InvalidOption

__all__ = [
    "option",
    "parse_assignments",
    "parse_value",
    "configure",
    "check_fields",
    "describe",
    "help_lines",
    "changed",
]

T = TypeVar("T")

#: Words read as booleans and as None in ``KEY=VALUE``.
TRUE, FALSE, NONE = ("true", "yes", "on"), ("false", "no", "off"), ("none", "null")


def option(
    default: Any,
    doc: str,
    *,
    choices: Iterable[Any] | None = None,
    minimum: float | None = None,
    positive: bool = False,
) -> Any:
    """A dataclass field with its help line and the checks :func:`check_fields` makes.

    ``choices``: the values allowed; ``minimum``: the smallest value allowed;
    ``positive``: the value must be > 0 (and finite).
    """
    meta = {
        "doc": doc,
        "choices": None if choices is None else tuple(choices),
        "minimum": minimum,
        "positive": positive,
    }
    if isinstance(default, (list, dict, set)):
        raise TypeError("an option's default must be immutable")
    return dataclasses.field(default=default, metadata=meta)


def parse_value(text: str) -> Any:
    """The value ``KEY=VALUE`` means: a boolean, None, an int, a float, or the text.

    >>> [parse_value(v) for v in ("true", "Off", "none", "7", "0.5", "farkas")]
    [True, False, None, 7, 0.5, 'farkas']
    """
    low = text.strip().lower()
    if low in TRUE:
        return True
    if low in FALSE:
        return False
    if low in NONE:
        return None
    for cast in (int, float):
        try:
            return cast(text.strip())
        except ValueError:
            pass
    return text.strip()


def parse_assignments(items: Iterable[str], solver: str = "solver") -> dict[str, Any]:
    """``KEY=VALUE`` strings as a dict (later ones win); a string without ``=`` is
    :class:`~plansynth.errors.InvalidOption`.

    >>> parse_assignments(["max-horizon=60", "prove=true"])
    {'max_horizon': 60, 'prove': True}
    """
    out: dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise InvalidOption(solver, item, "not KEY=VALUE")
        out[key.strip().replace("-", "_")] = parse_value(value)
    return out


def _names(cls: Any) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls))


def configure(
    solver: str, base: T, values: Mapping[str, Any], *, settable: Iterable[str] | None = None, why_fixed: str = ""
) -> T:
    """``base`` with ``values`` set. A name that is not a field of ``base`` (or not in
    ``settable``, when given) is :class:`~plansynth.errors.InvalidOption`; each value is
    checked by the dataclass's own ``__post_init__``."""
    allowed = _names(base) if settable is None else tuple(n for n in _names(base) if n in set(settable))
    for key in values:
        if key not in allowed:
            fixed = f" ({why_fixed})" if why_fixed and key in _names(base) else ""
            raise InvalidOption(
                solver, key, f"not an option of this solver{fixed}; its options: {', '.join(allowed) or 'none'}"
            )
    return dataclasses.replace(base, **values) if values else base  # type: ignore[type-var]


def _kind(annotation: Any) -> tuple[tuple[str, ...], bool]:
    """(base type names, None allowed) of a field's annotation, as written: ``bool | str``
    is either (a three-valued option: ``True``, ``False`` or a word such as ``"auto"``)."""
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", str(annotation))
    parts = [p.strip() for p in text.split("|")]
    optional = "None" in parts
    parts = [p for p in parts if p != "None"]
    return (tuple(parts) if parts else ("None",)), optional


def _is(kind: str, v: Any) -> bool:
    """``v`` is a value of the annotation's type ``kind`` (a type this module does not
    check, such as tuples or a solver's own values, takes anything)."""
    if kind == "bool":
        return isinstance(v, bool)
    if kind == "int":
        return isinstance(v, int) and not isinstance(v, bool)
    if kind == "float":
        return isinstance(v, (int, float)) and not isinstance(v, bool) and not math.isnan(v)
    if kind == "str":
        return isinstance(v, str)
    return True


def check_fields(value: Any, solver: str) -> None:
    """Check every field of the dataclass ``value`` against its annotation (``bool``,
    ``int``, ``float``, ``str``, a union of them such as ``bool | str``, optionally
    ``| None``) and its :func:`option` checks;
    the first that fails is :class:`~plansynth.errors.InvalidOption`.

    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Tri:
    ...     exact: bool | str = option("auto", "exact when asked", choices=("auto", True, False))
    ...     def __post_init__(self) -> None:
    ...         check_fields(self, "demo")
    >>> Tri(True).exact, Tri().exact
    (True, 'auto')
    >>> Tri(1)
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidOption: demo: option 'exact': expected bool or str, got 1
    >>> Tri("sometimes")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidOption: demo: option 'exact': unknown value 'sometimes' (known: auto, true, false)
    """
    for f in dataclasses.fields(value):
        v = getattr(value, f.name)
        kinds, optional = _kind(f.type)
        if v is None:
            if not optional:
                raise InvalidOption(solver, f.name, "a value is needed")
            continue
        if not any(_is(kind, v) for kind in kinds):
            raise InvalidOption(solver, f.name, f"expected {' or '.join(kinds)}, got {v!r}")
        meta = f.metadata
        choices = meta.get("choices")
        if choices is not None and v not in choices:
            raise InvalidOption(solver, f.name, f"unknown value {v!r} (known: {', '.join(map(_word, choices))})")
        minimum = meta.get("minimum")
        if minimum is not None and v < minimum:
            raise InvalidOption(solver, f.name, f"{v} is below its minimum {minimum}")
        if meta.get("positive") and not (0 < v < math.inf):
            raise InvalidOption(solver, f.name, f"must be positive and finite, got {v}")


def _word(value: Any) -> str:
    """A value as ``KEY=VALUE`` spells it (``true``, ``false``, ``none``, else as is)."""
    return "none" if value is None else str(value).lower() if isinstance(value, bool) else str(value)


def describe(cls: Any) -> list[tuple[str, Any, str]]:
    """(name, default, help) of every option of the dataclass ``cls`` (or a value of it)."""
    out = []
    for f in dataclasses.fields(cls):
        default = f.default if f.default is not dataclasses.MISSING else None
        if not isinstance(cls, type):
            default = getattr(cls, f.name)
        out.append((f.name, default, f.metadata.get("doc", "")))
    return out


def help_lines(cls: Any) -> list[str]:
    """One line per option, ``name (default: value): help``, for ``--help`` and docs."""
    lines = []
    for name, default, doc in describe(cls):
        shown = _word(default)
        lines.append(f"{name} (default {shown}): {doc}" if doc else f"{name} (default {shown})")
    return lines


def changed(value: Any, default: Any) -> dict[str, Any]:
    """The options of ``value`` that differ from ``default`` (what a result records)."""
    return {n: getattr(value, n) for n in _names(value) if getattr(value, n) != getattr(default, n)}

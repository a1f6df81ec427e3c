"""Checking the fields of a parsed document with errors that name the file, the field
and the reason (STYLE.md, point 2): :class:`Fields` for one mapping, the ``as_*``
readers for values, :func:`show` for a short ``repr`` of any value in a message.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Mapping, Sequence
from typing import Any

from plansynth.errors import InvalidProblem

__all__ = [
    "Fields",
    "show",
    "type_name",
    "key_text",
    "as_int",
    "as_int_vector",
    "as_float",
    "as_float_vector",
    "as_name",
    "MAX_NAME_LENGTH",
]


_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxtuple, _REPR.maxdict = 3, 6, 6, 4
_REPR.maxstring, _REPR.maxother, _REPR.maxlong = 60, 60, 40


def show(value: Any) -> str:
    """A short ``repr`` for error messages, whatever the size of the value.

    >>> show(list(range(100)))
    '[0, 1, 2, 3, 4, 5, ...]'
    """
    try:
        return _REPR.repr(value)
    except Exception:  # noqa: BLE001 - a message must never fail
        return f"<{type(value).__name__}>"


class Fields:
    """Checks one mapping of a document, remembering where it sits for error messages.

    >>> f = Fields({"a": 1}, "x.yaml", "robot")
    >>> f.require("a")
    1
    >>> f.optional("b", 7)
    7
    >>> f.reject_unknown({"a"})
    >>> f.require("c")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: x.yaml: robot.c: missing required field
    """

    def __init__(self, value: Any, file: str | None, where: str) -> None:
        self.file = file
        self.where = where
        if not isinstance(value, Mapping):
            raise InvalidProblem(file, where or "<document>", f"expected a mapping, got {type_name(value)}")
        self.value = value

    def path(self, key: str) -> str:
        return f"{self.where}.{key}" if self.where else key

    def error(self, key: str, reason: str) -> InvalidProblem:
        return InvalidProblem(self.file, self.path(key), reason)

    def require(self, key: str) -> Any:
        if key not in self.value:
            raise self.error(key, "missing required field")
        return self.value[key]

    def optional(self, key: str, default: Any = None) -> Any:
        v = self.value.get(key, default)
        return default if v is None else v

    def reject_unknown(self, allowed: set[str]) -> None:
        for key in self.value:
            if key not in allowed:
                raise self.error(key_text(key), f"unknown key (allowed: {', '.join(sorted(allowed))})")


def type_name(value: Any) -> str:
    if value is None:
        return "nothing"
    return type(value).__name__


def as_int(value: Any, file: str | None, field: str, *, lo: int | None = None, hi: int | None = None) -> int:
    """An integer (not a bool, not a float with a fraction), within ``lo..hi`` if given.

    >>> as_int(10**30, "p.yaml", "steps", hi=1000)
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: p.yaml: steps: must be <= 1000, got 1000000000000000000000000000000
    """
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidProblem(file, field, f"expected an integer, got {show(value)}")
    if lo is not None and value < lo:
        raise InvalidProblem(file, field, f"must be >= {lo}, got {show(value)}")
    if hi is not None and value > hi:
        raise InvalidProblem(file, field, f"must be <= {hi}, got {show(value)}")
    return value


def as_int_vector(
    value: Any, file: str | None, field: str, length: int | None = None, *, lo: int | None = None, hi: int | None = None
) -> tuple[int, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field, f"expected a list of integers, got {show(value)}")
    if length is not None and len(value) != length:
        raise InvalidProblem(file, field, f"expected {length} integers, got {len(value)}")
    return tuple(as_int(v, file, f"{field}[{i}]", lo=lo, hi=hi) for i, v in enumerate(value))


def as_float(
    value: Any, file: str | None, field: str, *, positive: bool = False, max_abs: float | None = None
) -> float:
    """A finite real number; with ``positive``, strictly greater than zero; with
    ``max_abs``, at most that in absolute value (a documented limit, README "Formats").

    >>> as_float(1e200, "p.yaml", "workspace.max[0]", max_abs=1e6)
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: p.yaml: workspace.max[0]: must lie within -1e+06..1e+06, got 1e+200
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InvalidProblem(file, field, f"expected a finite number, got {show(value)}")
    try:
        x = float(value)
    except OverflowError:
        x = math.inf if value > 0 else -math.inf
    if not math.isfinite(x):
        raise InvalidProblem(file, field, f"expected a finite number, got {show(value)}")
    if positive and not x > 0:
        raise InvalidProblem(file, field, f"must be positive, got {show(value)}")
    if max_abs is not None and not abs(x) <= max_abs:
        raise InvalidProblem(file, field, f"must lie within {-max_abs:g}..{max_abs:g}, got {x:g}")
    return x


def as_float_vector(
    value: Any, file: str | None, field: str, length: int | None = None, *, max_abs: float | None = None
) -> tuple[float, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field, f"expected a list of numbers, got {show(value)}")
    if length is not None and len(value) != length:
        raise InvalidProblem(file, field, f"expected {length} numbers, got {len(value)}")
    return tuple(as_float(v, file, f"{field}[{i}]", max_abs=max_abs) for i, v in enumerate(value))


def key_text(key: Any, limit: int = 60) -> str:
    """A mapping key as a field name in messages (short, whatever its size)."""
    if not isinstance(key, str):
        return show(key)
    return key if len(key) <= limit else key[: limit - 3] + "..."


#: Longest problem name (both halves): names appear in messages, tables and file names.
MAX_NAME_LENGTH = 200


def as_name(value: Any, file: str | None, field: str = "name", *, numbers: bool = False) -> str:
    """A problem's name: a string (with ``numbers``, also a number, as its text) of at
    most :data:`MAX_NAME_LENGTH` characters.

    >>> as_name(7, "p.yaml", numbers=True)
    '7'
    >>> as_name(7, "p.yaml")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: p.yaml: name: expected a string, got int
    """
    if not (isinstance(value, str) or (numbers and isinstance(value, (int, float)) and not isinstance(value, bool))):
        raise InvalidProblem(file, field, f"expected a string, got {type_name(value)}")
    text = str(value)
    if len(text) > MAX_NAME_LENGTH:
        raise InvalidProblem(file, field, f"at most {MAX_NAME_LENGTH} characters, got {len(text)}")
    return text

"""Reading problem files (YAML or JSON) and checking fields with errors that name the
file, the field and the reason (STYLE.md, point 2). Both halves of plansynth use this.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from plansynth.errors import InvalidProblem


def load_document(path: str | Path) -> tuple[Any, str]:
    """Parse a YAML or JSON file; return (document, file name for error messages).

    JSON is valid YAML 1.2 in all but corner cases, but we parse ``.json`` with the
    json module so its error positions are exact.
    """
    p = Path(path)
    name = str(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InvalidProblem(name, "<file>", f"cannot read: {exc.strerror or exc}") from exc
    try:
        if p.suffix.lower() == ".json":
            doc = json.loads(text, object_pairs_hook=_json_object_without_duplicates)
        else:
            doc = yaml.load(text, Loader=_StrictLoader)  # noqa: S506 - a SafeLoader subclass
    except _DuplicateKey as exc:
        raise InvalidProblem(name, exc.key, f"duplicated key{exc.where}") from None
    except (yaml.YAMLError, json.JSONDecodeError) as exc:
        raise InvalidProblem(name, "<file>", f"not valid YAML/JSON: {exc}") from exc
    return doc, name


class _DuplicateKey(Exception):
    def __init__(self, key: str, where: str = "") -> None:
        self.key, self.where = key, where


def _json_object_without_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in pairs:
        if k in out:
            raise _DuplicateKey(str(k))
        out[k] = v
    return out


class _StrictLoader(yaml.SafeLoader):
    """PyYAML's safe loader, except that a key written twice in one mapping is an error
    (plain PyYAML silently keeps the last one, hiding a typo in a problem file)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise _DuplicateKey(str(key), f" (line {key_node.start_mark.line + 1})")
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


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
                raise self.error(str(key), f"unknown key (allowed: {', '.join(sorted(allowed))})")


def type_name(value: Any) -> str:
    if value is None:
        return "nothing"
    return type(value).__name__


def as_int(value: Any, file: str | None, field: str) -> int:
    """An integer (not a bool, not a float with a fraction)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InvalidProblem(file, field, f"expected an integer, got {value!r}")
    return value


def as_int_vector(value: Any, file: str | None, field: str, length: int | None = None) -> tuple[int, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field, f"expected a list of integers, got {value!r}")
    if length is not None and len(value) != length:
        raise InvalidProblem(file, field, f"expected {length} integers, got {len(value)}")
    return tuple(as_int(v, file, f"{field}[{i}]") for i, v in enumerate(value))


def as_float(value: Any, file: str | None, field: str, *, positive: bool = False) -> float:
    """A finite real number; with ``positive``, strictly greater than zero."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InvalidProblem(file, field, f"expected a finite number, got {value!r}")
    if positive and not value > 0:
        raise InvalidProblem(file, field, f"must be positive, got {value!r}")
    return float(value)


def as_float_vector(value: Any, file: str | None, field: str, length: int | None = None) -> tuple[float, ...]:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(file, field, f"expected a list of numbers, got {value!r}")
    if length is not None and len(value) != length:
        raise InvalidProblem(file, field, f"expected {length} numbers, got {len(value)}")
    return tuple(as_float(v, file, f"{field}[{i}]") for i, v in enumerate(value))

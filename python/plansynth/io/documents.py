"""Reading documents: every file plansynth reads (problem files, result JSON files,
``.sl`` and program files) goes through :func:`read_text`, and every YAML/JSON document
through :func:`load_document` (or :func:`parse_document` for text in hand), so one set
of limits holds for all of them (README, "Formats and extensions"): a regular file of
at most :data:`MAX_FILE_BYTES`, UTF-8 text, and the nesting and size limits of
:mod:`plansynth.io.strict_yaml`. A hostile file is an :class:`InvalidProblem`, never
a traceback, a hang or a memory blow-up.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

import yaml

from plansynth.errors import InvalidProblem
from plansynth.io.fields import key_text
from plansynth.io.strict_yaml import MAX_NESTING, DuplicateKey, Refused, load_yaml

__all__ = ["read_text", "decode_utf8", "load_document", "parse_document", "MAX_FILE_BYTES"]

#: Largest file plansynth reads: 8 MiB (the examples are at most a few hundred kB).
MAX_FILE_BYTES = 8 * 1024 * 1024


def read_text(path: str | Path) -> tuple[str, str]:
    """The text of a file and its name for messages, or :class:`InvalidProblem`.

    Only regular files are read (a FIFO would block, ``/dev/zero`` never ends), at most
    :data:`MAX_FILE_BYTES` of them, and the bytes must be UTF-8 (a leading byte-order
    mark is dropped).

    >>> read_text("/dev/null")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: /dev/null: <file>: not a regular file (a device, FIFO or socket is refused)
    """
    name = str(path)
    try:
        st = os.stat(path)
        if stat.S_ISDIR(st.st_mode):
            raise InvalidProblem(name, "<file>", "is a directory, not a file")
        if not stat.S_ISREG(st.st_mode):
            raise InvalidProblem(name, "<file>", "not a regular file (a device, FIFO or socket is refused)")
        if st.st_size > MAX_FILE_BYTES:
            raise InvalidProblem(name, "<file>", f"too large: {st.st_size} bytes (limit {MAX_FILE_BYTES} bytes)")
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
        with os.fdopen(fd, "rb") as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):  # replaced since the stat above
                raise InvalidProblem(name, "<file>", "not a regular file (a device, FIFO or socket is refused)")
            data = fh.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise InvalidProblem(name, "<file>", f"cannot read: {exc.strerror or exc}") from None
    except ValueError as exc:  # an embedded NUL byte in the path
        raise InvalidProblem(name, "<file>", f"cannot read: {exc}") from None
    if len(data) > MAX_FILE_BYTES:
        raise InvalidProblem(name, "<file>", f"too large: over {MAX_FILE_BYTES} bytes")
    return decode_utf8(data, name), name


def decode_utf8(data: bytes, name: str, field: str = "<file>") -> str:
    """Decode UTF-8 or raise :class:`InvalidProblem` naming the first bad byte's place.

    >>> decode_utf8("# caf\\xe9".encode("latin-1"), "p.yaml")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: p.yaml: <file>: not UTF-8 text: byte 0xe9 at line 1, column 6 (save the file as UTF-8)
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise InvalidProblem(
            name,
            field,
            f"not UTF-8 text: byte 0x{data[exc.start]:02x} at line {line}, column {column} (save the file as UTF-8)",
        ) from None
    return text[1:] if text.startswith("\ufeff") else text


def load_document(path: str | Path) -> tuple[Any, str]:
    """Parse a YAML or JSON file; return (document, file name for error messages).

    JSON is valid YAML 1.2 in all but corner cases, but we parse ``.json`` with the
    json module so its error positions are exact. The limits of :func:`read_text` and
    of the module docstring apply.
    """
    text, name = read_text(path)
    return parse_document(text, name, json_syntax=Path(path).suffix.lower() == ".json"), name


def parse_document(text: str, name: str, *, json_syntax: bool = False, kind: str = "YAML/JSON") -> Any:
    """Parse YAML (or, with ``json_syntax``, JSON) text within the module's limits;
    ``kind`` names the format in messages."""
    try:
        if json_syntax:
            doc = json.loads(text, object_pairs_hook=_json_object_without_duplicates)
            _check_json_shape(doc, name)
        else:
            doc = load_yaml(text)
    except DuplicateKey as exc:
        raise InvalidProblem(name, exc.key, f"duplicated key{exc.where}") from None
    except Refused as exc:
        raise InvalidProblem(name, "<file>", str(exc)) from None
    except RecursionError:
        raise InvalidProblem(name, "<file>", f"nested deeper than {MAX_NESTING} levels") from None
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:  # JSONDecodeError is a ValueError
        raise InvalidProblem(name, "<file>", f"not valid {kind}: {_one_line(exc)}") from None
    return doc


def _one_line(exc: BaseException, limit: int = 300) -> str:
    text = " ".join(str(exc).replace('in "<unicode string>", ', "").split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _json_object_without_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in pairs:
        if k in out:
            raise DuplicateKey(key_text(k))
        out[k] = v
    return out


def _check_json_shape(doc: Any, name: str) -> None:
    """Refuse JSON nested deeper than MAX_NESTING (checked without recursion)."""
    stack: list[tuple[Any, int]] = [(doc, 1)]
    while stack:
        value, level = stack.pop()
        if isinstance(value, (list, dict)):
            if level > MAX_NESTING:
                raise Refused(f"nested deeper than {MAX_NESTING} levels")
            children = value.values() if isinstance(value, dict) else value
            stack.extend((c, level + 1) for c in children if isinstance(c, (list, dict)))

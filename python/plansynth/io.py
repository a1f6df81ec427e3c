"""Reading problem files (YAML or JSON) and checking fields with errors that name the
file, the field and the reason (STYLE.md, point 2); writing output files atomically.
Both halves of plansynth use this.
"""

from __future__ import annotations

import contextlib
import errno
import json
import math
import os
import signal
import tempfile
import threading
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from plansynth.errors import InvalidProblem, OutputUnwritable


# ------------------------------------------------------------------ writing outputs


def _reason(exc: OSError) -> str:
    if exc.errno == errno.EFBIG:
        return "file too large (the file size limit, ulimit -f, was reached)"
    if exc.errno == errno.ENOSPC:
        return "no space left on the device"
    return exc.strerror or str(exc)


def check_output_path(path: str | Path) -> Path:
    """Check, before any work, that a file can be written at ``path``: its folder
    exists, is a folder and accepts a new file (probed by creating and removing a
    temporary file there), and ``path`` is not a folder or a device. Raises
    :class:`~plansynth.errors.OutputUnwritable` naming the path and the reason.

    >>> check_output_path("/nonexistent-folder/r.json")
    Traceback (most recent call last):
    ...
    plansynth.errors.OutputUnwritable: cannot write /nonexistent-folder/r.json: folder /nonexistent-folder does not exist
    """
    p = Path(path)
    name = str(path)
    if p.name in ("", ".", ".."):
        raise OutputUnwritable(name, "not a file name")
    if p.exists() or p.is_symlink():
        if p.is_dir():
            raise OutputUnwritable(name, "is a folder")
        if not p.is_file():
            raise OutputUnwritable(name, "not a regular file (a device, pipe or socket)")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.exists():
        raise OutputUnwritable(name, f"folder {parent} does not exist")
    if not parent.is_dir():
        raise OutputUnwritable(name, f"{parent} is not a folder")
    try:
        fd, probe = tempfile.mkstemp(dir=parent, prefix=f".{p.name}.", suffix=".probe")
    except OSError as exc:
        raise OutputUnwritable(name, _reason(exc)) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)
    return p


def check_output_folder(path: str | Path) -> Path:
    """Like :func:`check_output_path` for a folder that receives files (created if
    missing, with its parents): it must be (or become) a writable folder."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputUnwritable(str(path), "not a folder")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputUnwritable(str(path), _reason(exc)) from None
    check_output_path(p / "probe")
    return p


@contextlib.contextmanager
def _file_size_signal_ignored() -> Iterator[None]:
    """Past ``ulimit -f`` the kernel sends SIGXFSZ, which kills the process by
    default and leaves a truncated file; ignored, the write fails with EFBIG instead."""
    sig = getattr(signal, "SIGXFSZ", None)
    if sig is None or threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(sig, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(sig, old)


@contextlib.contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path in the folder of ``path``; when the block ends without an
    exception, the temporary file is flushed to disk (fsync) and renamed onto ``path``,
    so ``path`` either keeps its old content or gets the whole new one, never a
    truncated file. Any OSError (missing folder, no space, EFBIG past ``ulimit -f``,
    a device) becomes :class:`~plansynth.errors.OutputUnwritable`; the temporary file
    is removed. For writers that need a file name (matplotlib, Pillow)."""
    p = check_output_path(path)
    name = str(path)
    with _file_size_signal_ignored():
        try:
            fd, tmp = tempfile.mkstemp(dir=p.parent if str(p.parent) else ".", prefix=f".{p.name}.", suffix=".tmp"
                                       + "".join(p.suffixes[-1:]))
        except OSError as exc:
            raise OutputUnwritable(name, _reason(exc)) from None
        os.close(fd)
        try:
            yield Path(tmp)
            fd = os.open(tmp, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, p)
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise OutputUnwritable(name, _reason(exc)) from None
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise


def write_output(path: str | Path, data: str | bytes) -> Path:
    """Write ``data`` (text as UTF-8) to ``path`` atomically (:func:`atomic_output`):
    every output file of plansynth goes through here or through :func:`atomic_output`.

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> write_output(d / "a.txt", "hello").read_text()
    'hello'
    """
    raw = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(raw)
            f.flush()
    return Path(path)


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

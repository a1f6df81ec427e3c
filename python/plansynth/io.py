"""Reading problem files (YAML or JSON) and checking fields with errors that name the
file, the field and the reason (STYLE.md, point 2); writing output files atomically
(:func:`write_output`, :func:`atomic_output`). Both halves of plansynth use this.

Every file plansynth reads (problem files, result JSON files, ``.sl`` and program
files) goes through :func:`read_text`, and every YAML/JSON document through
:func:`load_document`, so one set of limits holds for all of them (README, "Formats and
extensions"): a regular file of at most :data:`MAX_FILE_BYTES`, UTF-8 text, nesting of
at most :data:`MAX_NESTING` levels and at most :data:`MAX_NODES` values, counting every
use of a YAML alias as a copy of what it names (a "billion laughs" document is refused
before anything expands it). A hostile file is an :class:`InvalidProblem`, never a
traceback, a hang or a memory blow-up.
"""

from __future__ import annotations

import contextlib
import errno
import json
import math
import os
import re
import reprlib
import signal
import stat
import tempfile
import threading
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from plansynth.errors import InvalidProblem, OutputUnwritable

#: Largest file plansynth reads: 8 MiB (the examples are at most a few hundred kB).
MAX_FILE_BYTES = 8 * 1024 * 1024
#: Deepest nesting of lists and mappings in a document (the formats need at most 5).
MAX_NESTING = 64
#: Most values (scalars, lists, mappings) one document may hold, each use of a YAML
#: alias ``*a`` counting as a full copy of what it names.
MAX_NODES = 1_000_000


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
            doc = _load_yaml(text)
    except _DuplicateKey as exc:
        raise InvalidProblem(name, exc.key, f"duplicated key{exc.where}") from None
    except _Refused as exc:
        raise InvalidProblem(name, "<file>", str(exc)) from None
    except RecursionError:
        raise InvalidProblem(name, "<file>", f"nested deeper than {MAX_NESTING} levels") from None
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as exc:  # JSONDecodeError is a ValueError
        raise InvalidProblem(name, "<file>", f"not valid {kind}: {_one_line(exc)}") from None
    return doc


def _one_line(exc: BaseException, limit: int = 300) -> str:
    text = " ".join(str(exc).replace('in "<unicode string>", ', "").split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


class _DuplicateKey(Exception):
    def __init__(self, key: str, where: str = "") -> None:
        self.key, self.where = key, where


class _Refused(Exception):
    """A document beyond the limits (nesting, size through aliases, complex keys)."""


def _json_object_without_duplicates(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in pairs:
        if k in out:
            raise _DuplicateKey(_key_text(k))
        out[k] = v
    return out


def _check_json_shape(doc: Any, name: str) -> None:
    """Refuse JSON nested deeper than MAX_NESTING (checked without recursion)."""
    stack: list[tuple[Any, int]] = [(doc, 1)]
    while stack:
        value, level = stack.pop()
        if isinstance(value, (list, dict)):
            if level > MAX_NESTING:
                raise _Refused(f"nested deeper than {MAX_NESTING} levels")
            children = value.values() if isinstance(value, dict) else value
            stack.extend((c, level + 1) for c in children if isinstance(c, (list, dict)))


def _where(node: yaml.Node) -> str:
    return f"line {node.start_mark.line + 1}, column {node.start_mark.column + 1}"


def _load_yaml(text: str) -> Any:
    """One YAML document within the module's limits: with libyaml (PyYAML's C parser, about
    8x faster: a 3 kB problem file in 7 ms instead of 55 ms, most of a small ``grid
    solve``'s parse) when PyYAML was built with it, else with the pure-Python loader.
    Both apply the same limits and construct the same values (tests/test_io.py)."""
    if not _LIBYAML:
        return yaml.load(text, Loader=_StrictLoader)  # noqa: S506 - a SafeLoader subclass
    # libyaml composes nodes recursively in C: the nesting is refused from its event
    # stream first, before anything deep is composed
    try:
        _check_event_nesting(yaml.cyaml.CParser(text))
        loader = _StrictCLoader(text)
        try:
            node = loader.get_single_node()
            _check_expanded_size(node)
            return None if node is None else loader.construct_document(node)
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError:
        # not YAML: PyYAML's own parser words the error better (it names an undefined
        # alias, and what it expected); the cost of a second parse is only paid here
        return yaml.load(text, Loader=_StrictLoader)  # noqa: S506 - a SafeLoader subclass


def _check_event_nesting(parser: Any) -> None:
    """Refuse more than MAX_NESTING levels, counted as :class:`_StrictLoader` counts them
    (every value, scalars and keys included, one level below its container)."""
    depth = 0
    try:
        while parser.check_event():
            event = parser.get_event()
            if isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
                depth += 1
                level = depth
            elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
                depth -= 1
                continue
            elif isinstance(event, yaml.ScalarEvent):
                level = depth + 1
            else:
                continue
            if level > MAX_NESTING:
                raise _Refused(f"nested deeper than {MAX_NESTING} levels (line {event.start_mark.line + 1})")
    finally:
        parser.dispose()


class _NoDuplicateKeys:
    """Mapping construction that refuses a key written twice, or a key that is not a
    plain value (mixed in before PyYAML's SafeConstructor)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                kind = "list" if isinstance(key_node, yaml.SequenceNode) else "mapping"
                raise _Refused(f"a mapping key must be a plain value, not a {kind} ({_where(key_node)})")
            key = self.construct_object(key_node, deep=deep)  # type: ignore[attr-defined]
            if key in seen:
                raise _DuplicateKey(_key_text(key), f" (line {key_node.start_mark.line + 1})")
            seen.add(key)
        return super().construct_mapping(node, deep=deep)  # type: ignore[misc]


class _StrictLoader(_NoDuplicateKeys, yaml.SafeLoader):
    """PyYAML's safe loader with the module's limits, plus two fixes:

    - a key written twice in one mapping is an error (plain PyYAML silently keeps the
      last one, hiding a typo in a problem file), and so is a key that is not a scalar
      (``? [1, 2] : 3``);
    - numbers with an exponent and no dot (``5e-1``, ``1e3``, ``1.0e5``) are floats, as a
      user means them (YAML 1.1 reads them as strings).
    """

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._nesting = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            return super().compose_node(parent, index)
        self._nesting += 1
        try:
            if self._nesting > MAX_NESTING:
                mark = self.peek_event().start_mark
                raise _Refused(f"nested deeper than {MAX_NESTING} levels (line {mark.line + 1})")
            return super().compose_node(parent, index)
        finally:
            self._nesting -= 1

    def compose_document(self) -> Any:
        node = super().compose_document()
        _check_expanded_size(node)
        return node


_LIBYAML = bool(getattr(yaml, "__with_libyaml__", False))
if _LIBYAML:

    class _StrictCLoader(_NoDuplicateKeys, yaml.CSafeLoader):
        """:class:`_StrictLoader` on libyaml's parser and composer (the limits are
        checked around it by :func:`_load_yaml`)."""


_EXPONENT_FLOAT = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$")
for _loader in (_StrictLoader, _StrictCLoader) if _LIBYAML else (_StrictLoader,):
    _loader.add_implicit_resolver("tag:yaml.org,2002:float", _EXPONENT_FLOAT, list("-+0123456789."))


def _check_expanded_size(root: Any) -> None:
    """Refuse a node graph that expands to more than MAX_NODES values, or a cycle.

    Aliases make the composed document a graph with shared nodes; what the rest of the
    program sees (and prints) is its expansion as a tree. Counted iteratively with one
    visit per distinct node, so even a billion-laughs graph costs microseconds.
    """
    if root is None:
        return
    size: dict[int, int] = {}
    active: set[int] = set()
    stack: list[tuple[Any, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            active.discard(key)
            if isinstance(node, yaml.MappingNode):
                total = 1 + sum(size[id(k)] + size[id(v)] for k, v in node.value)
            elif isinstance(node, yaml.SequenceNode):
                total = 1 + sum(size[id(c)] for c in node.value)
            else:
                total = 1
            if total > MAX_NODES:
                raise _Refused(
                    f"expands to more than {MAX_NODES} values, each alias *name counting as a copy "
                    f"of what it names ({_where(node)})"
                )
            size[key] = total
            continue
        if key in size:
            continue
        if key in active:
            raise _Refused(f"an alias refers to a value that contains it ({_where(node)})")
        active.add(key)
        stack.append((node, True))
        if isinstance(node, yaml.MappingNode):
            children = [c for pair in node.value for c in pair]
        elif isinstance(node, yaml.SequenceNode):
            children = list(node.value)
        else:
            children = []
        for c in children:
            if id(c) in active:
                raise _Refused(f"an alias refers to a value that contains it ({_where(c)})")
            if id(c) not in size:
                stack.append((c, False))


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
                raise self.error(_key_text(key), f"unknown key (allowed: {', '.join(sorted(allowed))})")


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


def _key_text(key: Any, limit: int = 60) -> str:
    """A mapping key as a field name in messages (short, whatever its size)."""
    if not isinstance(key, str):
        return show(key)
    return key if len(key) <= limit else key[: limit - 3] + "..."


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
            fd, tmp = tempfile.mkstemp(
                dir=p.parent if str(p.parent) else ".", prefix=f".{p.name}.", suffix=".tmp" + "".join(p.suffixes[-1:])
            )
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

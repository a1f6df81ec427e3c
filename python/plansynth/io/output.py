"""Writing output files: checked before any work (:func:`check_output_path`,
:func:`check_output_folder`) and written atomically (:func:`atomic_output`,
:func:`write_output`), so an output file either keeps its old content or gets the
whole new one; every failure is :class:`~plansynth.errors.OutputUnwritable` naming the
path and the reason.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path

from plansynth.errors import OutputUnwritable

__all__ = ["check_output_path", "check_output_folder", "atomic_output", "write_output"]


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
    with atomic_output(path) as tmp, open(tmp, "wb") as f:
        f.write(raw)
        f.flush()
    return Path(path)

"""What a results database says about the machine, and what it must not say.

:func:`machine_info` is recorded with every sweep (host, CPU, memory, software
versions); :func:`scrub_paths` shortens the file paths in the messages a run records,
so that a shared database names no local directories.
"""

from __future__ import annotations

import os
import platform
import socket
from pathlib import Path
from typing import Any

__all__ = ["machine_info", "scrub_paths"]


def scrub_paths(text: str) -> str:
    """Shorten absolute file paths in tracebacks to what follows ``site-packages/`` or
    the ``plansynth`` package, so a shared results database names no local directories.

    >>> scrub_paths('File "/home/me/src/python/plansynth/grid/solve.py", line 3')
    'File ".../plansynth/grid/solve.py", line 3'
    """
    import re

    text = re.sub(r'(?:/[^\s"\']+)?/(site-packages|plansynth)/', r".../\1/", text)
    return re.sub(r'(?<![\w.])/(?:tmp|home|root|work|Users)/[^\s"\']*', "<path>", text)


def machine_info() -> dict[str, Any]:
    """Host, CPU, memory and software versions, recorded with every experiment."""
    from importlib.metadata import PackageNotFoundError, version

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gb = None
    try:
        mem_gb = round(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30, 1)
    except (ValueError, OSError, AttributeError):
        pass
    versions = {}
    for pkg in ("plansynth", "cvc5", "python-sat", "highspy", "ompl", "shapely", "numpy"):
        try:
            versions[pkg] = version(pkg)
        except PackageNotFoundError:
            versions[pkg] = None
    return {
        "hostname": socket.gethostname(),
        "cpuinfo": f"{cpu}, {os.cpu_count()} cores, {mem_gb} GB",
        "version": f"plansynth {versions['plansynth']}",
        "python": platform.python_version(),
        "platform": platform.platform(),
        "versions": versions,
    }

"""The compiled core (``plansynth._core``), behind the same signatures as the pure-Python
references it replaces (STYLE.md, point 6)."""

from __future__ import annotations


def available() -> bool:
    return False

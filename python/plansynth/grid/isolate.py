"""Moved to :mod:`plansynth.isolate` (process isolation is shared by the grid backends
and the benchmark runner); this name is kept for callers outside plansynth."""

from plansynth.isolate import *  # noqa: F401,F403
from plansynth.isolate import __all__  # noqa: F401

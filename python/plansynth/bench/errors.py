"""The bench's named errors: inputs it refuses before it runs or writes anything.

Both are :class:`~plansynth.errors.PlansynthError` values whose message is one line
naming what is wrong; the ``plansynth bench`` commands print it and exit with status 2.

>>> str(ClusterUnreachable("tcp://127.0.0.1:1", "Connection refused", 5.0))
'cannot reach the Dask scheduler at tcp://127.0.0.1:1: Connection refused (gave up after 5 s)'
>>> str(NoRuns("empty.db"))
'empty.db: the results database holds no runs (nothing to report)'
>>> str(NoDatabase("other.db"))
'other.db: no such results database'
"""

from __future__ import annotations

from plansynth.errors import PlansynthError

__all__ = ["ClusterUnreachable", "NoDatabase", "NoRuns"]


class ClusterUnreachable(PlansynthError):
    """No Dask scheduler answers at ``address`` within ``seconds`` (None: the address is
    not one, nothing was waited for)."""

    def __init__(self, address: str, reason: str, seconds: float | None) -> None:
        self.address = address
        self.reason = reason
        self.seconds = seconds
        waited = "" if seconds is None else f" (gave up after {seconds:g} s)"
        super().__init__(f"cannot reach the Dask scheduler at {address}: {reason}{waited}")


class NoRuns(PlansynthError):
    """A results database without a single run: there is nothing to report."""

    def __init__(self, path: str) -> None:
        self.path = path
        super().__init__(f"{path}: the results database holds no runs (nothing to report)")


class NoDatabase(PlansynthError):
    """A results database to read (a merge's source) that does not exist."""

    def __init__(self, path: str) -> None:
        self.path = path
        super().__init__(f"{path}: no such results database")

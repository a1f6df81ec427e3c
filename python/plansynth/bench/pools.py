"""Where a sweep's runs happen: a local pool, or a Dask distributed cluster.

:func:`run_local` runs the tasks on ``jobs`` threads, each waiting for its task's
isolated child (:func:`plansynth.bench.child.run_task`); :func:`run_on_cluster` submits
them to a Dask cluster (:func:`connect`), whose workers isolate every run in a child
process again. Both record each run the moment it finishes and, on Ctrl-C
(KeyboardInterrupt), drop what is queued, kill what runs, keep what finished and raise
again.

:func:`connect` gives up on a scheduler address after :data:`CONNECT_SECONDS`, with
:class:`~plansynth.bench.errors.ClusterUnreachable` naming the address and the reason
(Dask's own default waits 30 s and ends in a traceback).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Any

from plansynth.bench.child import run_task
from plansynth.bench.errors import ClusterUnreachable

__all__ = ["run_local", "connect", "run_on_cluster", "settled", "CONNECT_SECONDS", "PROBE_SECONDS"]

#: How long :func:`connect` waits for a Dask scheduler to answer.
CONNECT_SECONDS = 3.0


def run_local(todo: Sequence[Mapping[str, Any]], jobs: int, record: Callable[..., None], bar: Any) -> None:
    """Run ``todo`` on ``jobs`` threads, each waiting for its isolated child; record
    each run as it finishes. On KeyboardInterrupt: drop the queued runs, kill the
    running children, record the runs that finished meanwhile, raise again."""
    from plansynth.isolate import cancel_all

    pool = ThreadPoolExecutor(max_workers=max(1, jobs))
    futures = {pool.submit(run_task, t): t for t in todo}
    recorded: set[Any] = set()
    try:
        for fut in as_completed(futures):
            task = futures[fut]
            recorded.add(fut)
            result = settled(fut, task)
            if result is not None:
                record(task, result)
            if bar is not None:
                bar.advance(task)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        cancel_all()
        for fut, task in futures.items():  # runs that finished before the children were killed
            if fut in recorded or fut.cancelled():
                continue
            try:
                fut.result(timeout=5)
            except BaseException:  # noqa: BLE001 - cancelled, killed or failed: not a finished run
                continue
            result = settled(fut, task)
            if result is not None:
                record(task, result)
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def settled(fut: Any, task: Mapping[str, Any]) -> dict[str, Any] | None:
    """The run's attributes; None when its child was cancelled (not a finished run)."""
    from plansynth.isolate import Cancelled

    try:
        return dict(fut.result())
    except Cancelled:
        return None
    except Exception as exc:  # the runner itself failed for this task: record, go on
        return {"status": "crash", "solved": 0, "message": f"runner error: {type(exc).__name__}: {exc}"[:4000]}


def connect(cluster: str | Any, seconds: float = CONNECT_SECONDS) -> tuple[Any, bool]:
    """A ``distributed.Client`` for ``cluster`` (a scheduler address, or a client, used as
    it is), and whether it is ours to close. An address that no scheduler answers within
    ``seconds`` (or that is not an address) is :class:`ClusterUnreachable`, whose reason
    comes from one plain connection attempt made after the client gave up."""
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover - dask is a test/bench extra
        from plansynth.errors import SolverUnavailable

        raise SolverUnavailable("dask", 'install dask.distributed: pip install "dask[distributed]"') from exc
    if isinstance(cluster, Client):
        return cluster, False
    try:
        return Client(cluster, timeout=seconds), True
    except Exception as exc:  # noqa: BLE001 - refused, no answer, a bad address, a peer that is no scheduler
        reason, waited = _diagnose(str(cluster), exc)
        raise ClusterUnreachable(str(cluster), reason, seconds if waited else None) from None


#: How long :func:`_diagnose` waits for a plain connection to say why the client failed.
PROBE_SECONDS = 2.0


def _diagnose(address: str, exc: BaseException) -> tuple[str, bool]:
    """Why no scheduler answered at ``address``, in a few words, and whether the client
    waited for it (not for a malformed address). For a TCP address, one plain connection
    attempt tells refused (nothing listens), an unknown host and no answer apart, and a
    peer that accepts the connection is no Dask scheduler. (Dask's own error says only
    that time ran out.)"""
    import socket

    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address)
        host, port = parse_host_port(location) if scheme in ("tcp", "tls") else (None, None)
    except ValueError as bad:
        return "not a scheduler address: " + " ".join(str(bad).split()), False
    if host is None:  # another transport: Dask's own words
        return " ".join(str(exc).split()) or type(exc).__name__, True
    try:
        socket.create_connection((host, port), timeout=PROBE_SECONDS).close()
    except socket.gaierror as err:
        return f"unknown host {host!r} ({err.strerror})", True
    except TimeoutError:
        return "no answer", True
    except OSError as err:
        return err.strerror or type(err).__name__, True
    return f"it accepts connections but answers as no Dask scheduler does ({type(exc).__name__})", True


def run_on_cluster(client: Any, todo: Sequence[Mapping[str, Any]], record: Callable[..., None], bar: Any) -> None:
    """Run ``todo`` on the cluster of ``client`` (:func:`connect`); record each run as it
    finishes."""
    from distributed import as_completed as dask_completed

    futures = {}
    for t in todo:
        key = f"plansynth-{t['experiment']}-{t['solver']}-{t['repeat']}-{time.time_ns()}"
        f = client.submit(run_task, dict(t), pure=False, key=key)
        futures[f.key] = (f, t)
    seen: set[str] = set()
    try:
        for fut in dask_completed([f for f, _ in futures.values()]):
            task = futures[fut.key][1]
            seen.add(fut.key)
            result = settled(fut, task)
            if result is not None:
                record(task, result)
            if bar is not None:
                bar.advance(task)
    except BaseException:  # Ctrl-C: keep what finished, drop what is queued or running
        pending = [f for f, _ in futures.values() if not f.done()]
        client.cancel(pending)
        for key, (f, task) in futures.items():
            if key not in seen and f.status == "finished":
                try:
                    result = settled(f, task)
                except BaseException:  # noqa: BLE001 - not a finished run
                    continue
                if result is not None:
                    record(task, result)
        raise

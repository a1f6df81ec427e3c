"""`--cluster`: the sweep runs on a real dask.distributed LocalCluster with worker processes."""

from __future__ import annotations

import pytest

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import grid_family
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks


def test_sweep_on_local_cluster_with_two_worker_processes(tmp_path):
    from distributed import Client, LocalCluster

    tasks = make_tasks(grid_family("depth", [1]), ["native", "debug-ok"], timeout=20)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            assert len(client.scheduler_info()["workers"]) == 2
            counts = run_sweep(tmp_path / "r.db", tasks, cluster=cluster.scheduler_address, progress=False)
    assert counts["done"] == 2
    with ResultsDB(tmp_path / "r.db") as db:
        runs = {r["planner"]: r for r in db.runs()}
    assert runs["native"]["status"] == "solved" and runs["native"]["valid"] == 1
    assert runs["debug-ok"]["status"] == "solved"


def test_a_scheduler_that_does_not_answer_fails_fast_before_anything_is_written(tmp_path):
    """`--cluster` at an address nothing listens on waited Dask's 30 s and ended in an
    OSError traceback: now one line naming the address and the reason, within seconds,
    exit 2, and no database is created."""
    import time

    from typer.testing import CliRunner

    from plansynth.bench.errors import ClusterUnreachable
    from plansynth.bench.pools import CONNECT_SECONDS
    from plansynth.cli import app

    db = tmp_path / "r.db"
    started = time.monotonic()
    r = CliRunner().invoke(
        app,
        [
            "bench",
            "grid",
            "--family",
            "figure1",
            "--solvers",
            "native",
            "--db",
            str(db),
            "--cluster",
            "tcp://127.0.0.1:1",
        ],
    )
    seconds = time.monotonic() - started
    assert r.exit_code == 2, r.output
    (line,) = [x for x in r.output.splitlines() if "error" in x]
    assert "--cluster" in line and "tcp://127.0.0.1:1" in line and "Connection refused" in line, r.output
    assert "Traceback" not in r.output and "OSError" not in r.output
    assert CONNECT_SECONDS <= 5 and seconds < 20, seconds  # Dask's default wait is 30 s
    assert not db.exists()
    # the API raises the named error, with the address and the reason
    tasks = make_tasks(grid_family("depth", [1]), ["native"], timeout=5)
    with pytest.raises(ClusterUnreachable, match=r"tcp://127\.0\.0\.1:1: .*gave up after"):
        run_sweep(db, tasks, cluster="tcp://127.0.0.1:1", progress=False)
    with pytest.raises(ClusterUnreachable, match="not-an-address"):
        run_sweep(db, tasks, cluster="not-an-address", progress=False)
    assert not db.exists()

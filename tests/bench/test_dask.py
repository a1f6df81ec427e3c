"""`--cluster`: the sweep runs on a real dask.distributed LocalCluster with worker processes."""

from __future__ import annotations

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


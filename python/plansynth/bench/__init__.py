"""Benchmarks reproducing both papers' evaluations side by side with peers.

- :mod:`plansynth.bench.families` -- the benchmark families as code (and files);
- :mod:`plansynth.bench.tasks` -- a sweep's runs as plain tasks, with their limits;
- :mod:`plansynth.bench.runner` -- isolated, resumable sweeps, on the pools of
  :mod:`plansynth.bench.pools` (local or Dask), each run in its own child
  (:mod:`plansynth.bench.child`), recorded with :mod:`plansynth.bench.machine`'s facts;
- :mod:`plansynth.bench.execute` -- one run inside its child process;
- :mod:`plansynth.bench.db` -- the SQLite results database (OMPL's benchmark schema);
- :mod:`plansynth.bench.report` -- Markdown tables and log-scale plots;
- :mod:`plansynth.bench.publish` -- the sweep behind ``benchmarks/RESULTS.md``;
- :mod:`plansynth.bench.solvers` -- the order the bench lists solvers in;
- :mod:`plansynth.bench.errors` -- the bench's named errors (an unreachable cluster, a
  database without runs).

The Python API does everything the ``plansynth bench`` commands do:

>>> from plansynth.bench import grid_family, make_tasks
>>> len(make_tasks(grid_family("steps", [5, 10]), ["native", "cvc5"], repeat=3))
12
"""

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import Instance, family, grid_family, reach_family
from plansynth.bench.report import write_report
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks

__all__ = ["Instance", "ResultsDB", "family", "grid_family", "make_tasks", "reach_family", "run_sweep", "write_report"]

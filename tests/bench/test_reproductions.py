"""The papers' evaluations as regression tests (STYLE.md, point 10): slow, opt-in.

Run with ``pytest --runslow tests/bench/test_reproductions.py``. Each sweeps one
published family through the real runner (child processes, database) and checks the
answers, not the times: every instance of the grid paper is realizable with a verified
controller of the depth the instance is named for (depth-6 excepted: our semantics
admit a depth-5 controller), and every maze is solved by the baselines with a
validated, segment-safe trajectory.
"""

from __future__ import annotations

import pytest

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import family
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks


@pytest.mark.slow
def test_grid_paper_families_native(tmp_path):
    insts = [i for f in ("figure1", "depth", "steps", "obstacles", "dimensions") for i in family("grid", f)]
    run_sweep(tmp_path / "g.db", make_tasks(insts, ["native"], timeout=120), progress=False)
    with ResultsDB(tmp_path / "g.db") as db:
        runs = {r["instance"]: r for r in db.runs()}
    assert len(runs) == len(insts)
    for name, r in runs.items():
        assert r["status"] == "solved" and r["valid"] == 1, name
    assert [runs[f"depth-{d}"]["depth"] for d in (1, 4, 5)] == [1, 4, 5]
    assert runs["figure1"]["steps"] == 6


@pytest.mark.slow
def test_reactive_families_native_answers_match_their_design(tmp_path):
    insts = [
        i
        for f in ("crossing", "crossing-stall", "patrol", "patrol-walk")
        for i in family("grid", f)
        if i.expected is not None
    ]
    run_sweep(tmp_path / "r.db", make_tasks(insts, ["native"], timeout=60), progress=False)
    with ResultsDB(tmp_path / "r.db") as db:
        for r in db.runs():
            expected = r["setup"]["expected"]
            assert r["status"] == ("solved" if expected == "realizable" else "unrealizable"), r["instance"]


@pytest.mark.slow
@pytest.mark.parametrize("planner", ["rrt", "milp-bigm"])
def test_mazes_baselines(tmp_path, planner):
    insts = family("reach", "maze", [1, 2])
    run_sweep(tmp_path / "m.db", make_tasks(insts, [planner], timeout=120), progress=False)
    with ResultsDB(tmp_path / "m.db") as db:
        for r in db.runs():
            assert r["status"] == "solved" and r["valid"] == 1 and r["segment_safe"] == 1, r["instance"]

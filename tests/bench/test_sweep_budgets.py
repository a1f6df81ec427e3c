"""Bench sweeps: the resume key includes the budget, and the sweep's
arguments are checked before anything is run or written."""

from __future__ import annotations

import json
import sqlite3

import pytest
from typer.testing import CliRunner

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import grid_family
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks
from plansynth.cli import app


def _tasks(timeout=0.5, memory_mb=2048, solver="debug-ok"):
    tasks = make_tasks(grid_family("depth", [1]), [solver], timeout=timeout, memory_mb=memory_mb)
    for t in tasks:
        t["grace"] = 1.0
    return tasks


def _runs(db):
    with ResultsDB(db) as d:
        return d.runs()


def test_a_run_recorded_under_another_budget_is_run_again(tmp_path):
    db = tmp_path / "r.db"
    assert run_sweep(db, _tasks(solver="debug-raise"), progress=False)["crash"] == 1
    # same budget: resumed, nothing to do
    assert run_sweep(db, _tasks(solver="debug-raise"), progress=False) == {"skipped": 1, "done": 0}
    # another time limit: run again, and its row replaces the old one
    counts = run_sweep(db, _tasks(timeout=0.75, solver="debug-raise"), progress=False)
    assert counts["skipped"] == 0 and counts["done"] == 1
    (row,) = _runs(db)
    assert row["attributes"]["timelimit"] == 0.75 and row["attributes"]["memorylimit"] == 2048
    # another memory limit, or none: run again
    assert run_sweep(db, _tasks(timeout=0.75, memory_mb=1024, solver="debug-raise"), progress=False)["done"] == 1
    assert run_sweep(db, _tasks(timeout=0.75, memory_mb=None, solver="debug-raise"), progress=False)["done"] == 1
    assert run_sweep(db, _tasks(timeout=0.75, memory_mb=None, solver="debug-raise"), progress=False)["done"] == 0
    assert len(_runs(db)) == 1  # exactly one row per run, whatever happened


def test_an_older_database_without_the_memory_limit_is_still_resumed(tmp_path):
    db = tmp_path / "old.db"
    run_sweep(db, _tasks(), progress=False)
    with sqlite3.connect(db) as conn:  # as rows were written before the memory limit was kept
        ((rid, attrs),) = conn.execute("SELECT id, attributes FROM runs").fetchall()
        attrs = json.loads(attrs)
        del attrs["memorylimit"]
        conn.execute("UPDATE runs SET attributes = ? WHERE id = ?", (json.dumps(attrs), rid))
        conn.execute("UPDATE experiments SET memorylimit = NULL")
    assert run_sweep(db, _tasks(), progress=False) == {"skipped": 1, "done": 0}
    assert run_sweep(db, _tasks(timeout=2.0), progress=False)["done"] == 1  # its time limit still counts


runner = CliRunner()


@pytest.mark.parametrize(
    ("args", "option", "reason"),
    [
        (["--solvers", "nosuch"], "--solvers", "unknown grid solver 'nosuch'"),
        (["--solvers", ","], "--solvers", "give at least one name"),
        (["--memory", "0"], "--memory", "must be a positive number of MB"),
        (["--timeout", "-1"], "--timeout", "must be a positive number of seconds"),
        (["--timeout", "0"], "--timeout", "must be a positive number of seconds"),
        (["--timeout", "nan"], "--timeout", "must be a positive number of seconds"),
        (["--repeat", "0"], "--repeat", "must be at least 1"),
        (["--jobs", "0"], "--jobs", "must be at least 1"),
        (["--values", "one"], "--values", "expected comma-separated integers"),
    ],
)
def test_bad_grid_sweep_arguments_exit_2_with_one_line_and_write_nothing(tmp_path, args, option, reason):
    db = tmp_path / "b.db"
    r = runner.invoke(
        app,
        [
            "bench",
            "grid",
            "--family",
            "depth",
            "--values",
            "1",
            "--solvers",
            "native",
            "--timeout",
            "5",
            "--db",
            str(db),
            *args,
        ],
    )
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {option}: ") and reason in lines[0], r.output
    assert not db.exists()


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["--planners", "nosuch"], "--planners"),
        (["--orders", "0"], "--orders"),
        (["--orders", "x"], "--orders"),
        (["--memory", "-5"], "--memory"),
    ],
)
def test_bad_reach_sweep_arguments_exit_2(tmp_path, args, option):
    db = tmp_path / "b.db"
    r = runner.invoke(
        app, ["bench", "reach", "--family", "maze", "--values", "1", "--planners", "lazy-smt", "--db", str(db), *args]
    )
    assert r.exit_code == 2, r.output
    assert r.output.strip().startswith(f"error: {option}: ") and len(r.output.strip().splitlines()) == 1, r.output
    assert not db.exists()

"""The results database follows OMPL's benchmark schema (tables and core columns)."""

from __future__ import annotations

import sqlite3

from plansynth.bench.db import RUN_COLUMNS, ResultsDB


def _columns(conn, table):
    return [r[1] for r in conn.execute(f"PRAGMA table_info({table})")]


def test_schema_has_ompl_tables_and_columns(tmp_path):
    path = tmp_path / "r.db"
    ResultsDB(path).close()
    conn = sqlite3.connect(path)
    tables = {r[0] for r in conn.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert {"experiments", "plannerConfigs", "runs", "info"} <= tables
    assert set(_columns(conn, "experiments")) >= {
        "id",
        "name",
        "totaltime",
        "timelimit",
        "memorylimit",
        "runcount",
        "version",
        "hostname",
        "cpuinfo",
        "date",
        "seed",
        "setup",
    }
    assert set(_columns(conn, "plannerConfigs")) == {"id", "name", "settings"}
    runs = set(_columns(conn, "runs"))
    assert {
        "id",
        "experimentid",
        "plannerid",
        "time",
        "status",
        "memory",
        "solved",
        "valid",
        "depth",
        "steps",
        "iterations",
        "lp_calls",
        "sat_calls",
        "horizon",
    } <= runs
    assert set(RUN_COLUMNS) <= runs


def test_runs_round_trip_and_extra_attributes(tmp_path):
    with ResultsDB(tmp_path / "r.db") as db:
        e = db.experiment(
            "reach/maze/maze-1",
            kind="reach",
            family="maze",
            instance="maze-1",
            setup={"params": {"n": 1}},
            timelimit=60,
            runcount=2,
        )
        assert db.experiment("reach/maze/maze-1", kind="reach", family="maze", instance="maze-1", setup={}) == e
        p = db.planner("lazy-smt", {"options": {}})
        db.add_run(
            e, p, 0, {"time": 1.5, "status": "solved", "solved": True, "valid": True, "lp_calls": 7, "my_counter": 3}
        )
        db.add_run(e, p, 1, {"time": 60.0, "status": "unknown", "solved": 0})
        rows = db.runs("reach")
        assert [r["repeat"] for r in rows] == [0, 1]
        assert rows[0]["solved"] == 1 and rows[0]["lp_calls"] == 7
        assert rows[0]["attributes"] == {"my_counter": 3}
        assert rows[0]["planner"] == "lazy-smt" and rows[0]["family"] == "maze"
        assert db.done_keys() == {("reach/maze/maze-1", "lazy-smt", 0), ("reach/maze/maze-1", "lazy-smt", 1)}
        assert db.runs("grid") == []

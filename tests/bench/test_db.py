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


def _db_with(path, runs):
    """A database holding ``runs``: (experiment, planner, repeat, time, date) tuples."""
    with ResultsDB(path) as db:
        for name, planner, repeat, seconds, date in runs:
            fam, inst = name.split("/")[1:]
            e = db.experiment(name, kind="grid", family=fam, instance=inst, setup={"n": inst})
            p = db.planner(planner, {"planner": planner})
            db.add_run(e, p, repeat, {"time": seconds, "status": "solved", "solved": 1, "date": date})


def _times(path):
    with ResultsDB(path) as db:
        return {(r["experiment"], r["planner"], r["repeat"]): r["time"] for r in db.runs()}


def test_merge_unions_runs_and_keeps_the_newer_of_a_shared_one(tmp_path):
    a, b = tmp_path / "a.db", tmp_path / "b.db"
    _db_with(a, [("grid/f/x", "native", 0, 1.0, "2026-01-01 00:00:00"), ("grid/f/y", "native", 0, 2.0, "2026-01-01")])
    _db_with(b, [("grid/f/x", "native", 0, 5.0, "2026-02-01 00:00:00"), ("grid/g/z", "cvc5", 1, 3.0, "2026-01-01")])
    b_before = _times(b)
    with ResultsDB(a) as db:
        assert db.merge(b) == 2
        assert db.merge(b) == 0  # nothing newer the second time
    assert _times(a) == {
        ("grid/f/x", "native", 0): 5.0,  # b's run is newer
        ("grid/f/y", "native", 0): 2.0,
        ("grid/g/z", "cvc5", 1): 3.0,
    }
    assert _times(b) == b_before  # the source is left as it was
    with ResultsDB(b) as db:  # the other way round: a's older run does not replace b's
        db.merge(a)
    assert _times(b)[("grid/f/x", "native", 0)] == 5.0
    with ResultsDB(a) as db:
        (row,) = [r for r in db.runs() if r["experiment"] == "grid/g/z"]
        assert (row["family"], row["setup"]) == ("g", {"n": "z"})


def test_merge_names_a_missing_source(tmp_path):
    import pytest

    from plansynth.bench.errors import NoDatabase

    with ResultsDB(tmp_path / "a.db") as db, pytest.raises(NoDatabase, match="missing.db: no such results database"):
        db.merge(tmp_path / "missing.db")
    assert not (tmp_path / "missing.db").exists()

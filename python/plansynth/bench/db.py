"""The benchmark results database (SQLite), modelled on OMPL's benchmark database.

OMPL's ``ompl_benchmark_statistics.py`` writes one SQLite file that Planner Arena and
other tools read; we keep its table and column names so those tools (and plain SQL)
can read ours. One file, no server; every run is committed as soon as it finishes, so an
interrupted sweep loses at most the runs in flight and resumes where it stopped.

Schema
------

``experiments`` -- one row per problem instance of a sweep (OMPL: one per problem)::

    id INTEGER PRIMARY KEY, name TEXT UNIQUE      -- "<kind>/<family>/<instance>", e.g. "grid/steps/steps-10"
    totaltime REAL, timelimit REAL, memorylimit REAL, runcount INTEGER,
    version TEXT, hostname TEXT, cpuinfo TEXT, date TEXT, seed INTEGER,
    setup TEXT                                   -- the instance as JSON (kind, family, params)
    kind TEXT, family TEXT, instance TEXT        -- plansynth additions

``plannerConfigs`` -- one row per solver/planner configuration (OMPL's name)::

    id INTEGER PRIMARY KEY, name TEXT UNIQUE, settings TEXT (JSON options)

``runs`` -- one row per finished run (the OMPL attribute columns, plus ours)::

    id INTEGER PRIMARY KEY, experimentid INTEGER, plannerid INTEGER,
    repeat INTEGER                              -- the repeat index (resume key part)
    time REAL                                   -- seconds the solver reported (wall clock of the child if none)
    wall REAL                                   -- wall-clock seconds of the child process
    status TEXT                                 -- solved | unrealizable | infeasible | unknown | timeout | memout | crash | invalid | unavailable
    solved INTEGER                              -- 1 iff a plan/controller was returned AND independently validated
    valid INTEGER                               -- validator verdict on a returned plan (NULL if none)
    memory REAL                                 -- peak resident memory of the child, MB
    depth INTEGER, size INTEGER, steps INTEGER  -- grid: program depth and size, path length l
    horizon INTEGER, segment_safe INTEGER       -- reach: trajectory length N, segment safety
    iterations INTEGER, lp_calls INTEGER, sat_calls INTEGER, regions INTEGER
    solver_version TEXT, message TEXT, attributes TEXT (every counter as JSON)
    date TEXT

Resume key: (experiment name = kind/family/instance, planner name, repeat); a run is
done when a row exists for it with the same budget (``attributes`` keeps the run's
``timelimit`` and ``memorylimit``; rows written before the memory limit was kept fall
back to the experiment's), whatever its status.

``info`` -- key/value pairs about the database (schema version, machine).

>>> import tempfile, os
>>> with tempfile.TemporaryDirectory() as d:
...     db = ResultsDB(os.path.join(d, "r.db"))
...     e = db.experiment("grid/depth/depth-1", kind="grid", family="depth", instance="depth-1", setup={})
...     p = db.planner("native", {})
...     db.add_run(e, p, 0, {"time": 0.1, "status": "solved", "solved": 1})
...     db.done_keys() == {("grid/depth/depth-1", "native", 0)}
True
"""

from __future__ import annotations

import json
import sqlite3
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["ResultsDB", "RUN_COLUMNS", "SCHEMA_VERSION", "UNRECORDED"]

#: A budget that an older database did not record (see :meth:`ResultsDB.recorded_budgets`).
UNRECORDED = "unrecorded"

SCHEMA_VERSION = 1

#: Attribute columns of ``runs`` (name -> SQL type).
RUN_COLUMNS: dict[str, str] = {
    "repeat": "INTEGER",
    "time": "REAL",
    "wall": "REAL",
    "status": "TEXT",
    "solved": "INTEGER",
    "valid": "INTEGER",
    "memory": "REAL",
    "depth": "INTEGER",
    "size": "INTEGER",
    "steps": "INTEGER",
    "horizon": "INTEGER",
    "segment_safe": "INTEGER",
    "iterations": "INTEGER",
    "lp_calls": "INTEGER",
    "sat_calls": "INTEGER",
    "regions": "INTEGER",
    "solver_version": "TEXT",
    "message": "TEXT",
    "attributes": "TEXT",
    "date": "TEXT",
}

_SCHEMA = f"""
CREATE TABLE IF NOT EXISTS info (key TEXT PRIMARY KEY, value TEXT);
CREATE TABLE IF NOT EXISTS experiments (
    id INTEGER PRIMARY KEY AUTOINCREMENT, name TEXT UNIQUE NOT NULL,
    totaltime REAL, timelimit REAL, memorylimit REAL, runcount INTEGER,
    version TEXT, hostname TEXT, cpuinfo TEXT, date TEXT, seed INTEGER, setup TEXT,
    kind TEXT, family TEXT, instance TEXT);
CREATE TABLE IF NOT EXISTS plannerConfigs (
    id INTEGER PRIMARY KEY AUTOINCREMENT, name TEXT UNIQUE NOT NULL, settings TEXT);
CREATE TABLE IF NOT EXISTS runs (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    experimentid INTEGER REFERENCES experiments(id) ON DELETE CASCADE,
    plannerid INTEGER REFERENCES plannerConfigs(id) ON DELETE CASCADE,
    {", ".join(f'"{c}" {t}' for c, t in RUN_COLUMNS.items())},
    UNIQUE (experimentid, plannerid, "repeat"));
"""


class ResultsDB:
    """A results database file (created with the schema if it does not exist)."""

    def __init__(self, path: str | Path) -> None:
        from plansynth.errors import OutputUnwritable

        self.path = Path(path)
        if not self.path.parent.is_dir():  # (as for every output: the folder must exist)
            raise OutputUnwritable(str(self.path), "folder does not exist")
        try:
            self.conn = sqlite3.connect(str(self.path), timeout=30.0)
            self.conn.row_factory = sqlite3.Row
            self.conn.executescript(_SCHEMA)
            self.conn.execute("INSERT OR IGNORE INTO info VALUES ('schema_version', ?)", (str(SCHEMA_VERSION),))
            self.conn.commit()
        except sqlite3.DatabaseError as exc:  # not SQLite, a directory, a file it may not open
            raise OutputUnwritable(str(self.path), f"not a results database ({exc})") from None

    def close(self) -> None:
        self.conn.close()

    def __enter__(self) -> ResultsDB:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ writing

    def set_info(self, values: Mapping[str, Any]) -> None:
        self.conn.executemany(
            "INSERT OR REPLACE INTO info VALUES (?, ?)",
            [(k, v if isinstance(v, str) else json.dumps(v)) for k, v in values.items()],
        )
        self.conn.commit()

    def experiment(
        self,
        name: str,
        *,
        kind: str,
        family: str,
        instance: str,
        setup: Mapping[str, Any],
        timelimit: float | None = None,
        memorylimit: float | None = None,
        runcount: int | None = None,
        machine: Mapping[str, Any] | None = None,
        seed: int | None = None,
    ) -> int:
        """The id of experiment ``name``, created (or its limits updated) as needed."""
        row = self.conn.execute("SELECT id FROM experiments WHERE name = ?", (name,)).fetchone()
        m = dict(machine or {})
        if row is None:
            cur = self.conn.execute(
                "INSERT INTO experiments (name, totaltime, timelimit, memorylimit, runcount, version, hostname,"
                " cpuinfo, date, seed, setup, kind, family, instance) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                (
                    name,
                    0.0,
                    timelimit,
                    memorylimit,
                    runcount,
                    m.get("version"),
                    m.get("hostname"),
                    m.get("cpuinfo"),
                    time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
                    seed,
                    json.dumps(dict(setup), sort_keys=True),
                    kind,
                    family,
                    instance,
                ),
            )
            self.conn.commit()
            return int(cur.lastrowid)
        self.conn.execute(
            "UPDATE experiments SET timelimit = COALESCE(?, timelimit), memorylimit = COALESCE(?, memorylimit),"
            " runcount = MAX(COALESCE(runcount, 0), COALESCE(?, 0)) WHERE id = ?",
            (timelimit, memorylimit, runcount, row["id"]),
        )
        self.conn.commit()
        return int(row["id"])

    def planner(self, name: str, settings: Mapping[str, Any]) -> int:
        row = self.conn.execute("SELECT id FROM plannerConfigs WHERE name = ?", (name,)).fetchone()
        if row is not None:
            return int(row["id"])
        cur = self.conn.execute(
            "INSERT INTO plannerConfigs (name, settings) VALUES (?, ?)",
            (name, json.dumps(dict(settings), sort_keys=True)),
        )
        self.conn.commit()
        return int(cur.lastrowid)

    def add_run(self, experiment_id: int, planner_id: int, repeat: int, attrs: Mapping[str, Any]) -> None:
        """Record one finished run (committed at once). Unknown keys go to ``attributes``."""
        cols = {k: attrs[k] for k in RUN_COLUMNS if k in attrs and k not in ("repeat", "attributes")}
        extra = {k: v for k, v in attrs.items() if k not in RUN_COLUMNS}
        if "attributes" in attrs:
            extra.update(attrs["attributes"])
        cols["repeat"] = repeat
        cols["attributes"] = json.dumps(extra, sort_keys=True, default=str)
        cols.setdefault("date", time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()))
        for k in ("solved", "valid", "segment_safe"):
            if isinstance(cols.get(k), bool):
                cols[k] = int(cols[k])
        names = ", ".join(f'"{c}"' for c in cols)
        marks = ", ".join("?" for _ in cols)
        self.conn.execute(
            f"INSERT OR REPLACE INTO runs (experimentid, plannerid, {names}) VALUES (?, ?, {marks})",
            (experiment_id, planner_id, *cols.values()),
        )
        self.conn.execute(
            "UPDATE experiments SET totaltime = totaltime + ? WHERE id = ?",
            (float(cols.get("wall") or 0.0), experiment_id),
        )
        self.conn.commit()

    def merge(self, other: str | Path) -> int:
        """Copy every run of the database file ``other`` into this one; returns how many
        runs were copied.

        Runs are matched by the resume key (experiment name, planner name, repeat); a run
        present in both is replaced only when ``other``'s is newer (its ``date``), so two
        sweeps run on separate machines or branches merge into one file in either order.
        Experiments and planner configurations are created by name as needed.
        """
        if not Path(other).is_file():
            from plansynth.bench.errors import NoDatabase

            raise NoDatabase(str(other))
        src = ResultsDB(other)
        try:
            exps = {r["name"]: dict(r) for r in src.conn.execute("SELECT * FROM experiments")}
            planners = {
                r["id"]: (r["name"], json.loads(r["settings"] or "{}"))
                for r in src.conn.execute("SELECT * FROM plannerConfigs")
            }
            mine = {
                (a, b, int(c)): d
                for a, b, c, d in self.conn.execute(
                    'SELECT e.name, p.name, r."repeat", r.date FROM runs r JOIN experiments e'
                    " ON r.experimentid = e.id JOIN plannerConfigs p ON r.plannerid = p.id"
                )
            }
            ids = {r["id"]: r["name"] for r in exps.values()}
            copied = 0
            for row in src.conn.execute("SELECT * FROM runs ORDER BY id"):
                run = dict(row)
                name, (planner, settings) = ids[run["experimentid"]], planners[run["plannerid"]]
                key = (name, planner, int(run["repeat"]))
                if key in mine and (mine[key] or "") >= (run["date"] or ""):
                    continue
                eid = self._experiment_row(exps[name])
                pid = self.planner(planner, settings)
                names = ", ".join(f'"{c}"' for c in RUN_COLUMNS)
                marks = ", ".join("?" for _ in RUN_COLUMNS)
                self.conn.execute(
                    f"INSERT OR REPLACE INTO runs (experimentid, plannerid, {names}) VALUES (?, ?, {marks})",
                    (eid, pid, *(run[c] for c in RUN_COLUMNS)),
                )
                copied += 1
            self.conn.commit()
            return copied
        finally:
            src.close()

    def _experiment_row(self, e: Mapping[str, Any]) -> int:
        """The id of the experiment named ``e["name"]``, copied from row ``e`` when absent."""
        row = self.conn.execute("SELECT id FROM experiments WHERE name = ?", (e["name"],)).fetchone()
        if row is not None:
            return int(row["id"])
        cols = [c for c in e if c != "id"]
        cur = self.conn.execute(
            f"INSERT INTO experiments ({', '.join(cols)}) VALUES ({', '.join('?' for _ in cols)})",
            tuple(e[c] for c in cols),
        )
        return int(cur.lastrowid)

    # ------------------------------------------------------------------ reading

    def done_keys(self, retry: Iterable[str] = ()) -> set[tuple[str, str, int]]:
        """(experiment name, planner name, repeat) of every recorded run: the resume key.

        Runs whose status is in ``retry`` (for example ``crash``) are left out, so that a
        resumed sweep runs them again (the new row replaces the old one).
        """
        retry = tuple(retry)
        q = (
            'SELECT e.name, p.name, r."repeat" FROM runs r JOIN experiments e ON r.experimentid = e.id'
            " JOIN plannerConfigs p ON r.plannerid = p.id"
        )
        if retry:
            q += f" WHERE r.status NOT IN ({', '.join('?' for _ in retry)})"
        rows = self.conn.execute(q, retry)
        return {(a, b, int(c)) for a, b, c in rows}

    def recorded_budgets(self, retry: Iterable[str] = ()) -> dict[tuple[str, str, int], tuple[Any, Any, Any]]:
        """The resume key of every recorded run (as :meth:`done_keys`) -> the (time limit,
        memory limit, solver options) it ran with (None: no limit; :data:`UNRECORDED` or a
        None time limit: the database does not say, and the run counts as done under any
        budget or options)."""
        retry = tuple(retry)
        q = (
            'SELECT e.name, p.name, r."repeat", r.attributes, e.timelimit, e.memorylimit FROM runs r'
            " JOIN experiments e ON r.experimentid = e.id JOIN plannerConfigs p ON r.plannerid = p.id"
        )
        if retry:
            q += f" WHERE r.status NOT IN ({', '.join('?' for _ in retry)})"
        out: dict[tuple[str, str, int], tuple[Any, Any, Any]] = {}
        for a, b, c, attributes, e_time, e_memory in self.conn.execute(q, retry):
            try:
                attrs = json.loads(attributes or "{}")
            except ValueError:
                attrs = {}
            attrs = attrs if isinstance(attrs, dict) else {}
            timelimit = attrs.get("timelimit", e_time)
            # None in attributes: the run had no memory limit; absent (older rows): the
            # experiment's limit, else UNRECORDED
            memorylimit = (
                attrs["memorylimit"] if "memorylimit" in attrs else (UNRECORDED if e_memory is None else e_memory)
            )
            out[(a, b, int(c))] = (timelimit, memorylimit, attrs.get("options", UNRECORDED))
        return out

    def runs(self, kind: str | None = None) -> list[dict[str, Any]]:
        """Every run joined with its experiment and planner, as plain dicts."""
        q = (
            "SELECT r.*, e.name AS experiment, e.kind, e.family, e.instance, e.setup, e.timelimit,"
            " p.name AS planner FROM runs r JOIN experiments e ON r.experimentid = e.id"
            " JOIN plannerConfigs p ON r.plannerid = p.id"
        )
        args: Iterable[Any] = ()
        if kind is not None:
            q += " WHERE e.kind = ?"
            args = (kind,)
        out = []
        for row in self.conn.execute(q + " ORDER BY r.id", tuple(args)):
            d = dict(row)
            d["attributes"] = json.loads(d["attributes"] or "{}")
            d["setup"] = json.loads(d["setup"] or "{}")
            out.append(d)
        return out

    def run_count(self) -> int:
        """How many runs the database holds."""
        return int(self.conn.execute("SELECT COUNT(*) FROM runs").fetchone()[0])

    def info(self) -> dict[str, str]:
        return {k: v for k, v in self.conn.execute("SELECT key, value FROM info")}

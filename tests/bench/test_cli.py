"""`plansynth bench` commands, end to end on tiny sweeps."""

from __future__ import annotations

from typer.testing import CliRunner

from plansynth.bench.db import ResultsDB
from plansynth.cli import app

runner = CliRunner()


def test_grid_sweep_then_report(tmp_path):
    db = tmp_path / "b.db"
    r = runner.invoke(
        app,
        [
            "bench",
            "grid",
            "--family",
            "depth",
            "--values",
            "1,4",
            "--solvers",
            "native",
            "--timeout",
            "20",
            "--db",
            str(db),
        ],
    )
    assert r.exit_code == 0, r.output
    assert "2 runs" in r.output and "solved 2" in r.output
    # rerunning resumes: nothing left to do
    r = runner.invoke(
        app,
        [
            "bench",
            "grid",
            "--family",
            "depth",
            "--values",
            "1,4",
            "--solvers",
            "native",
            "--timeout",
            "20",
            "--db",
            str(db),
        ],
    )
    assert "skipped 2" in r.output and "done 0" in r.output
    with ResultsDB(db) as d:
        assert {row["status"] for row in d.runs()} == {"solved"}
    out = tmp_path / "rep"
    r = runner.invoke(app, ["bench", "report", "--db", str(db), "--out", str(out)])
    assert r.exit_code == 0, r.output
    text = (out / "REPORT.md").read_text()
    assert "Figure 2: time vs program depth" in text and "| depth-1 | 0.061 |" in text
    assert (out / "grid-depth.png").exists()


def test_bad_family_and_missing_db_are_exit_2(tmp_path):
    r = runner.invoke(app, ["bench", "grid", "--family", "nope", "--db", str(tmp_path / "b.db")])
    assert r.exit_code == 2 and "unknown grid family" in r.output
    r = runner.invoke(app, ["bench", "report", "--db", str(tmp_path / "none.db")])
    assert r.exit_code == 2


def test_families_writes_problem_files(tmp_path):
    r = runner.invoke(app, ["bench", "families", "--out", str(tmp_path)])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "grid" / "steps" / "steps-25.yaml").exists()
    assert (tmp_path / "grid" / "crossing" / "crossing-2.yaml").read_text().startswith("# plansynth bench family")
    assert (tmp_path / "reach" / "maze" / "maze-4.yaml").exists()


def test_a_bad_database_or_value_is_one_line_and_exit_2(tmp_path):
    """Not SQLite, a folder that does not exist, a family value it lacks: one line and
    exit 2, not a traceback (found by a review; the missing folder used to be created)."""
    junk = tmp_path / "junk.db"
    junk.write_text("not a database\n")
    cases = [
        (["bench", "grid", "--family", "figure1", "--solvers", "native", "--db", str(junk)], "not a results database"),
        (["bench", "report", "--db", str(junk), "--out", str(tmp_path / "rep")], "not a results database"),
        (
            ["bench", "grid", "--family", "figure1", "--solvers", "native", "--db", str(tmp_path / "no" / "x.db")],
            "folder does not exist",
        ),
        (
            [
                "bench",
                "reach",
                "--family",
                "maze",
                "--values",
                "0",
                "--planners",
                "lazy-smt",
                "--db",
                str(tmp_path / "v.db"),
            ],
            "--values",
        ),
    ]
    for args, fragment in cases:
        r = CliRunner().invoke(app, args)
        assert r.exit_code == 2 and fragment in r.output and "Traceback" not in r.output, (args, r.output)
    assert not (tmp_path / "no").exists()


def test_a_report_of_a_database_without_runs_is_refused_and_writes_nothing(tmp_path):
    """`bench report` on a database with no runs wrote an empty report and exit 0: now
    one line naming the file, exit 2, and no output folder (nor `publish --report-only`)."""
    import pytest

    from plansynth.bench.errors import NoRuns
    from plansynth.bench.report import write_report

    db = tmp_path / "empty.db"
    with ResultsDB(db) as d:  # the schema and an experiment, as a sweep stopped before its first run leaves it
        d.experiment("grid/depth/depth-1", kind="grid", family="depth", instance="depth-1", setup={})
    for args, out in (
        (["bench", "report"], tmp_path / "rep"),
        (["bench", "publish", "--report-only"], tmp_path / "pub"),
    ):
        r = CliRunner().invoke(app, [*args, "--db", str(db), "--out", str(out)])
        assert r.exit_code == 2, r.output
        (line,) = r.output.strip().splitlines()
        assert "empty.db" in line and "holds no runs" in line and "Traceback" not in r.output
        assert not out.exists()
    with pytest.raises(NoRuns, match="empty.db: the results database holds no runs"):
        write_report(db, tmp_path / "api")
    assert not (tmp_path / "api").exists()


def test_merge_copies_a_sweep_into_another_database(tmp_path):
    db = tmp_path / "b.db"
    r = runner.invoke(
        app, ["bench", "grid", "--family", "depth", "--values", "1", "--solvers", "native", "--db", str(db)]
    )
    assert r.exit_code == 0, r.output
    merged = tmp_path / "merged.db"
    r = runner.invoke(app, ["bench", "merge", str(db), "--db", str(merged)])
    assert r.exit_code == 0, r.output
    assert f"{db}: 1 runs merged into {merged}" in " ".join(r.output.split())
    with ResultsDB(db) as a, ResultsDB(merged) as b:
        assert [(x["experiment"], x["planner"], x["status"]) for x in a.runs()] == [
            (x["experiment"], x["planner"], x["status"]) for x in b.runs()
        ]
    r = runner.invoke(app, ["bench", "merge", str(tmp_path / "none.db"), "--db", str(merged)])
    assert r.exit_code == 2 and "none.db: no such results database" in " ".join(r.output.split())

"""Outputs, certification and claims: every output file is checked
before the work and written atomically; unwritable outputs exit 2 with one line that
names the path; an ``unrealizable`` is certified by the native engine; a validation
tolerance must be sane and a file's segment-safety claim is checked; an exported
function name must be an identifier."""

from __future__ import annotations

import errno
import json
import os
import resource
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from plansynth.cli import app
from plansynth.errors import OutputUnwritable
from plansynth.io import check_output_folder, check_output_path, write_output
from plansynth.reach.families import maze
from plansynth.reach.fileformat import reach_problem_to_dict

runner = CliRunner()
ROOT = Path(__file__).parents[1]
FIGURE1 = ROOT / "examples" / "grid" / "figure1.yaml"
PROGRAM = "(ite (<= 4 rx) 1 2)"  # figure1's controller at l = 6


@pytest.fixture(scope="module")
def maze1(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("reach") / "maze-1.yaml"
    path.write_text(yaml.safe_dump(reach_problem_to_dict(maze(1))), encoding="utf-8")
    return path


def _unwritable(tmp_path: Path) -> dict[str, str]:
    """Output paths that cannot be written, and a word of the reason each must give."""
    (tmp_path / "a-folder").mkdir()
    return {
        str(tmp_path / "missing" / "r.json"): "does not exist",
        "/proc/r.json": "cannot write /proc/r.json",
        str(tmp_path / "a-folder"): "is a folder",
        "/dev/full": "not a regular file",
    }


def _one_line_error(r, path: str, word: str) -> None:
    assert r.exit_code == 2, r.output
    assert r.exception is None or isinstance(r.exception, SystemExit)
    assert "Traceback" not in r.output
    lines = [ln for ln in r.output.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and f"cannot write {path}" in lines[0] and word in lines[0], r.output


@pytest.mark.parametrize("case", range(4))
def test_unwritable_outputs_exit_2_before_the_work(tmp_path: Path, maze1: Path, case: int) -> None:
    path, word = list(_unwritable(tmp_path).items())[case]
    commands = [
        ["grid", "solve", str(FIGURE1), "--out", path],
        ["grid", "compile", str(FIGURE1), "--steps", "6", "--output", path],
        ["grid", "animate", str(FIGURE1), PROGRAM, "--steps", "6", "--out", path],
        ["grid", "animate", str(FIGURE1), PROGRAM, "--steps", "6", "--out", str(tmp_path / "ok.gif"), "--png", path],
        ["grid", "export", PROGRAM, "--lang", "c", "--problem", str(FIGURE1), "--out", path],
        ["reach", "solve", str(maze1), "--out", path],
        ["reach", "solve", str(maze1), "--plot", path],
        ["reach", "plot", str(maze1), "--output", path],
    ]
    for argv in commands:
        r = runner.invoke(app, argv)
        _one_line_error(r, path, word)
        # checked before solving: no answer was printed and then lost
        assert "realizable" not in r.output and "found" not in r.output
    assert not (tmp_path / "ok.gif").exists()  # nothing written when one output is bad


def test_keep_sl_must_be_a_folder(tmp_path: Path) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    r = runner.invoke(app, ["grid", "solve", str(FIGURE1), "--solver", "cvc5", "--steps", "6", "--keep-sl", str(f)])
    assert r.exit_code == 2 and f"cannot write {f}: not a folder" in r.output


def test_bench_report_folder_must_be_writable(tmp_path: Path) -> None:
    f = tmp_path / "file"
    f.write_text("x")
    db = tmp_path / "r.db"
    db.write_bytes(b"")
    r = runner.invoke(app, ["bench", "report", "--db", str(db), "--out", str(f)])
    assert r.exit_code == 2 and f"cannot write {f}: not a folder" in r.output


def test_file_size_limit_leaves_no_truncated_file(tmp_path: Path) -> None:
    """``ulimit -f``: SIGXFSZ is ignored, the write fails with EFBIG, exit 2, and the
    old file (here: none) is untouched, with no temporary file left behind."""
    out = tmp_path / "r.json"

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (200, 200))

    p = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "grid", "solve", str(FIGURE1), "--steps", "6", "--out", str(out)],
        capture_output=True,
        text=True,
        preexec_fn=limit,
        timeout=120,
    )
    assert p.returncode == 2, p.stdout + p.stderr
    assert "Traceback" not in p.stderr and f"cannot write {out}: file too large" in p.stderr
    assert list(tmp_path.iterdir()) == []
    # an existing result keeps its whole old content
    out.write_text('{"old": true}\n')
    p = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "grid", "solve", str(FIGURE1), "--steps", "6", "--out", str(out)],
        capture_output=True,
        text=True,
        preexec_fn=limit,
        timeout=120,
    )
    assert p.returncode == 2 and out.read_text() == '{"old": true}\n'
    assert sorted(x.name for x in tmp_path.iterdir()) == ["r.json"]


def test_write_output_is_atomic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "a.json"
    write_output(out, "old\n")

    def full(*_args: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(OutputUnwritable, match="no space left on the device"):
        write_output(out, "new\n")
    assert out.read_text() == "old\n" and sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]


def test_output_checks_name_the_reason(tmp_path: Path) -> None:
    with pytest.raises(OutputUnwritable, match="does not exist"):
        check_output_path(tmp_path / "no" / "x.json")
    with pytest.raises(OutputUnwritable, match="is a folder"):
        check_output_path(tmp_path)
    with pytest.raises(OutputUnwritable, match="not a regular file"):
        check_output_path("/dev/null")
    assert check_output_folder(tmp_path / "new" / "sub").is_dir()
    assert check_output_path(tmp_path / "x.json") == tmp_path / "x.json" and list(tmp_path.glob(".x.json*")) == []


# ---------------------------------------------------------------- certified unrealizable


def _script(tmp_path: Path, text: str) -> str:
    path = tmp_path / "solver.sh"
    path.write_text("#!/bin/sh\n" + text)
    path.chmod(0o755)
    return f"{path} {{file}}"


@pytest.mark.parametrize(
    "body", ["echo infeasible\n", 'echo "(error \\"boom\\")"\nkill -SEGV $$\n', "echo infeasible\nkill -SEGV $$\n"]
)
def test_a_lying_external_solver_never_makes_unrealizable(tmp_path: Path, body: str) -> None:
    r = runner.invoke(
        app,
        ["grid", "solve", str(FIGURE1), "--steps", "6", "--solver", "external", "--command", _script(tmp_path, body)],
    )
    assert r.exit_code == 3 and "\nunknown (external command" in r.output, r.output


def test_unrealizable_claims_are_certified_by_the_native_engine(tmp_path: Path) -> None:
    out = tmp_path / "r.json"
    r = runner.invoke(
        app,
        [
            "grid",
            "solve",
            str(FIGURE1),
            "--steps",
            "6",
            "--solver",
            "external",
            "--command",
            _script(tmp_path, "echo infeasible\n"),
            "--out",
            str(out),
        ],
    )
    assert r.exit_code == 3 and "BACKEND ERROR: external claims unrealizable at l = 6" in r.output
    assert "(ite (<= 4 rx) 1 2)" in r.output and json.loads(out.read_text())["certified_by"] is None
    # at l = 5 there is no controller: the claim is certified, and the result says so
    r = runner.invoke(
        app,
        [
            "grid",
            "solve",
            str(FIGURE1),
            "--steps",
            "5",
            "--solver",
            "external",
            "--command",
            _script(tmp_path, "echo infeasible\n"),
            "--out",
            str(out),
        ],
    )
    assert r.exit_code == 1 and "certified by the native engine" in r.output
    doc = json.loads(out.read_text())
    assert doc["status"] == "unrealizable" and doc["certified_by"] == "native"
    assert doc["attempts"][0]["counters"]["certified_by"] == "native"


def test_cvc5_unrealizable_is_certified_too() -> None:
    r = runner.invoke(app, ["grid", "solve", str(FIGURE1), "--steps", "5", "--solver", "cvc5", "--depth-bound", "4"])
    assert r.exit_code == 1 and "certified by the native engine" in r.output


# ---------------------------------------------------------------- validation claims


def _result(tmp_path: Path, states: list, inputs: list, **extra: object) -> Path:
    path = tmp_path / "r.json"
    path.write_text(json.dumps({"status": "found", "states": states, "inputs": inputs, **extra}))
    return path


def _corner_problem(tmp_path: Path) -> Path:
    """A 4x4 workspace, obstacle [1,3]^2, single integrator: (0,0) -> (3.5,3.5) cuts it."""
    doc = {
        "workspace": {"min": [0, 0], "max": [4, 4]},
        "obstacles": [{"min": [1, 1], "max": [3, 3]}],
        "goal": {"min": [3, 3], "max": [4, 4]},
        "robot": {"dynamics": {"model": "single-integrator", "dt": 1.0}, "start": [0, 0], "input_bound": 4},
    }
    path = tmp_path / "corner.yaml"
    path.write_text(yaml.safe_dump(doc))
    return path


@pytest.mark.parametrize("tol", ["inf", "nan", "-1e-6", "0.5"])
def test_validate_refuses_an_insane_tolerance(tmp_path: Path, tol: str) -> None:
    p = _corner_problem(tmp_path)
    leaves = _result(tmp_path, [[0, 0], [3.5, 9.0]], [[3.5, 9.0]])  # leaves the workspace
    r = runner.invoke(app, ["reach", "validate", str(p), str(leaves), "--tol", tol])
    assert r.exit_code == 2 and "--tol" in r.output and "segment-safe" not in r.output, r.output
    r = runner.invoke(app, ["reach", "validate", str(p), str(leaves)])
    assert r.exit_code == 1 and "INVALID" in r.output and "workspace" in r.output


def test_validate_checks_a_claimed_segment_safety(tmp_path: Path) -> None:
    p = _corner_problem(tmp_path)
    states, inputs = [[0, 0], [3.5, 3.5]], [[3.5, 3.5]]
    r = runner.invoke(app, ["reach", "validate", str(p), str(_result(tmp_path, states, inputs))])
    assert r.exit_code == 0 and "valid" in r.output and "not segment-safe" in r.output
    r = runner.invoke(app, ["reach", "validate", str(p), str(_result(tmp_path, states, inputs, segment_safe=True))])
    assert r.exit_code == 1 and "INVALID" in r.output and "claims segment safety" in r.output
    r = runner.invoke(app, ["reach", "validate", str(p), str(_result(tmp_path, states, inputs, segment_safe="yes"))])
    assert r.exit_code == 2 and "segment_safe: expected true or false" in r.output


# ---------------------------------------------------------------- export --name


@pytest.mark.parametrize(
    ("lang", "name"),
    [
        ("c", "f(); system(0); int g"),
        ("c", "for"),
        ("c", "int"),
        ("python", "lambda"),
        ("python", "x y"),
        ("python", "1st"),
        ("sygus", "ite"),
        ("sygus", "define-fun"),
        ("c", "rx"),
        ("python", "mövé"),
    ],
)
def test_export_name_must_be_an_identifier(lang: str, name: str) -> None:
    r = runner.invoke(app, ["grid", "export", PROGRAM, "--lang", lang, "--problem", str(FIGURE1), "--name", name])
    assert r.exit_code == 2 and "--name:" in r.output and "Traceback" not in r.output, r.output


def test_export_with_a_good_name_runs() -> None:
    r = runner.invoke(
        app, ["grid", "export", PROGRAM, "--lang", "python", "--problem", str(FIGURE1), "--name", "go_right"]
    )
    assert r.exit_code == 0
    namespace: dict = {}
    exec(r.output, namespace)  # noqa: S102 - our own exporter's output
    assert namespace["go_right"](5, 0, 0, 0, 0, 0) == 1 and namespace["go_right"](0, 0, 0, 0, 0, 0) == 2

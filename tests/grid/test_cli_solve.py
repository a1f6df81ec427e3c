"""``plansynth grid solve`` and ``plansynth grid compile`` from the command line."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from typer.testing import CliRunner

from plansynth.cli import app
from plansynth.grid.problem import load_grid_problem
from plansynth.grid.programs import parse_program
from plansynth.grid.sygus import compile_sygus
from plansynth.grid.verify import verify

EXAMPLES = Path(__file__).parents[2] / "examples" / "grid"
FIGURE1 = EXAMPLES / "figure1.yaml"
runner = CliRunner()


def _corridor(tmp_path: Path, extra: str = "") -> Path:
    p = tmp_path / "corridor.yaml"
    p.write_text("grid: [3, 1]\nrobot: {start: [0, 0], goal: [2, 0], moves: [stay, right]}\nmax_steps: 3\n" + extra)
    return p


def test_solve_figure1_with_cvc5(tmp_path: Path) -> None:
    out = tmp_path / "result.json"
    res = runner.invoke(
        app,
        [
            "grid",
            "solve",
            str(FIGURE1),
            "--solver",
            "cvc5",
            "--steps",
            "6",
            "-O",
            "sygus-enum=fast",
            "--out",
            str(out),
            "--keep-sl",
            str(tmp_path / "sl"),
        ],
    )
    assert res.exit_code == 0, res.output
    assert "realizable at l = 6" in res.output
    assert "verified by the independent verifier" in res.output
    assert "def move(rx: int, ry: int, o0x: int, o0y: int, o1x: int, o1y: int) -> int:" in res.output
    doc = json.loads(out.read_text())
    assert doc["status"] == "realizable" and doc["steps"] == 6 and doc["verified"] is True
    assert doc["solver"] == "cvc5" and doc["options"] == {
        "options": ["sygus-enum=fast"],
        "keep_sl": str(tmp_path / "sl"),
    }
    problem = load_grid_problem(FIGURE1)
    assert verify(problem, parse_program(doc["program"]), 6).wins
    assert (tmp_path / "sl" / "figure1-l6.sl").read_text() == compile_sygus(problem, 6)


def test_solve_exit_statuses(tmp_path: Path) -> None:
    corridor = _corridor(tmp_path)
    res = runner.invoke(app, ["grid", "solve", str(corridor), "-s", "cvc5", "--steps", "1"])
    assert res.exit_code == 1 and "unrealizable" in res.output and "no controller wins at l = 1" in res.output
    res = runner.invoke(app, ["grid", "solve", str(FIGURE1), "-s", "cvc5", "--steps", "6", "--timeout", "0.5"])
    assert res.exit_code == 3 and "unknown" in res.output and "time budget" in res.output
    res = runner.invoke(app, ["grid", "solve", str(tmp_path / "missing.yaml"), "-s", "cvc5"])
    assert res.exit_code == 2 and "missing.yaml: <file>: cannot read" in res.output


def test_solve_with_an_external_command(tmp_path: Path) -> None:
    cmd = f"{sys.executable} -m plansynth.grid.backends.cvc5_cli {{file}}"
    res = runner.invoke(app, ["grid", "solve", str(_corridor(tmp_path)), "-s", "external", "--command", cmd])
    assert res.exit_code == 0, res.output
    assert "realizable at l = 2" in res.output


def test_solve_rejects_mismatched_options(tmp_path: Path) -> None:
    corridor = str(_corridor(tmp_path))
    res = runner.invoke(app, ["grid", "solve", corridor, "-s", "cvc5", "--command", "x"])
    assert res.exit_code == 2 and "--command is for --solver external" in res.output
    res = runner.invoke(app, ["grid", "solve", corridor, "-s", "external"])
    assert res.exit_code == 2 and "give the solver's command line" in res.output
    res = runner.invoke(app, ["grid", "solve", corridor, "-s", "nope"])
    assert res.exit_code == 2 and "unknown grid solver" in res.output
    res = runner.invoke(app, ["grid", "solve", corridor, "-s", "cvc5", "-O", "sygus-enum=sideways"])
    assert res.exit_code == 2 and "cvc5 options: sygus-enum" in res.output


def test_solve_depth_bound_and_max_steps(tmp_path: Path) -> None:
    res = runner.invoke(
        app, ["grid", "solve", str(_corridor(tmp_path)), "-s", "cvc5", "--max-steps", "1", "--depth-bound", "1"]
    )
    assert res.exit_code == 1
    assert "no controller (programs of depth <= 1) wins at l = 1" in res.output


def test_solve_help_has_examples() -> None:
    res = runner.invoke(app, ["grid", "solve", "--help"])
    assert res.exit_code == 0 and "plansynth grid solve examples/grid/figure1.yaml --solver cvc5" in res.output


def test_compile(tmp_path: Path) -> None:
    out = tmp_path / "f.sl"
    res = runner.invoke(app, ["grid", "compile", str(FIGURE1), "--steps", "6", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_text() == compile_sygus(load_grid_problem(FIGURE1), 6)
    res = runner.invoke(app, ["grid", "compile", str(FIGURE1), "--steps", "2", "--depth-bound", "4"])
    assert res.exit_code == 0 and res.output == compile_sygus(load_grid_problem(FIGURE1), 2, 4)


def test_compile_needs_a_path_length() -> None:
    res = runner.invoke(app, ["grid", "compile", str(FIGURE1)])
    assert res.exit_code == 2 and "give --steps N" in res.output


def test_compile_uses_the_files_steps(tmp_path: Path) -> None:
    p = tmp_path / "fixed.yaml"
    p.write_text("grid: [3, 1]\nrobot: {start: [0, 0], goal: [2, 0], moves: [stay, right]}\nsteps: 2\n")
    res = runner.invoke(app, ["grid", "compile", str(p)])
    assert res.exit_code == 0 and "path length l = 2" in res.output


def test_solve_minimize_proves_the_paper_depth_5(tmp_path: Path) -> None:
    # depth-5 of the paper's depth family: no program of depth 1 or 4 wins at l = 5.
    out = tmp_path / "r.json"
    res = runner.invoke(app, ["grid", "solve", str(EXAMPLES / "depth-5.yaml"), "--minimize", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert "depth 5 is minimal (proved)" in res.output
    doc = json.loads(out.read_text())
    assert doc["depth"] == 5 and doc["verified"] is True
    res = runner.invoke(app, ["grid", "solve", str(EXAMPLES / "depth-5.yaml"), "--minimize", "-s", "cvc5"])
    assert res.exit_code == 2 and "--minimize needs --solver native" in res.output

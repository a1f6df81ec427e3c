"""``plansynth grid verify / animate / export`` through typer's CliRunner."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image
from typer.testing import CliRunner

from plansynth.cli import app

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"
FIGURE1 = str(EXAMPLES / "figure1.yaml")
WINNER = "(ite (<= rx 3) 2 1)"
LOSER = "(ite (<= rx 1) 2 1)"

runner = CliRunner()


def invoke(*args: str):
    return runner.invoke(app, ["grid", *args])


@pytest.fixture
def result_json(tmp_path: Path) -> Path:
    """A result file as `plansynth grid solve -o` writes it (spec: Result file)."""
    path = tmp_path / "result.json"
    path.write_text(
        json.dumps(
            {
                "status": "realizable",
                "steps": 6,
                "program": WINNER,
                "depth": 4,
                "solver": "native",
                "seconds": 0.01,
                "verified": True,
                "problem": FIGURE1,
            }
        ),
        encoding="utf-8",
    )
    return path


# -- verify ---------------------------------------------------------------------------------


def test_verify_a_literal_term_that_wins() -> None:
    r = invoke("verify", FIGURE1, WINNER, "--steps", "6")
    assert r.exit_code == 0, r.output
    assert r.output.startswith("WINS at l = 6: (ite (<= rx 3) 2 1)")
    assert "states explored" in r.output


def test_verify_prints_the_counterexample_table_when_the_controller_loses() -> None:
    r = invoke("verify", FIGURE1, LOSER, "--steps", "6")
    assert r.exit_code == 1, r.output
    assert "LOSES at l = 6" in r.output
    assert "counterexample: collision at step 2 in cell (2, 3) with obstacle 0" in r.output
    lines = r.output.splitlines()
    assert any(line.split()[:4] == ["0", "│", "(1,", "1)"] for line in lines)  # step 0 row
    assert any(line.strip().startswith("end") for line in lines)
    assert "right" in r.output and "down" in r.output  # move names, not only numbers


def test_verify_a_result_json_takes_its_steps(result_json: Path) -> None:
    r = invoke("verify", FIGURE1, str(result_json))
    assert r.exit_code == 0, r.output
    assert "WINS at l = 6" in r.output
    r = invoke("verify", FIGURE1, str(result_json), "--steps", "7")  # --steps overrides
    assert r.exit_code == 1 and "not on the goal (4, 4) after step 6" in r.output


@pytest.mark.parametrize(
    "text", [f"(define-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int {WINNER})", WINNER]
)
def test_verify_a_program_file(tmp_path: Path, text: str) -> None:
    path = tmp_path / "controller.sl"
    path.write_text(f"; from a solver\n{text}\n", encoding="utf-8")
    r = invoke("verify", FIGURE1, str(path), "--steps", "6")
    assert r.exit_code == 0, r.output


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((FIGURE1, WINNER), "no path length: give --steps N"),
        ((FIGURE1, "(ite (<= rx 1) 7 1)", "--steps", "6"), "move number 7 is not in 0..4"),
        ((FIGURE1, "(ite (<= rx 1) 2", "--steps", "6"), "is neither a file nor a controller term"),
        (("missing.yaml", WINNER, "--steps", "6"), "missing.yaml: <file>: cannot read"),
    ],
)
def test_verify_bad_input_exits_2(args: tuple[str, ...], message: str) -> None:
    r = invoke("verify", *args)
    assert r.exit_code == 2, r.output
    assert message in r.output


def test_verify_a_result_without_program_exits_2(tmp_path: Path) -> None:
    path = tmp_path / "unknown.json"
    path.write_text(json.dumps({"status": "unknown", "steps": None, "program": None}), encoding="utf-8")
    r = invoke("verify", FIGURE1, str(path))
    assert r.exit_code == 2 and "the result has no program (status unknown)" in r.output
    broken = tmp_path / "broken.json"
    broken.write_text("{", encoding="utf-8")
    r = invoke("verify", FIGURE1, str(broken))
    assert r.exit_code == 2 and "not valid JSON" in r.output


def test_verify_help_has_examples() -> None:
    r = invoke("verify", "--help")
    assert r.exit_code == 0
    assert "plansynth grid verify examples/grid/figure1.yaml" in r.output
    assert "Exit status" in r.output


# -- animate ---------------------------------------------------------------------------------


def gif_frames(path: Path) -> int:
    with Image.open(path) as im:
        assert im.format == "GIF"
        return im.n_frames


def test_animate_writes_a_gif_and_a_png(tmp_path: Path, result_json: Path) -> None:
    gif, png = tmp_path / "run.gif", tmp_path / "step.png"
    r = invoke("animate", FIGURE1, str(result_json), "-o", str(gif), "--png", str(png), "--step", "2")
    assert r.exit_code == 0, r.output
    assert "controller wins at l = 6" in r.output and "on the goal (4, 4) after step 5" in r.output
    assert gif_frames(gif) > 1
    with Image.open(png) as im:
        assert im.format == "PNG" and im.size[0] > 200 and im.size[1] > 200


def test_animate_a_losing_controller_with_random_obstacles(tmp_path: Path) -> None:
    gif = tmp_path / "lose.gif"
    r = invoke("animate", FIGURE1, LOSER, "--steps", "6", "-o", str(gif), "--obstacles", "random", "--seed", "4")
    assert r.exit_code == 0, r.output
    assert "controller loses at l = 6; this run (random obstacles)" in r.output
    assert gif_frames(gif) > 1


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (("--obstacles", "sideways"), "--obstacles must be one of adversarial, random"),
        (("--step", "2"), "--step needs --png"),
        (("--png", "x.png", "--step", "40"), "--step 40: the run has states 0..6"),
    ],
)
def test_animate_bad_input_exits_2(tmp_path: Path, result_json: Path, extra: tuple[str, ...], message: str) -> None:
    r = invoke("animate", FIGURE1, str(result_json), "-o", str(tmp_path / "x.gif"), *extra)
    assert r.exit_code == 2, r.output
    assert message in r.output
    assert not (tmp_path / "x.gif").exists()


# -- export ----------------------------------------------------------------------------------


def test_export_python_runs(tmp_path: Path, result_json: Path) -> None:
    r = invoke("export", str(result_json), "--lang", "python", "--problem", FIGURE1)
    assert r.exit_code == 0, r.output
    namespace: dict[str, object] = {}
    exec(r.output, namespace)  # noqa: S102 - the exported controller
    move = namespace["move"]
    assert move(3, 1, 2, 5, 3, 5) == 2 and move(4, 1, 2, 5, 3, 5) == 1  # type: ignore[operator]


def test_export_uses_the_results_problem_field(result_json: Path) -> None:
    r = invoke("export", str(result_json), "--lang", "sygus")
    assert r.exit_code == 0, r.output
    assert (
        "(define-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int (ite (<= rx 3) 2 1))"
        in r.output
    )


def test_export_c_to_a_file_compiles(tmp_path: Path) -> None:
    out = tmp_path / "controller.c"
    r = invoke("export", WINNER, "--lang", "c", "--problem", FIGURE1, "-o", str(out), "--name", "controller")
    assert r.exit_code == 0, r.output
    main = tmp_path / "main.c"
    main.write_text(
        '#include <stdio.h>\n#include "controller.c"\n'
        'int main(void) { printf("%d %d\\n", controller(3, 1, 2, 5, 3, 5), controller(4, 1, 2, 5, 3, 5)); return 0; }\n',
        encoding="utf-8",
    )
    subprocess.run(["gcc", "-std=c99", "-pedantic-errors", "-o", str(tmp_path / "m"), str(main)], check=True)
    assert subprocess.run([str(tmp_path / "m")], capture_output=True, text=True, check=True).stdout == "2 1\n"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((WINNER, "--lang", "rust", "--problem", FIGURE1), "--lang must be python, c or sygus"),
        ((WINNER, "--lang", "c"), "give --problem FILE"),
        (("(ite (<= o2x 1) 0 1)", "--lang", "c", "--problem", FIGURE1), "unknown input 'o2x'"),
    ],
)
def test_export_bad_input_exits_2(args: tuple[str, ...], message: str) -> None:
    r = invoke("export", *args)
    assert r.exit_code == 2, r.output
    assert message in r.output


def test_export_with_a_stale_problem_path(tmp_path: Path) -> None:
    path = tmp_path / "r.json"
    path.write_text(json.dumps({"status": "realizable", "steps": 6, "program": WINNER, "problem": "gone/figure1.yaml"}))
    r = invoke("export", str(path), "--lang", "python")
    assert r.exit_code == 2 and "which is not a file from here: give --problem FILE" in r.output


def test_the_installed_command_runs() -> None:
    """The real entry point (not CliRunner): exit status 1 for a losing controller."""
    r = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "grid", "verify", FIGURE1, LOSER, "--steps", "6"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 1, r.stderr
    assert "LOSES" in r.stdout

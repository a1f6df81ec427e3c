"""``plansynth grid solve`` on a small problem starts fast (the targets: every
reactive-suite problem under 1 s wall through the CLI, median under 0.2 s, start-up
included): it imports only what the command needs. Guarded by what a fresh process
imports, not by timing it (a loaded machine would make a timed test flaky): numpy
(0.1-0.15 s of imports), rich's console, tables and progress bars, the other commands'
shells and the cvc5 bindings stay out of a small native solve."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]

#: Modules a small ``grid solve`` must not import, with why each one is heavy or needless.
NOT_ON_A_SMALL_SOLVE = {
    "numpy": "the verifier's tables on large grids only",
    "rich.console": "the answer is printed with click's styles",
    "rich.table": "tables belong to grid verify and explain",
    "rich.progress": "the spinner is shown only on a terminal",
    "click": "typer brings its own copy of click",
    "cvc5": "the cvc5 backend only",
    "plansynth.grid.cli_inspect": "verify, animate and export's shells",
    "plansynth.grid.cli_native": "explain and minimize's shells",
    "plansynth.grid.render": "animations",
    "plansynth.grid.sygus": "the SyGuS backends only",
    "plansynth.reach": "the other half",
}


def _imports(*args: str) -> tuple[int, set[str], str]:
    """Exit status, every module imported (full dotted names), and the output of
    ``plansynth ARGS`` in a fresh process, standard error not a terminal (as in bench)."""
    run = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", "from plansynth.cli import main; main()", *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    names = set(re.findall(r"^import time:\s+\d+ \|\s+\d+ \|\s+(\S+)$", run.stderr, re.M))
    assert "plansynth.cli" in names, "no import trace: " + run.stderr[-2000:]
    return run.returncode, names, run.stdout


def _assert_lean(names: set[str]) -> None:
    loaded = {m: why for m, why in NOT_ON_A_SMALL_SOLVE.items() if any(n == m or n.startswith(m + ".") for n in names)}
    assert not loaded, f"a small grid solve imported {sorted(loaded)}: {loaded}"


def test_a_small_realizable_solve_imports_neither_numpy_nor_rich() -> None:
    """The crossing example: a controller that reads the car's position, verified."""
    code, names, out = _imports("grid", "solve", str(ROOT / "examples/grid/crossing.yaml"), "--timeout", "30")
    assert code == 0 and "realizable at l = 9" in out and "verified by the independent verifier" in out, out
    assert "plansynth.grid.verify" in names  # the program was verified, without numpy
    _assert_lean(names)


def test_a_reactive_suite_solve_imports_neither_numpy_nor_rich() -> None:
    from plansynth.bench.families import reactive_suite_dir

    code, names, out = _imports("grid", "solve", str(reactive_suite_dir() / "r03_traffic.yaml"), "--timeout", "10")
    assert code == 1 and "unrealizable" in out, out
    _assert_lean(names)


def test_a_large_grid_still_verifies_with_numpy(tmp_path: Path) -> None:
    """The guard above is not vacuous: above PYTHON_CELLS cells the verifier's numpy
    tables are used (and imported)."""
    doc = {
        "grid": [70, 70],
        "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
        "obstacles": [{"start": [60, 60], "moves": ["stay", "left"]}],
        "steps": 3,
    }
    path = tmp_path / "wide.yaml"
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    code, names, out = _imports("grid", "solve", str(path), "--timeout", "30")
    assert code == 0 and "verified by the independent verifier" in out, out
    assert "numpy" in names

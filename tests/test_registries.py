"""One planner registry per half, complete on first use, and a CLI that imports only
what a sub-command needs. Each check runs in a fresh process,
so that nothing imported by another test can make a registry look complete."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("highspy", "shapely", "matplotlib", "cvc5", "pysat")

#: An open workspace every planner solves in seconds.
OPEN = {
    "name": "open",
    "workspace": {"min": [0, 0], "max": [10, 10]},
    "goal": {"min": [8, 8], "max": [9, 9]},
    "robot": {
        "dynamics": {"model": "double-integrator", "dt": 0.5},
        "start": [1, 1, 0, 0],
        "input_bound": 1,
        "state_bounds": {"min": [0, 0, -2, -2], "max": [10, 10, 2, 2]},
    },
    "max_horizon": 60,
}


def _python(code: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=ROOT)


def _imported_by(*args: str) -> set[str]:
    """Top-level packages imported by ``plansynth ARGS`` in a fresh process."""
    run = subprocess.run(
        [sys.executable, "-X", "importtime", "-c", "from plansynth.cli import main; main()", *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    names = re.findall(r"^import time:\s+\d+ \|\s+\d+ \|\s+(\S+)$", run.stderr, re.M)
    assert "plansynth.cli" in names, "no import trace"
    return {n.split(".")[0] for n in names}


@pytest.mark.parametrize("args", [("--version",), ("--help",), ("version",)])
def test_version_and_help_import_neither_half(args: tuple[str, ...]) -> None:
    imported = _imported_by(*args)
    assert not imported & set(HEAVY), f"plansynth {' '.join(args)} imported {sorted(imported & set(HEAVY))}"


def test_grid_solve_does_not_import_the_reach_half_or_cvc5(tmp_path: Path) -> None:
    imported = _imported_by("grid", "solve", str(ROOT / "examples/grid/figure1.yaml"), "--steps", "6")
    assert not imported & {"highspy", "shapely", "matplotlib", "cvc5"}, sorted(imported)


def test_version_option_prints_the_versions() -> None:
    run = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "--version"], capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 0 and re.fullmatch(r"plansynth \S+ \(core \S+\)\n", run.stdout), run.stdout + run.stderr


def test_every_reach_planner_loads_by_name_in_a_fresh_process() -> None:
    run = _python(
        "from plansynth.reach.solve import get_planner, planners\n"
        "print(' '.join(n for n in planners() if callable(get_planner(n))))\n"
    )
    assert run.returncode == 0, run.stderr
    names = run.stdout.split()
    assert set(names) >= {
        "lazy-smt",
        "lazy-smt-paper",
        "lazy-smt-paper-trivial",
        "lazy-smt-zeroprefix",
        "milp",
        "milp-bigm",
        "rrt",
        "est",
        "kpiece",
    }


def test_every_planner_the_help_lists_is_accepted() -> None:
    from plansynth.reach.solve import planners

    run = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "reach", "solve", "--help"],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, "COLUMNS": "400"},
    )
    text = " ".join(run.stdout.split())
    listed = set(
        re.findall(
            r"\b(lazy-smt(?:-[a-z]+)*|milp(?:-bigm)?|rrt|est|kpiece)\b",
            text.split("--planner", 1)[1].split("--out", 1)[0],
        )
    )
    assert len(listed) >= 9 and listed <= set(planners()), listed


@pytest.mark.parametrize(
    "planner",
    [
        "lazy-smt",
        "lazy-smt-paper",
        "lazy-smt-paper-trivial",
        "lazy-smt-zeroprefix",
        "milp",
        "milp-bigm",
        "rrt",
        "est",
        "kpiece",
    ],
)
def test_reach_solve_runs_every_planner_from_the_cli(planner: str, tmp_path: Path) -> None:
    problem = tmp_path / "open.yaml"
    problem.write_text(yaml.safe_dump(OPEN), encoding="utf-8")
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "plansynth.cli",
            "reach",
            "solve",
            str(problem),
            "--planner",
            planner,
            "--timeout",
            "60",
            "--out",
            str(tmp_path / "r.json"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "COLUMNS": "200"},
    )
    assert run.returncode == 0 and "found" in run.stdout, run.stdout + run.stderr
    assert '"validated": true' in (tmp_path / "r.json").read_text()


def test_an_unknown_planner_is_a_named_error_listing_the_names(tmp_path: Path) -> None:
    from plansynth.errors import SolverUnavailable, UnknownSolver
    from plansynth.reach.solve import get_planner, planners

    with pytest.raises(UnknownSolver, match="unknown planner; choose one of: lazy-smt, .*kpiece") as info:
        get_planner("rrtx")
    assert isinstance(info.value, (ValueError, SolverUnavailable)) and info.value.known == planners()
    problem = tmp_path / "open.yaml"
    problem.write_text(yaml.safe_dump(OPEN), encoding="utf-8")
    run = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "reach", "solve", str(problem), "--planner", "rrtx"],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, "COLUMNS": "400"},
    )
    assert run.returncode == 2 and "unknown planner 'rrtx'" in run.stderr and "kpiece" in run.stderr, run.stderr


def test_register_planner_still_takes_plugins() -> None:
    run = _python(
        "from plansynth.reach.solve import get_planner, planners, register_planner\n"
        "def mine(problem, budget=None, **options): return 'mine'\n"
        "register_planner('mine', mine)\n"
        "assert planners()[-1] == 'mine' and get_planner('mine') is mine\n"
        "try:\n    register_planner('rrt', mine)\nexcept ValueError:\n    print('ok')\n"
    )
    assert run.returncode == 0 and run.stdout == "ok\n", run.stderr


def test_every_grid_backend_loads_by_name_in_a_fresh_process() -> None:
    run = _python(
        "import sys\n"
        "from plansynth.grid.result import backend_names, get_backend\n"
        "assert 'cvc5' not in sys.modules\n"
        "get_backend('native')\n"
        "assert 'cvc5' not in sys.modules, 'the native backend loaded cvc5'\n"
        "print(' '.join(n for n in backend_names() if get_backend(n, **({'command': 'echo {file}'} if n == 'external' else {}))))\n"
    )
    assert run.returncode == 0, run.stderr
    assert set(run.stdout.split()) >= {"native", "cvc5", "external"}


def test_an_unknown_grid_backend_lists_the_names() -> None:
    from plansynth.errors import UnknownSolver
    from plansynth.grid.result import get_backend

    with pytest.raises(UnknownSolver, match="unknown grid solver; choose one of: native, cvc5, external"):
        get_backend("nosuch")


@pytest.mark.parametrize(
    ("planner", "hidden"), [("gcs", "pydrake"), ("fpp", "fastpathplanning"), ("rrt", "ompl"), ("kpiece", "ompl")]
)
def test_a_baseline_without_its_extra_names_the_extra(planner: str, hidden: str) -> None:
    """Without the ``baselines`` extra (its module made unimportable here), asking for a
    baseline is one line naming the extra to install, exit 2; lazy-smt still plans."""
    code = (
        "import sys\n"
        f"sys.modules[{hidden!r}] = None  # as if the package were not installed\n"
        "from plansynth.cli import main\n"
        f"main(['reach', 'solve', 'examples/reach/maze-1.yaml', '--planner', {planner!r}])\n"
    )
    run = _python(code)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "pip install 'plansynth[baselines]'" in run.stdout + run.stderr
    assert "Traceback" not in run.stdout + run.stderr
    ok = _python(code.replace(f"'--planner', {planner!r}", "'--planner', 'lazy-smt'"))
    assert ok.returncode == 0 and "found" in ok.stdout, ok.stdout + ok.stderr

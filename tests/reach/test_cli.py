"""``plansynth reach solve | validate | plot`` through typer's CliRunner."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from plansynth.cli import app
from plansynth.reach.families import maze
from plansynth.reach.fileformat import reach_problem_to_dict

runner = CliRunner()


@pytest.fixture(scope="module")
def maze1(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("reach") / "maze-1.yaml"
    path.write_text(yaml.safe_dump(reach_problem_to_dict(maze(1))), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def solved(maze1: Path, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, object]:
    d = tmp_path_factory.mktemp("out")
    out, png = d / "traj.json", d / "traj.png"
    result = runner.invoke(app, ["reach", "solve", str(maze1), "--out", str(out), "--plot", str(png)])
    return out, png, result


def test_solve_prints_the_record_and_writes_spec_json(solved: tuple[Path, Path, object]) -> None:
    out, png, result = solved
    assert result.exit_code == 0, result.output
    text = result.output
    for word in ("found", "horizon", "iterations", "sat calls", "lp calls", "time per phase", "validated", "segments"):
        assert word in text
    doc = json.loads(out.read_text())
    for key in ("status", "planner", "seconds", "states", "inputs", "regions", "segment_safe"):
        assert key in doc
    assert doc["status"] == "found" and doc["planner"] == "lazy-smt" and doc["segment_safe"] is True
    assert len(doc["states"]) == len(doc["inputs"]) + 1 == len(doc["regions"])
    assert doc["validated"] is True and doc["counters"]["lp_calls"] >= 1 and "highspy" in doc["versions"]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_validate_accepts_the_result_and_rejects_a_tampered_one(
    maze1: Path, solved: tuple[Path, Path, object], tmp_path: Path
) -> None:
    out, _, _ = solved
    ok = runner.invoke(app, ["reach", "validate", str(maze1), str(out), "--segment-safe"])
    assert ok.exit_code == 0 and "valid" in ok.output
    doc = json.loads(out.read_text())
    doc["states"][5][0] += 0.5  # breaks the dynamics
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    rejected = runner.invoke(app, ["reach", "validate", str(maze1), str(bad)])
    assert rejected.exit_code == 1 and "INVALID" in rejected.output and "dynamics" in rejected.output


def test_plot_with_and_without_result(maze1: Path, solved: tuple[Path, Path, object], tmp_path: Path) -> None:
    out, _, _ = solved
    for args in ([str(maze1)], [str(maze1), str(out)]):
        png = tmp_path / f"p{len(args)}.png"
        r = runner.invoke(app, ["reach", "plot", *args, "-o", str(png)])
        assert r.exit_code == 0, r.output
        assert png.read_bytes()[:4] == b"\x89PNG"


def test_solve_without_a_trajectory_draws_the_problem(tmp_path: Path) -> None:
    problem = Path(__file__).resolve().parents[2] / "examples" / "reach" / "mission-ringed.yaml"
    png, gif = tmp_path / "ringed.png", tmp_path / "ringed.gif"
    r = runner.invoke(app, ["reach", "solve", str(problem), "--plot", str(png), "--animate", str(gif)])
    assert r.exit_code == 1 and "infeasible" in r.output, r.output
    assert "picture of the problem written to" in r.output and "no trajectory to animate" in r.output
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert not gif.exists()


def test_bad_problem_file_exits_2_with_the_field(tmp_path: Path) -> None:
    doc = reach_problem_to_dict(maze(1))
    doc["robot"]["input_bound"] = -1
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(doc))
    for cmd in (["reach", "solve", str(path)], ["reach", "plot", str(path), "-o", str(tmp_path / "x.png")]):
        r = runner.invoke(app, cmd)
        assert r.exit_code == 2
        assert "robot.input_bound" in r.output and "bad.yaml" in r.output


def test_missing_result_file_exits_2(maze1: Path, tmp_path: Path) -> None:
    r = runner.invoke(app, ["reach", "validate", str(maze1), str(tmp_path / "none.json")])
    assert r.exit_code == 2 and "cannot read" in r.output


def test_infeasible_and_unknown_exit_codes(maze1: Path) -> None:
    r = runner.invoke(app, ["reach", "solve", str(maze1), "--max-horizon", "30"])
    assert r.exit_code == 1 and "infeasible" in r.output and "none up to 30" in r.output
    r = runner.invoke(app, ["reach", "solve", str(maze1), "--timeout", "0.001"])
    assert r.exit_code == 3 and "unknown" in r.output


def test_options_reach_the_planner(tmp_path: Path) -> None:
    small = tmp_path / "corridor.yaml"
    small.write_text(
        yaml.safe_dump(
            {
                "workspace": {"min": [0, 0], "max": [10, 4]},
                "obstacles": [{"min": [4, 0], "max": [5, 3]}],
                "goal": {"min": [8, 0.5], "max": [9, 1.5]},
                "robot": {
                    "dynamics": {"model": "double-integrator", "dt": 1.0},
                    "start": [1, 1, 0, 0],
                    "input_bound": 1.0,
                },
            }
        )
    )
    out = tmp_path / "r.json"
    r = runner.invoke(
        app,
        [
            "reach",
            "solve",
            str(small),
            "-O",
            "counterexample=trivial",
            "--option",
            "generalize=false",
            "--no-segment-safe",
            "--out",
            str(out),
        ],
    )
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    assert doc["options"]["counterexample"] == "trivial" and doc["options"]["generalize"] is False
    assert doc["guarantee"] == "samples"
    r = runner.invoke(app, ["reach", "solve", str(small), "--planner", "milp", "--out", str(out)])
    doc = json.loads(out.read_text())
    assert (
        r.exit_code == 0 and doc["planner"] == doc["solver"] == "milp" and doc["solver_version"].startswith("highspy")
    )


def test_search_options_and_the_paper_mode(maze1: Path, tmp_path: Path) -> None:
    out = tmp_path / "r.json"
    r = runner.invoke(
        app,
        [
            "reach",
            "solve",
            str(maze1),
            "-O",
            "horizon_search=linear",
            "-O",
            "transit=false",
            "-O",
            "guided=false",
            "-O",
            "widen=true",
            "-O",
            "window-growth=0.5",
            "-O",
            "wait_shifts=no",
            "--out",
            str(out),
        ],
    )
    assert r.exit_code == 0, r.output
    # segment-safe: the horizon is minimal among plans whose consecutive samples share a
    # region, above the proved bound for the problem
    assert "(minimal through the decomposition only)" in r.output and "(proved minimal)" not in r.output
    assert json.loads(out.read_text())["counters"]["minimal_relative_to"] == "decomposition"
    opts = json.loads(out.read_text())["options"]
    assert (
        opts["horizon_search"],
        opts["transit"],
        opts["guided"],
        opts["widen"],
        opts["window_growth"],
        opts["wait_shifts"],
    ) == ("linear", False, False, True, 0.5, False)
    r = runner.invoke(app, ["reach", "solve", str(maze1), "--paper", "--out", str(out)])
    assert r.exit_code == 0, r.output
    opts = json.loads(out.read_text())["options"]
    assert opts["counterexample"] == "zeroprefix" and opts["generalize"] is False and opts["horizon_search"] == "linear"
    assert opts["transit"] is False and opts["slack_weights"] == "uniform" and opts["wait_shifts"] is False


def test_bad_options_exit_2(maze1: Path) -> None:
    assert runner.invoke(app, ["reach", "solve", str(maze1), "--planner", "astar"]).exit_code == 2
    for bad, why in [
        ("counterexample=magic", "unknown value 'magic'"),
        ("horizon_search=binary", "unknown value"),
        ("window_growth=0", "must be positive"),
        ("window_growth=nan", "expected float"),
        ("max_horizon=-3", "below its minimum 0"),
        ("transit=maybe", "expected bool"),
        ("transit", "not KEY=VALUE"),
    ]:
        r = runner.invoke(app, ["reach", "solve", str(maze1), "-O", bad])
        assert r.exit_code == 2 and why in r.output, (bad, r.output)
    assert runner.invoke(app, ["reach", "solve", str(maze1), "--timeout", "-1"]).exit_code == 2


def test_the_help_lists_every_planners_options_with_defaults_and_help() -> None:
    from plansynth.options import describe
    from plansynth.reach.planners import get_planner, planners

    r = runner.invoke(app, ["reach", "solve", "--help"], env={"COLUMNS": "400"})
    assert r.exit_code == 0
    text = r.output
    for name in planners():
        assert f"  {name}" in text, name
        p = get_planner(name)
        for value in (p.defaults, p.mission_defaults):
            for key, _default, _doc in describe(value) if value is not None else ():
                if key in p.option_names(mission=value is p.mission_defaults):
                    assert key in text
    lazy = text.split("  lazy-smt:", 1)[1].split("  lazy-smt, for a problem with a mission:", 1)[0]
    assert "counterexample (default farkas): how CON-PLAN explains an infeasible plan" in " ".join(lazy.split())
    assert "semantics (default any)" in text and "loop_first (default true)" in text
    assert "lazy-smt-paper: max_horizon, segment_safe (as lazy-smt, with counterexample=zeroprefix" in text


def test_the_solve_help_loads_no_solver() -> None:
    """The options listed by --help come from light modules: with the reach package's own
    __init__ set aside, building the help text loads neither numpy nor a solver."""
    import subprocess
    import sys

    code = (
        "import os, sys, types\n"
        "import plansynth\n"
        "pkg = types.ModuleType('plansynth.reach')\n"
        "pkg.__path__ = [os.path.join(os.path.dirname(plansynth.__file__), 'reach')]\n"
        "sys.modules['plansynth.reach'] = pkg\n"
        "from plansynth.reach.cli import planner_options_help\n"
        "assert 'lazy-smt' in planner_options_help()\n"
        "print(sorted(m for m in ('numpy', 'highspy', 'shapely', 'pysat', 'matplotlib') if m in sys.modules))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout == "[]\n", run.stdout + run.stderr


def test_help_shows_examples() -> None:
    for cmd in ("solve", "validate", "plot"):
        r = runner.invoke(app, ["reach", cmd, "--help"])
        assert r.exit_code == 0 and "Examples" in r.output and "plansynth reach" in r.output


def test_table_runs_the_maze_family() -> None:
    r = runner.invoke(app, ["reach", "table", "--mazes", "1", "-c", "zeroprefix", "-c", "trivial"])
    assert r.exit_code == 0, r.output
    assert "zeroprefix+gen+min" in r.output and "trivial+gen+min" in r.output and r.output.count("found") == 2
    assert runner.invoke(app, ["reach", "table", "--mazes", "one"]).exit_code == 2


@pytest.mark.parametrize(
    "args, flag",
    [
        (["--paper", "-p", "milp"], "--paper"),
        (
            ["-p", "lazy-smt-zeroprefix", "-O", "counterexample=trivial"],
            "lazy-smt-zeroprefix: option 'counterexample': not an option of this planner (a named configuration: its "
            "other options are fixed); its options: max_horizon, segment_safe",
        ),
        (["-p", "lazy-smt-paper", "-O", "transit=false"], "lazy-smt-paper: option 'transit'"),
        (
            ["-p", "milp", "-O", "generalize=false"],
            "milp: option 'generalize': not an option of this planner; its options: max_horizon, start_horizon, segment_safe",
        ),
        (["-p", "rrt", "--max-horizon", "40"], "rrt: option 'max_horizon'"),
        (["-p", "lazy-smt", "-O", "variant=convex"], "lazy-smt: option 'variant'"),
    ],
)
def test_an_option_the_planner_does_not_take_is_one_line_and_exit_2(maze1: Path, args: list[str], flag: str) -> None:
    import os
    import subprocess
    import sys

    run = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "reach", "solve", str(maze1), *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "COLUMNS": "400"},
    )
    assert run.returncode == 2, run.stdout + run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and flag in lines[0], run.stderr
    assert run.stdout == ""  # refused before any planning


def test_paper_mode_takes_the_options_given_on_top(maze1: Path, tmp_path: Path) -> None:
    out = tmp_path / "r.json"
    r = runner.invoke(app, ["reach", "solve", str(maze1), "--paper", "-O", "counterexample=trivial", "--out", str(out)])
    assert r.exit_code == 0, r.output
    opts = json.loads(out.read_text())["options"]
    assert opts["counterexample"] == "trivial" and opts["horizon_search"] == "linear" and opts["transit"] is False


def test_a_mission_takes_its_options_through_the_same_flag(tmp_path: Path) -> None:
    out = tmp_path / "r.json"
    mission = "examples/reach/mission-patrol.yaml"
    r = runner.invoke(
        app, ["reach", "solve", mission, "-O", "semantics=lasso", "-O", "loop_first=false", "--out", str(out)]
    )
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text())
    assert doc["mission"]["semantics"] == "lasso" and doc["options"]["loop_first"] is False
    assert doc["solver"] == "lazy-smt" and doc["mission"]["ok"] is True
    bad = runner.invoke(app, ["reach", "solve", mission, "-O", "counterexample=trivial"])
    assert bad.exit_code == 2 and "not an option of this planner for a problem with a mission" in bad.output
    assert "semantics" in bad.output  # the options it does take
    paper = runner.invoke(app, ["reach", "solve", mission, "--paper"])
    assert paper.exit_code == 2 and "--paper" in paper.output


def test_table_takes_the_lazy_options_through_O() -> None:
    r = runner.invoke(app, ["reach", "table", "--mazes", "1", "-c", "zeroprefix", "-O", "generalize=false"])
    assert r.exit_code == 0, r.output
    assert "zeroprefix " in r.output and "+gen" not in r.output and r.output.count("found") == 1
    bad = runner.invoke(app, ["reach", "table", "--mazes", "1", "-O", "variant=convex"])
    assert bad.exit_code == 2 and "lazy-smt: option 'variant'" in bad.output

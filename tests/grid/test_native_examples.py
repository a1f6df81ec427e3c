"""The reactive examples need controllers that read obstacles; explain and minimize."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from plansynth.budget import Budget
from plansynth.cli import app
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.cone import influence_cone
from plansynth.grid.native.engine import Engine
from plansynth.grid.native.explain import check_witness_play, explain
from plansynth.grid.problem import load_grid_problem
from plansynth.grid.programs import reads_obstacles
from plansynth.grid.result import GridStatus
from plansynth.grid.verify import verify

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"

REACTIVE = [("crossing.yaml", 9), ("traffic.yaml", 9), ("patrol.yaml", 7), ("door.yaml", 10)]


@pytest.mark.parametrize("name,steps", REACTIVE)
def test_reactive_examples_need_obstacle_readings(name, steps):
    problem = load_grid_problem(EXAMPLES / name)
    out = Engine().solve_length(problem, steps, Budget(seconds=60))
    assert out.status is GridStatus.REALIZABLE
    assert reads_obstacles(out.program)
    assert verify(problem, out.program, steps).wins
    # Proof that reading obstacles is necessary: no obstacle-blind strategy exists
    # (the blind arena decides exactly the programs over rx, ry only).
    blind = Arena.build(problem, steps, influence_cone(problem, steps), ())
    assert not blind.layers[0] or not blind.solve_game() or _no_stationary(blind)


def _no_stationary(arena):
    from plansynth.grid.native.stationary import stationary_strategy

    return stationary_strategy(arena) is None


@pytest.mark.parametrize("name,steps", REACTIVE)
def test_every_shorter_length_is_refuted_with_a_checked_witness(name, steps):
    problem = load_grid_problem(EXAMPLES / name)
    for l in range(1, steps):
        e = explain(problem, l, Budget(seconds=30))
        assert e.kind in ("goal", "game", "stationary")
        if e.kind == "game":
            assert check_witness_play(problem, e.play, l)


def test_explain_cli_prints_and_animates_the_witness(tmp_path):
    gif = tmp_path / "why.gif"
    r = CliRunner().invoke(app, ["grid", "explain", str(EXAMPLES / "crossing.yaml"), "--steps", "7", "--gif", str(gif)])
    assert r.exit_code == 1, r.output
    assert "unrealizable" in r.output and "the robot loses" in r.output
    assert gif.stat().st_size > 1000


def test_explain_cli_on_a_realizable_length():
    r = CliRunner().invoke(app, ["grid", "explain", str(EXAMPLES / "patrol.yaml"), "--steps", "7"])
    assert r.exit_code == 0, r.output
    assert "realizable" in r.output


def test_minimize_cli_proves_figure1(tmp_path):
    out = tmp_path / "r.json"
    r = CliRunner().invoke(app, ["grid", "minimize", str(EXAMPLES / "figure1.yaml"), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "depth 4 (proved minimal)" in r.output
    assert '"verified": true' in out.read_text()


def test_solve_with_the_minimize_option_through_the_solve_loop():
    from plansynth.grid.solve import solve

    problem = load_grid_problem(EXAMPLES / "patrol.yaml")
    r = solve(problem, "native", Budget(seconds=60), minimize=True)
    assert r.status is GridStatus.REALIZABLE and r.steps == 7 and r.verified
    assert r.attempts[-1].counters["minimal_depth_proved"] is True


def test_solve_cli_passes_native_options():
    r = CliRunner().invoke(app, ["grid", "solve", str(EXAMPLES / "figure1.yaml"), "-O", "minimize=true"])
    assert r.exit_code == 0, r.output
    assert "(ite (<= 4 rx) 1 2)" in r.output
    bad = CliRunner().invoke(app, ["grid", "solve", str(EXAMPLES / "figure1.yaml"), "-O", "bogus=1"])
    assert bad.exit_code == 2 and "not an option of this solver" in bad.output

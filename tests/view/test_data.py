"""The pages' data and the checks at the door of ``plansynth view``."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from tests.view.conftest import EXAMPLES

from plansynth.errors import InvalidProblem
from plansynth.grid import load as load_grid
from plansynth.grid.native.explain import explain
from plansynth.grid.semantics import initial_state, step
from plansynth.view import build_page
from plansynth.view.grid_data import grid_page_data, state_key, strategy_table
from plansynth.view.page import render_page

TRAFFIC = EXAMPLES / "grid/traffic.yaml"


def test_strategy_table_beats_every_robot_move() -> None:
    """Every run the table allows ends in a loss for the robot: each reply either collides
    or leads to a state the table holds, and after the last step the robot is off the goal."""
    problem = load_grid(TRAFFIC)
    table, complete = strategy_table(problem, explain(problem, 8).strategy, 8)
    assert complete and state_key(0, initial_state(problem)) in table
    layer = [initial_state(problem)]
    for t in range(8):
        nxt = []
        for s in layer:
            for k, joint in enumerate(table[state_key(t, s)]):
                out = step(problem, s, k, tuple(joint))
                if not out.collided:
                    nxt.append(out.state)
        layer = nxt
    assert all(s.robot != problem.robot.goal for s in layer)


def test_a_page_is_self_contained_and_loads_nothing(results: dict) -> None:
    for problem, result in ((TRAFFIC, results["traffic"]), (EXAMPLES / "reach/mission-patrol.yaml", results["patrol"])):
        html = build_page(problem, result)
        assert "connect-src 'none'" in html and "default-src 'none'" in html
        assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", html, re.I)
        assert "fetch(" not in html or "/plan" in html  # only the served page's re-plan may fetch


def test_data_cannot_end_the_script_element() -> None:
    html = render_page({"kind": "grid", "problem": {"name": "</script><script>alert(1)</script>"}}, title="x")
    assert html.count("</script>") == 4  # the data's and the three scripts' own


def _fails(problem: Path, result: Path, pattern: str) -> None:
    with pytest.raises(InvalidProblem, match=pattern):
        build_page(problem, result)


def test_results_of_another_half_or_problem_are_refused(results: dict, tmp_path: Path) -> None:
    patrol = EXAMPLES / "reach/mission-patrol.yaml"
    _fails(patrol, results["traffic"], r"traffic\.json: status: .*a grid result")
    _fails(TRAFFIC, results["patrol"], r"patrol\.json: status: .*a reach result")
    _fails(EXAMPLES / "reach/maze-3.yaml", results["patrol"], r"patrol\.json: mission: .*another problem")
    _fails(EXAMPLES / "reach/dubins.yaml", results["maze-1"], r"maze-1\.json: states\[0\]: .* is not the start")
    _fails(EXAMPLES / "grid/figure1.yaml", results["traffic"], r"traffic\.json: problem: the result was solved for")
    doc = json.loads(results["patrol"].read_text())
    doc["states"] = [s[:3] for s in doc["states"]]
    (tmp_path / "short.json").write_text(json.dumps(doc))
    _fails(patrol, tmp_path / "short.json", r"short\.json: states\[0\]: has 3 components, but the dynamics")
    raw = json.loads(results["traffic"].read_text())
    raw["program"], raw["problem"] = "(ite (<= o5x 1) 0 2)", ""
    (tmp_path / "other.json").write_text(json.dumps(raw))
    _fails(TRAFFIC, tmp_path / "other.json", r"other\.json: program: not a controller of traffic: unknown input 'o5x'")


def test_a_trajectory_the_validator_rejects_is_shown_as_rejected(results: dict) -> None:
    """maze-1's plan starts where maze-3's would: it is drawn, with the validator's verdict."""
    from plansynth.reach import load
    from plansynth.view.reach_data import reach_page_data

    d = reach_page_data(load(EXAMPLES / "reach/maze-3.yaml"), json.loads(results["maze-1"].read_text()))
    assert d["validation"]["ok"] is False and d["validation"]["summary"].startswith("INVALID")


def test_a_controller_that_loses_comes_with_the_counterexample() -> None:
    d = grid_page_data(load_grid(TRAFFIC), {"status": "realizable", "steps": 9, "program": "2"})
    assert d["verdict"]["status"] == "loses"
    assert d["counterexample"]["reason"].startswith("collision at step")


TEAM = EXAMPLES / "reach/team-crossing.yaml"


def test_team_data_positions_per_robot_per_step_equal_the_result_file(results: dict) -> None:
    from plansynth.reach.team.fileformat import load_problem
    from plansynth.view.team_data import team_page_data

    problem = load_problem(TEAM)
    doc = json.loads(results["team-crossing"].read_text())
    d = team_page_data(problem, doc, source="team-crossing.json")
    assert d["kind"] == "team" and [r["name"] for r in d["robots"]] == [r["name"] for r in doc["robots"]]
    assert len({r["colour"] for r in d["robots"]}) == len(d["robots"])
    for shown, written in zip(d["trajectories"], doc["robots"]):
        assert shown["positions"] == [s[:2] for s in written["states"]]  # single integrators: x, y
        assert shown["inputs"] == written["inputs"]
    assert d["steps"] == len(doc["robots"][0]["states"]) - 1
    assert d["validation"]["ok"] is True and d["validation"]["summary"].startswith("valid, 2 robots")
    assert d["words"][0] == "status: found" and d["words"][1].startswith(f"horizon: {doc['horizon']}")
    cart = problem.moving_obstacles[0]
    assert d["moving"] == [
        {
            "name": "cart",
            "shape": {"box": [[-0.5, -0.5], [0.5, 0.5]]},
            "times": list(cart.times),
            "positions": [list(p) for p in cart.positions],
        }
    ]


def test_a_team_result_and_a_single_robot_result_are_not_swapped(results: dict, tmp_path: Path) -> None:
    _fails(TEAM, results["maze-1"], r"maze-1\.json: robots: missing: a single-robot result .*single-robot problem")
    _fails(EXAMPLES / "reach/maze-1.yaml", results["team-crossing"], r"team-crossing\.json: states: missing: a team")
    _fails(
        EXAMPLES / "reach/team-swap.yaml",
        results["team-crossing"],
        r"team-crossing\.json: robots\[0\]\.states\[0\]: has 2 components, but robot A of team-swap has 4",
    )
    doc = json.loads(results["team-crossing"].read_text())
    doc["robots"][1]["states"][0] = [7.0, 3.0]
    (tmp_path / "moved.json").write_text(json.dumps(doc))
    _fails(TEAM, tmp_path / "moved.json", r"moved\.json: robots\[1\]\.states\[0\]: \(7, 3\) is not the start")
    with pytest.raises(InvalidProblem, match="only a single-robot reach page re-plans"):
        build_page(TEAM, serve=True)


def test_a_team_page_without_a_result_plays_the_moving_obstacles() -> None:
    from plansynth.reach.team.fileformat import load_problem
    from plansynth.view.team_data import team_page_data

    d = team_page_data(load_problem(TEAM), None)
    assert d["trajectories"] is None and d["status"] is None and d["steps"] == 12  # the cart's last waypoint
    assert '"kind":"team"' in build_page(TEAM)

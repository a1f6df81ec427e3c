"""Robust planning under bounded disturbances (plansynth.reach.robust): the format of
``robot.disturbance``, the feedback designs, the tube, the tightened problem, the
planners that plan it and those that refuse it, the independent worst-case check and
the closed-loop simulation, missions, and the CLI."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

from plansynth.budget import Budget
from plansynth.cli import app
from plansynth.errors import InvalidOption, InvalidProblem
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import double_integrator, integrator_chain, single_integrator
from plansynth.reach.families import maze, narrow_maze, windy_maze
from plansynth.reach.fileformat import reach_problem_from_dict, reach_problem_to_dict
from plansynth.reach.result import ReachStatus
from plansynth.reach.robust.check import check_robust, error_supports, tube_polygons
from plansynth.reach.robust.feedback import dare, deadbeat_gain, design_feedback
from plansynth.reach.robust.simulate import simulate
from plansynth.reach.robust.tighten import GUARANTEE, RELATIVE, robust_design, tightened
from plansynth.reach.solve import register_planner, solve
from plansynth.reach.tube import Tube

runner = CliRunner()


def flat(output: str) -> str:
    """The CLI's output as one line of words (the table's borders and wrapping gone)."""
    return " ".join(re.sub(r"[\u2500-\u257f]", " ", output).split())


BOX = (0.02, 0.02, 0.05, 0.05)


def doc_with(disturbance: object) -> dict:
    d = reach_problem_to_dict(maze(1))
    d["robot"]["disturbance"] = disturbance
    return d


# ------------------------------------------------------------------ the format


def test_a_file_without_disturbance_means_what_it_meant() -> None:
    p = reach_problem_from_dict(reach_problem_to_dict(maze(1)))
    assert p.disturbance is None and p.tube is None and p == maze(1)
    assert solve(p).robust is None


@pytest.mark.parametrize(
    "disturbance",
    [
        {"box": [0.02, 0.02, 0.05, 0.05]},
        {"box": [0.02, 0.02, 0.05, 0.05], "feedback": "deadbeat"},
        {"box": [0.02, 0.02, 0.05, 0.05], "feedback": {"lqr": {"q": [10, 10, 1, 1], "r": [2, 2]}}},
        {
            "polytope": [
                [0.02, 0, 0, 0],
                [-0.02, 0.02, 0, 0],
                [0, -0.02, 0.05, 0],
                [0, 0, -0.05, 0.05],
                [0, 0, 0, -0.05],
            ]
        },
        {"box": [0.01, 0.01, 0.0, 0.0], "feedback": {"gain": [[-0.5, 0, -1, 0], [0, -0.5, 0, -1]]}},
    ],
)
def test_the_disturbance_round_trips(disturbance: dict) -> None:
    p = reach_problem_from_dict(doc_with(disturbance))
    assert p.disturbance is not None
    again = reach_problem_from_dict(reach_problem_to_dict(p))
    assert again == p and again.disturbance == p.disturbance


@pytest.mark.parametrize(
    ("disturbance", "field", "reason"),
    [
        ({"box": [0.1, 0.1]}, "robot.disturbance.box", "expected 4"),
        ({"box": [0.1, -0.1, 0, 0]}, "robot.disturbance.box", ">= 0"),
        ({"box": [0.1] * 4, "polytope": [[0, 0, 0, 0]]}, "robot.disturbance", "exactly one"),
        ({}, "robot.disturbance", "exactly one"),
        ({"box": [0.1] * 4, "wind": 3}, "robot.disturbance.wind", "unknown"),
        ({"polytope": [[1, 0, 0, 0], [2, 1, 0, 0]]}, "robot.disturbance.polytope", "must contain 0"),
        ({"box": [0.1] * 4, "feedback": "pid"}, "robot.disturbance.feedback", "unknown design"),
        ({"box": [0.1] * 4, "feedback": {"gain": [[1, 2]]}}, "robot.disturbance.feedback.gain", "must be 2 x 4"),
        ({"box": [0.1] * 4, "feedback": {"lqr": {"q": [1, 1, 1, 0]}}}, "robot.disturbance.feedback.lqr.q", "positive"),
    ],
)
def test_a_bad_disturbance_is_refused_at_the_door(disturbance: dict, field: str, reason: str) -> None:
    with pytest.raises(InvalidProblem, match=reason) as info:
        reach_problem_from_dict(doc_with(disturbance), source="w.yaml")
    assert info.value.field == field


def test_a_disturbance_needs_a_2d_workspace() -> None:
    from plansynth.reach.geometry import Box
    from plansynth.reach.problem import ReachProblem

    with pytest.raises(InvalidProblem, match="2-D workspace"):
        ReachProblem(
            workspace=Box((0, 0, 0), (4, 4, 4)),
            obstacles=(),
            goal=Box((3, 3, 3), (4, 4, 4)),
            dynamics=single_integrator(3, 1.0),
            start=[0.5, 0.5, 0.5],
            input_bound=1.0,
            disturbance=Disturbance(box=(0.1, 0.1, 0.1)),
        )


# ------------------------------------------------------------------ the feedback


@pytest.mark.parametrize("seed", range(5))
def test_the_riccati_solution_solves_the_dare_and_stabilises(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, m = 4, 2
    A = rng.normal(size=(n, n))
    B = rng.normal(size=(n, m))
    Q, R = np.diag(rng.uniform(0.5, 2, n)), np.diag(rng.uniform(0.5, 2, m))
    X = dare(A, B, Q, R)
    S = R + B.T @ X @ B
    assert np.allclose(A.T @ X @ A - A.T @ X @ B @ np.linalg.solve(S, B.T @ X @ A) + Q, X, atol=1e-8)
    assert np.all(np.linalg.eigvalsh(X) > 0)
    K = -np.linalg.solve(S, B.T @ X @ A)
    assert max(abs(np.linalg.eigvals(A + B @ K))) < 1


def test_the_riccati_iteration_refuses_an_unstabilisable_pair() -> None:
    with pytest.raises(ValueError):
        dare(np.array([[2.0, 0], [0, 1]]), np.array([[0.0], [1.0]]), np.eye(2), np.eye(1))


@pytest.mark.parametrize("order", [1, 2, 3])
def test_deadbeat_is_nilpotent_after_the_chain_order(order: int) -> None:
    dyn = integrator_chain(order, 2, 0.5)
    K = deadbeat_gain(dyn)
    P = np.linalg.matrix_power(dyn.A + dyn.B @ K, order)
    assert np.abs(P).max() < 1e-9
    assert Tube(dyn.A + dyn.B @ K, K, Disturbance(box=(0.1,) * dyn.n_states)).exact_steps == order


def test_an_unstable_gain_is_refused_naming_the_feedback() -> None:
    w = Disturbance(box=(0.1, 0.1), feedback="gain", gain=np.array([[0.5, 0.0]]))
    with pytest.raises(InvalidProblem, match="not stable") as info:
        design_feedback(double_integrator(1, 0.5), w)
    assert info.value.field == "robot.disturbance.feedback"


# ------------------------------------------------------------------ the tube


def zonotope_support(A_K: np.ndarray, box: np.ndarray, c: np.ndarray, t: int) -> float:
    """h_{E_t}(c) from the zonotope's generators, written out."""
    G = np.hstack([np.linalg.matrix_power(A_K, i) @ np.diag(box) for i in range(t)]) if t else np.zeros((len(c), 0))
    return float(np.abs(c @ G).sum())


def test_the_tube_is_the_zonotope_sum_and_its_cap_bounds_every_later_step() -> None:
    p = windy_maze(1)
    design = robust_design(p)
    tube = design.tube
    rng = np.random.default_rng(0)
    D = rng.normal(size=(5, 4))
    S = tube.support(D, 400)
    for t in (0, 1, 2, 7, 30):
        for k in range(5):
            assert S[t, k] == pytest.approx(zonotope_support(tube.A_K, np.array(BOX), D[k], t), rel=1e-9, abs=1e-12)
    assert np.all(np.diff(S, axis=0) >= 0)  # 0 in W: the sets only grow
    long = np.array([zonotope_support(tube.A_K, np.array(BOX), D[k], 400) for k in range(5)])
    cap = tube.cap(D)
    assert np.all(cap >= long - 1e-12) and np.all(cap - long < 1e-6)


def test_a_polytope_disturbance_has_the_support_of_its_vertices() -> None:
    V = np.array([[0.1, 0.0], [-0.05, 0.1], [-0.05, -0.1]])
    tube = Tube(np.array([[0.5, 0.1], [0.0, 0.3]]), np.zeros((1, 2)), Disturbance(vertices=V))
    c = np.array([[1.0, -2.0]])
    expected = sum(max(float(c[0] @ np.linalg.matrix_power(tube.A_K, i) @ v) for v in V) for i in range(3))
    assert tube.support(c, 3)[3, 0] == pytest.approx(expected)


# ------------------------------------------------------------------ planning and checking


@pytest.fixture(scope="module")
def robust3():
    p = windy_maze(3)
    return p, solve(p)


def test_a_robust_plan_says_what_it_guarantees(robust3) -> None:
    p, r = robust3
    assert r.status is ReachStatus.FOUND and r.validated is True
    rec = r.robust
    assert rec["guarantee"] == GUARANTEE and rec["relative_to"] == RELATIVE
    assert rec["feedback"]["design"] == "lqr" and np.array(rec["feedback"]["gain"]).shape == (2, 4)
    assert rec["check"]["ok"] is True and rec["check"]["clearance"] >= 0
    grown = rec["margins"]["obstacles_grown_by"]
    assert all(0.1 < v < 0.3 for v in grown["lo"] + grown["hi"])
    doc = r.to_json_dict()
    assert doc["robust"]["feedback"]["gain"] == rec["feedback"]["gain"]


def test_a_robust_plan_survives_sampled_disturbances_and_the_nominal_plan_does_not(robust3) -> None:
    p, r = robust3
    K = np.array(r.robust["feedback"]["gain"])
    runs = simulate(p, r.trajectory, K, sequences=200, seed=3)
    assert runs.violated == 0 and runs.total == 400
    nominal = solve(replace(p, disturbance=None))
    bad = simulate(p, nominal.trajectory, K, sequences=200, seed=3)
    assert bad.violated > 0 and "obstacle" in bad.kinds_violated
    assert not check_robust(p, nominal.trajectory, K).ok


def test_the_worst_case_check_catches_a_plan_that_rides_an_edge(robust3) -> None:
    """A robust plan shifted towards a wall by a centimetre fails the worst case (it was
    tight against it) although its samples stay free."""
    p, r = robust3
    K = np.array(r.robust["feedback"]["gain"])
    X = np.array(r.trajectory.states)
    worst = check_robust(p, r.trajectory, K)
    assert worst.ok
    shifted = replace(r.trajectory, states=X - np.array([0.0, 0.01, 0, 0]))
    report = check_robust(p, shifted, K)
    assert not report.ok and set(report.counts) & {"workspace", "obstacle", "segment", "state-bound"}


def test_the_tube_polygons_are_the_support_functions(robust3) -> None:
    p, r = robust3
    K = np.array(r.robust["feedback"]["gain"])
    polys = tube_polygons(p, K, 12)
    dirs = np.array([[1.0, 0, 0, 0], [0, -1.0, 0, 0], [0.6, 0.8, 0, 0]])
    S = error_supports(p, K, dirs, 12)
    for t in range(13):
        assert np.max(polys[t] @ dirs[:, :2].T, axis=0) == pytest.approx(S[t], abs=1e-12)


@pytest.mark.parametrize("shape", [{"radius": 0.3}, {"half_extent": (0.3, 0.2)}])
def test_a_robot_with_a_size_keeps_its_clearance_under_disturbance(shape: dict) -> None:
    from plansynth.reach.robot import RobotShape

    p = replace(windy_maze(2), robot_shape=RobotShape(**shape))
    r = solve(p)
    assert r.status is ReachStatus.FOUND and r.robust["check"]["ok"]
    K = np.array(r.robust["feedback"]["gain"])
    assert simulate(p, r.trajectory, K, sequences=50).violated == 0
    shifted = replace(r.trajectory, states=np.array(r.trajectory.states) - np.array([0.0, 0.02, 0, 0]))
    assert not check_robust(p, shifted, K).ok  # it rides the grown obstacles' edges: no slack to spare


def test_milps_plan_the_same_tightened_problem_and_pass_the_check() -> None:
    p = windy_maze(1)
    lazy = solve(p, "lazy-smt", horizon_search="linear", exact_segments=False)
    region = solve(p, "milp", Budget(seconds=120))
    assert lazy.status is region.status is ReachStatus.FOUND
    assert lazy.horizon == region.horizon and region.robust["check"]["ok"]
    bigm = solve(p, "milp-bigm", Budget(seconds=120), horizon=lazy.horizon)
    assert bigm.status is ReachStatus.FOUND and bigm.robust["check"]["ok"]


def test_the_nominal_check_baseline_plans_without_the_tube_and_fails_the_check() -> None:
    r = solve(windy_maze(1), "nominal-check")
    assert r.status is ReachStatus.UNKNOWN and r.trajectory is not None
    assert "robust check" in r.message and r.robust["check"]["ok"] is False


def test_a_disturbance_wider_than_the_gap_has_no_robust_plan() -> None:
    r = solve(narrow_maze())
    assert r.status is ReachStatus.INFEASIBLE and RELATIVE in r.message
    assert "not connected" in r.message  # the gap closes, not the goal
    assert solve(narrow_maze(1.0)).status is ReachStatus.FOUND
    assert r.robust is not None and "check" not in r.robust


def test_planners_that_do_not_plan_under_disturbances_refuse() -> None:
    def plain(problem, budget, **_):  # a plugin that knows nothing of tubes
        raise AssertionError("must not be called")

    from plansynth.reach.planners import PLANNERS

    register_planner("plain-plugin", plain, replace_existing=True)
    try:
        with pytest.raises(InvalidOption, match="does not plan under disturbances"):
            solve(windy_maze(1), "plain-plugin")
    finally:
        PLANNERS.unregister("plain-plugin")  # (the planners' list is the other tests' business)


def test_early_steps_use_the_smaller_tube() -> None:
    """At step 0 the tube is a point: the start may sit closer to a wall than the tube's
    cap allows later (the time-varying tightening of the workspace)."""
    p = replace(windy_maze(1), start=np.array([0.05, 1.0, 0.0, 0.0]))
    design = robust_design(p)
    assert design.position_lo[0] > 0.05  # the cap is wider than the start's room
    r = solve(p)
    assert r.status is ReachStatus.FOUND and r.robust["check"]["ok"]


def test_the_tightening_limits_the_horizon_when_the_tube_outgrows_a_bound() -> None:
    p = replace(windy_maze(1), max_horizon=200)
    slow = replace(
        p, disturbance=Disturbance(box=BOX, feedback="gain", gain=np.array([[-0.02, 0, -0.3, 0], [0, -0.02, 0, -0.3]]))
    )
    t = tightened(slow)
    assert t.problem is not None and t.problem.max_horizon < 200 and "no longer plan is robust" in t.note


# ------------------------------------------------------------------ missions


def test_a_mission_under_disturbance_reads_its_labels_robustly() -> None:
    from plansynth.reach.mission.families import mission_problem

    p = replace(mission_problem("maze-1", "patrol"), disturbance=Disturbance(box=BOX))
    r = solve(p)
    assert r.status is ReachStatus.FOUND and r.robust["check"]["ok"], r.message
    K = np.array(r.robust["feedback"]["gain"])
    runs = simulate(p, r.trajectory, K, sequences=200, loop_start=r.mission["loop_start"])
    assert runs.violated == 0
    nominal = solve(replace(p, disturbance=None))
    bad = simulate(p, nominal.trajectory, K, sequences=50, loop_start=nominal.mission["loop_start"])
    assert bad.violated > 0


# ------------------------------------------------------------------ the CLI


@pytest.fixture(scope="module")
def windy_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("robust") / "maze-1-windy.yaml"
    path.write_text(yaml.safe_dump(reach_problem_to_dict(windy_maze(1))), encoding="utf-8")
    return path


def test_the_cli_solves_and_validates_under_disturbances(windy_file: Path, tmp_path: Path) -> None:
    out, png = tmp_path / "plan.json", tmp_path / "plan.png"
    r = runner.invoke(app, ["reach", "solve", str(windy_file), "--out", str(out), "--plot", str(png)])
    assert r.exit_code == 0, r.output
    text = flat(r.output)
    for words in (
        "every disturbance sequence within W keeps the closed loop safe",
        "K = [",
        "obstacles grown by",
        "robust check",
    ):
        assert words in text
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    v = runner.invoke(app, ["reach", "validate", str(windy_file), str(out), "--disturbances", "50", "--nominal"])
    assert v.exit_code == 0, v.output
    assert "0 of 50 random, 0 of 50 vertex runs violated" in v.output
    assert "nominal plan" in v.output and "the disturbance ignored" in v.output
    doc = json.loads(out.read_text())
    doc["states"] = [[x, y - 0.05, vx, vy] for x, y, vx, vy in doc["states"]]  # towards the floor
    doc["states"][0] = [1, 1, 0, 0]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    rejected = runner.invoke(app, ["reach", "validate", str(windy_file), str(bad)])
    assert rejected.exit_code == 1


def test_validate_refuses_disturbances_for_a_problem_without_one(tmp_path: Path) -> None:
    plain = tmp_path / "m.yaml"
    plain.write_text(yaml.safe_dump(reach_problem_to_dict(maze(1))), encoding="utf-8")
    out = tmp_path / "t.json"
    assert runner.invoke(app, ["reach", "solve", str(plain), "--out", str(out)]).exit_code == 0
    r = runner.invoke(app, ["reach", "validate", str(plain), str(out), "--disturbances", "10"])
    assert r.exit_code == 2 and "no disturbance" in r.output


def test_the_cli_says_infeasible_is_relative_to_the_design(tmp_path: Path) -> None:
    path = tmp_path / "storm.yaml"
    path.write_text(yaml.safe_dump(reach_problem_to_dict(narrow_maze())), encoding="utf-8")
    r = runner.invoke(app, ["reach", "solve", str(path)])
    assert r.exit_code == 1
    assert "relative to the feedback design" in flat(r.output)

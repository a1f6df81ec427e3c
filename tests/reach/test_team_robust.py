"""Teams under bounded disturbances (plansynth.reach.team.robust): the tightened team
planned by lazy-smt-team and milp-team, the independent worst-case team check and the
sampled closed loops, the nominal plan that breaks under disturbances, the result's
record, the file format and its errors (clause soundness under disturbances is in
test_team_properties.py)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_team_properties import windy_team
from typer.testing import CliRunner

from plansynth.budget import Budget
from plansynth.cli import app
from plansynth.errors import InvalidOption, InvalidProblem
from plansynth.reach import ReachStatus, solve
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.team.families import corridor_swap, windy_swap
from plansynth.reach.team.fileformat import load_problem, team_problem_from_dict, team_problem_to_dict
from plansynth.reach.team.problem import GoalPoint
from plansynth.reach.team.robust import tightened_team, without_disturbances
from plansynth.reach.team.robust_check import check_robust_team, team_gains
from plansynth.reach.team.robust_simulate import simulate_team
from plansynth.reach.trajectory import Trajectory

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "reach" / "team-swap-windy.yaml"


@pytest.fixture(scope="module")
def swap_plans():
    p = windy_swap()
    return p, solve(p, "lazy-smt-team", Budget(seconds=120)), solve(p, "milp-team", Budget(seconds=120))


def test_the_windy_swap_is_planned_robustly_by_both_team_planners(swap_plans) -> None:
    p, lazy, milp = swap_plans
    for r in (lazy, milp):
        assert r.status is ReachStatus.FOUND and r.validated is True, r.message
        assert r.robust["check"]["ok"] is True
        assert set(r.robust["robots"]) == {"A", "B"}
        assert "each robot's W" in r.robust["guarantee"]
        assert "h_E_i,t(-a) + h_E_j,t(a)" in r.robust["separation"]
        gains = team_gains(p, r.robust)
        assert check_robust_team(p, r.trajectories, gains).ok
        assert simulate_team(p, r.trajectories, gains, sequences=200, seed=1).violated == 0
    assert lazy.horizon == milp.horizon  # both minimal through the tightened encoding
    nominal = solve(corridor_swap())
    assert nominal.status is ReachStatus.FOUND and nominal.horizon < lazy.horizon  # robustness costs steps


def test_the_nominal_team_plan_breaks_under_sampled_disturbances(swap_plans) -> None:
    """Shown, not assumed: the nominal plan, run with the same gains under the same
    sequences, violates the problem (the separation among other things), and the
    worst-case check says so with robots and steps named."""
    p, lazy, _ = swap_plans
    gains = team_gains(p, lazy.robust)
    nominal = solve(without_disturbances(p), "lazy-smt-team")
    runs = simulate_team(p, nominal.trajectories, gains, sequences=100, seed=0)
    assert runs.violated > 0 and "separation" in runs.kinds_violated
    assert runs.first is not None and "robot" in runs.first.violation
    worst = check_robust_team(p, nominal.trajectories, gains)
    assert not worst.ok and "separation" in worst.counts
    sep = next(v for v in worst.violations if v.kind == "separation")
    assert "robots A and B" in sep.detail and sep.step is not None


def test_the_worst_case_separation_is_the_sum_of_both_error_sets() -> None:
    """Two parked robots 0.15 farther apart than the separation: safe without
    disturbances; in the worst case violated from the first step at which both robots'
    error sets together reach across the gap (h_E_A,t + h_E_B,t > 0.15), and with one
    robot's alone only from the step at which its own does."""
    p = replace(windy_swap(), obstacles=())
    gap, N = 0.15, 8
    a, b = np.zeros((N + 1, 4)), np.zeros((N + 1, 4))
    a[:, :2] = (2.0, 0.5)
    b[:, :2] = (2.0 + 0.7 + gap, 0.5)  # the zone's half-side is d + h_A + h_B = 0.7
    trajs = [Trajectory(a, np.zeros((N, 2))), Trajectory(b, np.zeros((N, 2)))]
    gains = team_gains(p, None)
    from plansynth.reach.robust.error_sets import error_supports

    e = error_supports(p.robot_problems[0], gains[0], np.array([[1.0, 0, 0, 0]]), N)[:, 0]  # same for B (box W)
    both, one = int(np.argmax(2 * e > gap)), int(np.argmax(e > gap))
    assert 0 < both < one
    steps = sorted({v.step for v in check_robust_team(p, trajs, gains).violations if v.kind == "separation"})
    assert steps[0] == both, (e, steps)
    alone = replace(p, robots=(p.robots[0], replace(p.robots[1], disturbance=None)))
    steps = sorted(
        {v.step for v in check_robust_team(alone, trajs, [gains[0], None]).violations if v.kind == "separation"}
    )
    assert steps[0] == one, (e, steps)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10**6))
def test_tightened_lazy_and_milp_agree_on_random_windy_pairs(seed: int) -> None:
    """Random small 2-robot teams under small disturbances: the tightened lazy-smt-team
    and milp-team agree on found / infeasible and the horizon; every plan passes the
    worst-case team check and 200 random (and 200 vertex) disturbed runs."""
    p = windy_team(seed)
    lazy = solve(p, "lazy-smt-team", Budget(seconds=120), horizon_search="linear", incumbent="none")
    milp = solve(p, "milp-team", Budget(seconds=120))
    tight = tightened_team(p)
    if tight.status is not None:  # the tightening leaves nothing to plan (a goal swallowed by grown obstacles)
        assert lazy.status.value == milp.status.value == tight.status and lazy.message == milp.message
        assert "relative to the feedback design" in lazy.message
        return
    assert lazy.status is not ReachStatus.UNKNOWN and milp.status is not ReachStatus.UNKNOWN, (
        lazy.message,
        milp.message,
    )
    assert lazy.status is milp.status and lazy.horizon == milp.horizon, (p.name, lazy.message, milp.message)
    for r in (lazy, milp):
        if r.status is ReachStatus.FOUND:
            gains = team_gains(p, r.robust)
            assert r.robust["check"]["ok"] and check_robust_team(p, r.trajectories, gains).ok
            assert simulate_team(p, r.trajectories, gains, sequences=200, seed=seed).violated == 0
        else:
            assert "feedback design" in r.message


def test_a_tube_wider_than_the_corridor_has_no_robust_plan_relative_to_the_designs() -> None:
    p = windy_swap(8.0)
    t = tightened_team(p)
    r = solve(p, "lazy-smt-team", Budget(seconds=60))
    assert r.status is not ReachStatus.FOUND
    assert t.status is not None or "feedback design" in r.message
    assert "relative to the feedback design" in r.message
    assert r.robust is not None and set(r.robust["robots"]) == {"A", "B"}


def test_robots_that_stop_rest_with_room_for_their_feedback() -> None:
    """``stop`` under a disturbance: the nominal ends where it can stay, with a resting
    input that leaves the feedback its largest share of the input bound."""
    p = windy_swap()
    p = replace(p, robots=tuple(replace(r, stop=True) for r in p.robots))
    lazy, milp = solve(p, "lazy-smt-team"), solve(p, "milp-team")
    assert lazy.status is milp.status is ReachStatus.FOUND and lazy.horizon == milp.horizon
    for r in (lazy, milp):
        assert r.robust["check"]["ok"]
        for robot, traj in zip(p.robots, r.trajectories):
            A, B = np.asarray(robot.dynamics.A), np.asarray(robot.dynamics.B)
            x = traj.states[-1]
            rest = np.linalg.lstsq(B, x - A @ x, rcond=None)[0]
            share = max(r.robust["robots"][robot.name]["margins"]["input_bound_at_most"]["hi"])
            assert np.allclose(B @ rest, x - A @ x, atol=1e-7)
            assert np.max(np.abs(rest)) <= robot.input_bound - share + 1e-7


def test_prioritized_refuses_a_team_under_disturbances() -> None:
    with pytest.raises(InvalidOption, match="plans no disturbance"):
        solve(windy_swap(), "prioritized")


# ------------------------------------------------------------------ the file format


def _doc() -> dict:
    return yaml.safe_load(EXAMPLE.read_text())


def test_the_example_is_the_windy_swap_and_round_trips() -> None:
    p = load_problem(EXAMPLE)
    assert p.robots == windy_swap().robots
    assert team_problem_from_dict(team_problem_to_dict(p)) == p
    assert all(r.disturbance == Disturbance(box=(0.02, 0.02, 0.05, 0.05)) for r in p.robots)
    assert team_problem_to_dict(p)["robots"][0]["disturbance"] == {"box": [0.02, 0.02, 0.05, 0.05]}


def test_a_robot_may_override_the_default_disturbance() -> None:
    doc = _doc()
    doc["robots"][1]["disturbance"] = {"box": [0.01, 0.01, 0.0, 0.0], "feedback": "deadbeat"}
    p = team_problem_from_dict(doc)
    assert p.robots[0].disturbance.feedback == "lqr" and p.robots[1].disturbance.feedback == "deadbeat"


def test_a_disturbance_of_the_wrong_dimension_names_the_robot_and_field() -> None:
    doc = _doc()
    doc["robots"][1]["disturbance"] = {"box": [0.02, 0.02]}
    with pytest.raises(InvalidProblem, match=r"robots\[1\]\.disturbance\.box.*robot B"):
        team_problem_from_dict(doc)
    doc = _doc()
    doc["robot"]["disturbance"] = {"polytope": [[0.1, 0, 0], [0, 0.1, 0], [-0.1, -0.1, 0]]}
    with pytest.raises(InvalidProblem, match=r"robot\.disturbance\.polytope\[0\].*robot A"):
        team_problem_from_dict(doc)


def test_a_bad_feedback_names_the_robot_and_field() -> None:
    doc = _doc()
    doc["robots"][0]["disturbance"] = {"box": [0.02, 0.02, 0.05, 0.05], "feedback": {"gain": [[1, 0, 0, 0]]}}
    with pytest.raises(InvalidProblem, match=r"robots\[0\]\.disturbance\.feedback.*robot A"):
        team_problem_from_dict(doc)


def test_a_disturbed_robot_needs_a_goal_region_and_no_mission() -> None:
    p = windy_swap()
    with pytest.raises(InvalidProblem, match=r"robots\[0\]\.goal.*robot A has a disturbance"):
        replace(p, robots=(replace(p.robots[0], goal=GoalPoint((9.5, 0.5))), p.robots[1]))
    with pytest.raises(InvalidProblem, match=r"robots\[1\]\.disturbance.*mission"):
        replace(p, robots=(p.robots[0], replace(p.robots[1], goal=None, mission="F a")), labels={"a": p.robots[0].goal})


# ------------------------------------------------------------------ the CLI


def test_reach_validate_checks_a_team_under_disturbances(tmp_path: Path, swap_plans) -> None:
    _, lazy, _ = swap_plans
    plan = tmp_path / "team.json"
    lazy.write(plan)
    runner = CliRunner()
    out = runner.invoke(app, ["reach", "validate", str(EXAMPLE), str(plan), "--disturbances", "50", "--nominal"])
    assert out.exit_code == 0, out.output
    assert "worst case: robust" in out.output and "0 of 50 random, 0 of 50 vertex runs violated" in out.output
    assert "feedback of robot B" in out.output and "nominal plan (horizon" in out.output
    doc = json.loads(plan.read_text())
    doc["robots"][0]["states"] = [
        [x + (0.3 if k == 1 else 0.0) for k, x in enumerate(s)] for s in doc["robots"][0]["states"]
    ]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    out = runner.invoke(app, ["reach", "validate", str(EXAMPLE), str(bad), "--disturbances", "5"])
    assert out.exit_code == 1 and "NOT robust" in out.output
    plain = Path(str(EXAMPLE).replace("-windy", ""))
    out = runner.invoke(app, ["reach", "validate", str(plain), str(plan), "--disturbances", "5"])
    assert out.exit_code == 2 and "no robot of the team has a disturbance" in out.output

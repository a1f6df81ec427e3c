"""Teams of robots and moving obstacles (plansynth.reach.team): the file format, the
independent team validator, the planners on the team family's small cases, the CLI.

The property tests (random small teams against the joint MILP, the soundness of every
clause the joint CON-PLAN learns) are in test_team_properties.py.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from plansynth.budget import Budget
from plansynth.errors import InvalidOption, InvalidProblem
from plansynth.reach import ReachStatus, solve
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.fileformat import load_reach_problem, reach_problem_to_dict
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.robot import RobotShape
from plansynth.reach.team.families import (
    TEAM_CASES,
    corridor_swap,
    narrow_corridor,
    patrol_gap,
    room_corners,
    smc_crossing,
)
from plansynth.reach.team.fileformat import load_problem, team_problem_from_dict, team_problem_to_dict
from plansynth.reach.team.geometry import obstacle_facets, pair_facets
from plansynth.reach.team.problem import GoalPoint, MovingObstacle, Separation, TeamProblem, TeamRobot
from plansynth.reach.team.result import team_trajectories_from_dict
from plansynth.reach.team.validate import validate_team
from plansynth.reach.trajectory import Trajectory

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "reach"

SINGLE = {"model": "single-integrator", "dt": 1.0}


def _doc(**extra) -> dict:
    doc = {
        "workspace": {"min": [0, 0], "max": [10, 10]},
        "robot": {"dynamics": SINGLE, "input_bound": 2.0},
        "robots": [
            {"name": "a", "start": [1, 1], "goal": {"min": [8, 8], "max": [9, 9]}},
            {"name": "b", "start": [9, 1], "goal": {"min": [1, 8], "max": [2, 9]}},
        ],
        "separation": 0.5,
    }
    doc.update(extra)
    return doc


# ------------------------------------------------------------------------------ format


def test_a_file_with_one_robot_means_what_it_meant() -> None:
    for name in ("maze-1", "cluttered", "mission-patrol"):
        assert load_problem(EXAMPLES / f"{name}.yaml") == load_reach_problem(EXAMPLES / f"{name}.yaml")


def test_team_files_round_trip_and_the_example_is_the_family_case() -> None:
    p = load_problem(EXAMPLES / "team-swap.yaml")
    assert isinstance(p, TeamProblem) and [r.name for r in p.robots] == ["A", "B"]
    assert team_problem_from_dict(team_problem_to_dict(p)) == p
    case = corridor_swap()
    assert p.robots == case.robots and p.obstacles == case.obstacles and p.separation == case.separation
    for f in TEAM_CASES.values():
        q = f()
        assert team_problem_from_dict(team_problem_to_dict(q)) == q


def test_defaults_robot_fields_and_a_team_of_one_among_moving_obstacles() -> None:
    p = team_problem_from_dict(
        _doc(
            robots=[
                {"start": [1, 1], "goal": {"point": [5, 5]}, "radius": 0.3, "stop": True},
                {"start": [9, 9], "goal": {"min": [0, 0], "max": [1, 1]}},
            ]
        )
    )
    assert p.robots[0].robot_shape == RobotShape(radius=0.3) and p.robots[1].robot_shape is None
    assert p.robots[0].goal == GoalPoint((5.0, 5.0)) and p.robots[0].stop and not p.robots[1].stop
    one = team_problem_from_dict(
        {
            "workspace": {"min": [0, 0], "max": [10, 10]},
            "goal": {"min": [8, 8], "max": [9, 9]},
            "robot": {"dynamics": SINGLE, "start": [1, 1], "input_bound": 1},
            "moving_obstacles": [{"shape": {"min": [-1, -1], "max": [1, 1]}, "path": [{"t": 0, "at": [5, 5]}]}],
        }
    )
    assert one.n_robots == 1 and one.moving_obstacles[0].name == "m0"
    single = reach_problem_to_dict(load_reach_problem(EXAMPLES / "maze-1.yaml"))
    single["separation"] = 0.0  # a team key makes a team of the same robot
    assert load_problem_from(single).n_robots == 1


def load_problem_from(doc: dict) -> TeamProblem:
    return team_problem_from_dict(doc, "t.yaml")


@pytest.mark.parametrize(
    "change, field, reason",
    [
        ({"separation": -1}, "separation.distance", "non-negative"),
        ({"separation": {"distance": 0.5, "norm": [[0, 0], [1, 0], [0, 1]]}}, "separation.norm", "centrally symmetric"),
        ({"separation": {"distance": 0.5, "norm": "l2"}}, "separation.norm", "unknown norm"),
        (
            {
                "robots": [
                    {"start": [1, 1], "goal": {"min": [8, 8], "max": [9, 9]}},
                    {"start": [1.2, 1], "goal": {"min": [1, 8], "max": [2, 9]}},
                ]
            },
            "robots[1].start",
            "closer than the separation",
        ),
        (
            {
                "robots": [
                    {
                        "start": [1, 1],
                        "goal": {"min": [8, 8], "max": [9, 9]},
                        "dynamics": {"model": "single-integrator", "dt": 0.5},
                    },
                    {"start": [9, 1], "goal": {"min": [1, 8], "max": [2, 9]}},
                ]
            },
            "robots",
            "same time step",
        ),
        (
            {"robots": [{"start": [11, 1], "goal": {"min": [8, 8], "max": [9, 9]}}]},
            "robots[0].start",
            "outside the workspace",
        ),
        (
            {
                "robots": [
                    {"name": "x", "start": [1, 1], "goal": {"min": [8, 8], "max": [9, 9]}},
                    {"name": "x", "start": [9, 1], "goal": {"min": [1, 8], "max": [2, 9]}},
                ]
            },
            "robots[1].name",
            "used twice",
        ),
        (
            {
                "moving_obstacles": [
                    {"shape": [[0, 0], [2, 0], [1, 1], [2, 2], [0, 2]], "path": [{"t": 0, "at": [5, 5]}]}
                ]
            },
            "moving_obstacles[0].shape",
            "convex",
        ),
        (
            {
                "moving_obstacles": [
                    {"shape": {"min": [0, 0], "max": [1, 1]}, "path": [{"t": 5, "at": [5, 5]}, {"t": 5, "at": [6, 5]}]}
                ]
            },
            "moving_obstacles[0].path[1].t",
            "increase",
        ),
        (
            {"moving_obstacles": [{"shape": {"min": [-1, -1], "max": [1, 1]}, "path": [{"t": 0, "at": [1, 1]}]}]},
            "robots[0].start",
            "moving obstacle m0",
        ),
        ({"goal": {"min": [1, 1], "max": [2, 2]}}, "goal", "each robot has its own"),
        ({"labels": {"dock": {"min": [1, 1], "max": [2, 2], "margin": 0.1}}}, "labels.dock.margin", "one robot"),
    ],
)
def test_bad_team_files_name_the_field(change: dict, field: str, reason: str) -> None:
    with pytest.raises(InvalidProblem, match=reason) as exc:
        team_problem_from_dict(_doc(**change), "t.yaml")
    assert exc.value.field == field


# ------------------------------------------------------------------------------ validator


def _crossing_team(separation: float = 0.5, starts=((0.0, 0.0), (4.0, 0.0)), **robot) -> TeamProblem:  # noqa: ANN001
    dyn = single_integrator(2, 1.0)
    a = TeamRobot("a", dyn, list(starts[0]), 4.0, goal=Box((3, 3), (4, 4)), **robot)
    b = TeamRobot("b", dyn, list(starts[1]), 4.0, goal=Box((0, 3), (1, 4)), **robot)
    return TeamProblem(Box((0, 0), (4, 4)), (), (a, b), Separation(separation))


def _path(points: list[list[float]]) -> Trajectory:
    P = np.array(points, float)
    return Trajectory(states=P, inputs=np.diff(P, axis=0))


def test_validator_rejects_robots_that_meet_between_samples_naming_them_and_the_step() -> None:
    p = _crossing_team()
    # apart at both samples (4 m, then 4 m), through the same point at mid-step
    a = _path([[0, 0], [0, 1], [4, 3.5]])
    b = _path([[4, 0], [4, 1], [0, 3.5]])
    r = validate_team(p, [a, b])
    assert not r.ok and not r.segment_safe
    assert [(v.kind, v.step) for v in r.violations] == [("separation", 1)]
    assert "robots a and b come closer than the separation along the segment from step 1 to 2" in r.violations[0].detail
    # the same moves, one of them a step later: apart along every segment
    b_late = _path([[4, 0], [4, 1], [4, 2], [0, 3.5]])
    a_wait = _path([[0, 0], [0, 1], [0, 1], [4, 3.5]])
    assert validate_team(p, [a_wait, b_late]).violations[0].kind == "separation"  # still meet in step 2
    b_ahead = _path([[4, 0], [4, 1], [0, 3.5], [0, 3.5]])
    a_behind = _path([[0, 0], [0, 1], [0, 1], [4, 3.5]])
    assert validate_team(p, [a_behind, b_ahead]).ok


def test_validator_reads_the_norm_the_sizes_and_the_discs_exactly() -> None:
    # the infinity norm: 0.5 along one axis is enough, 0.49 along both is not
    inf = _crossing_team()
    a, b = _path([[1, 1], [1, 1]]), _path([[1.5, 3], [1.5, 3]])
    only = {"check_robots": False}  # the separation alone
    assert validate_team(inf, [a, b], **only).ok
    assert not validate_team(inf, [a, _path([[1.49, 1.49], [1.49, 1.49]])], **only).ok
    # a polygonal norm (a diamond: the 1-norm): 0.3 + 0.3 < 0.5 fails, 0.3 + 0.25 passes
    diamond = Polygon(((1, 0), (0, 1), (-1, 0), (0, -1)))
    l1 = TeamProblem(inf.workspace, (), inf.robots, Separation(0.5, diamond))
    assert not validate_team(l1, [a, _path([[1.2, 1.2], [1.2, 1.2]])], **only).ok
    assert validate_team(l1, [a, _path([[1.3, 1.25], [1.3, 1.25]])], **only).ok
    # discs of radius 0.3, separation 0.2 (infinity norm): centres 0.8 apart along a diagonal
    # are 0.8 / sqrt(2) = 0.566 apart per axis, the discs' gap then 0.8 - 0.6 = 0.2 Euclidean,
    # 0.2 / sqrt(2) = 0.14 in the infinity norm: too close; along an axis 0.8 apart is enough
    discs = _crossing_team(0.2, ((0.5, 0.5), (3.5, 0.5)), robot_shape=RobotShape(radius=0.3))
    d = 0.8 / np.sqrt(2)
    assert not validate_team(discs, [a, _path([[1 + d, 1 + d]] * 2)], **only).ok
    assert validate_team(discs, [a, _path([[1.8, 1], [1.8, 1]])], **only).ok


def test_validator_follows_a_moving_obstacle_through_its_bend_inside_a_step() -> None:
    robot = TeamRobot("r", single_integrator(2, 1.0), [0.0, 0.0], 10.0, goal=Box((9, 0), (10, 1)))
    # the obstacle (a point, 0.5 apart) goes up to (5, 4) at t = 0.5 s and back down by 1 s:
    # at both samples it is far above the robot's straight move along y = 0, at the bend too
    up_down = MovingObstacle(Box((0, 0), (0, 0)), (0.0, 0.5, 1.0), ((5.0, 4.0), (5.0, 4.0), (5.0, 4.0)), "o")
    p = TeamProblem(Box((0, 0), (10, 10)), (), (robot,), Separation(0.5), (up_down,))
    move = _path([[0, 0], [10, 0]])
    assert validate_team(p, [move]).ok
    # now it dips to the robot's path exactly when the robot passes x = 5 (t = 0.5 s)
    dip = MovingObstacle(Box((0, 0), (0, 0)), (0.0, 0.5, 1.0), ((5.0, 4.0), (5.0, 0.0), (5.0, 4.0)), "o")
    q = TeamProblem(Box((0, 0), (10, 10)), (), (robot,), Separation(0.5), (dip,))
    r = validate_team(q, [move])
    assert [(v.kind, v.step) for v in r.violations] == [("moving-obstacle", 0)]
    assert "comes within the separation of o along the segment from step 0 to 1" in r.violations[0].detail


def test_validator_checks_each_robot_as_the_reach_validator_does() -> None:
    p = _crossing_team()
    bad = Trajectory(states=[[0, 0], [3.5, 3.5]], inputs=[[9, 9]])  # too fast: |u| > 4
    b = _path([[4, 0], [0.5, 3.5]])
    r = validate_team(p, [bad, b])
    assert {v.kind for v in r.violations} >= {"dynamics"} or {v.kind for v in r.violations} >= {"input"}
    assert all(v.detail.startswith("robot a:") for v in r.violations if v.kind in ("dynamics", "input"))
    point = TeamProblem(
        p.workspace, (), (TeamRobot("a", single_integrator(2, 1.0), [0, 0], 4.0, goal=GoalPoint((3, 3)), stop=True),)
    )
    assert validate_team(point, [_path([[0, 0], [3, 3]])]).ok
    assert validate_team(point, [_path([[0, 0], [3, 2.9]])]).violations[0].kind == "goal"


# ------------------------------------------------------------------------------ planners


def test_planner_geometry_holds_the_exact_zone() -> None:
    """The facets' polygon contains the exact zone (a disc by its circumscribed 16-gon)."""
    p = _crossing_team(0.2, ((0.5, 0.5), (3.5, 0.5)), robot_shape=RobotShape(radius=0.3))
    f = pair_facets(p, 0, 1)
    zone = p.pair_zone(0, 1)
    rng = np.random.default_rng(0)
    for z in rng.uniform(-1.5, 1.5, size=(400, 2)):
        if zone.intrusion(z, z) > 1e-9:  # inside the exact zone: no side holds
            assert np.max(f.margins(z)) < 0
    o = MovingObstacle(Polygon(((0, 0), (1, 0), (0, 1))), (0.0,), ((2.0, 2.0),))
    q = TeamProblem(p.workspace, (), p.robots, p.separation, (o,))
    g, zone = obstacle_facets(q, 0, 0), q.obstacle_zone(0, 0)
    for z in rng.uniform(-2, 2, size=(400, 2)):
        if zone.intrusion(z, z) > 1e-9:
            assert np.max(g.margins(z)) < 0


def test_smc_crossing_is_solved_by_every_planner_with_its_numbers() -> None:
    p = smc_crossing()
    assert p.dt == 0.2 and p.robots[0].input_bound == 0.5 and p.separation.distance == 0.5
    for planner in ("lazy-smt", "milp-team", "prioritized"):
        r = solve(p, planner, Budget(seconds=120))
        assert r.status is ReachStatus.FOUND and r.validated is True, (planner, r.message)
        ends = [t.states[-1] for t in r.trajectories]
        assert np.allclose(ends[0][:2], [4, 2.5], atol=1e-6) and np.allclose(ends[1][:2], [2, 4.5], atol=1e-6)
        assert np.allclose(ends[0][2:], 0, atol=1e-6) and np.allclose(ends[1][2:], 0, atol=1e-6)
    lazy = solve(p, "lazy-smt-team", horizon_search="linear")
    milp = solve(p, "milp-team")
    assert lazy.horizon == milp.horizon and lazy.counters["minimal"] is True


def test_corridor_swap_needs_the_joint_planner_and_the_narrow_corridor_has_no_plan() -> None:
    p = corridor_swap()
    lazy = solve(p, "lazy-smt-team", Budget(seconds=120))
    assert lazy.status is ReachStatus.FOUND and lazy.validated is True
    # one robot waits in the bay (y above the corridor) while the other passes
    ys = [t.states[:, 1].max() for t in lazy.trajectories]
    assert max(ys) > 1.0
    prio = solve(p, "prioritized", Budget(seconds=120))
    assert prio.status is ReachStatus.UNKNOWN and "incomplete" in prio.message
    q = narrow_corridor()
    for planner in ("lazy-smt-team", "milp-team"):
        r = solve(q, planner, Budget(seconds=120))
        assert r.status is ReachStatus.INFEASIBLE and r.counters["infeasible_relative_to"] == "encoding", r.message
    assert solve(q, "prioritized", Budget(seconds=120)).status is ReachStatus.UNKNOWN


def test_four_robots_around_a_pillar_and_a_patrolled_gap() -> None:
    for p in (room_corners(), patrol_gap()):
        r = solve(p, budget=Budget(seconds=120))
        assert r.status is ReachStatus.FOUND and r.validated is True, r.message
    r = solve(patrol_gap(), "lazy-smt-team", Budget(seconds=120))
    assert r.counters["engaged_obstacle_steps"] > 0  # the vehicle had to be dodged


def test_robots_with_missions() -> None:
    """Per-robot LTL missions, finite semantics: each mission checked on its robot."""
    doc = {
        "workspace": {"min": [0, 0], "max": [10, 4]},
        "labels": {"left": {"min": [0, 0], "max": [2, 4]}, "right": {"min": [8, 0], "max": [10, 4]}},
        "robot": {"dynamics": {"model": "double-integrator", "dt": 1.0}, "input_bound": 1.0,
                  "state_bounds": {"min": [0, 0, -2, -2], "max": [10, 4, 2, 2]}},
        "robots": [
            {"name": "p", "start": [1, 1, 0, 0], "mission": "F right & F G left"},
            {"name": "q", "start": [9, 3, 0, 0], "mission": "F left & G !right | F G right"},
        ],
        "separation": 0.5,
        "max_horizon": 40,
    }  # fmt: skip
    p = team_problem_from_dict(doc)
    r = solve(p, budget=Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.validated is True, r.message
    assert all(m is not None and m["ok"] for m in r.validation.missions)
    with pytest.raises(InvalidOption, match="plans no missions"):
        solve(p, "milp-team")


def test_planner_names_on_teams_and_a_reach_problem_as_a_team_of_one() -> None:
    with pytest.raises(InvalidOption, match="a team is planned by lazy-smt-team, milp-team, prioritized"):
        solve(smc_crossing(), "rrt")
    maze = load_reach_problem(EXAMPLES / "maze-1.yaml")
    r = solve(maze, "lazy-smt-team", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.validated is True and r.horizon == solve(maze, "milp").horizon


# ------------------------------------------------------------------------------ CLI


def _cli(*args: str, cwd: Path):  # noqa: ANN202 - typer's Result
    import os

    from typer.testing import CliRunner

    from plansynth.cli import app

    here = os.getcwd()
    os.chdir(cwd)
    try:
        return CliRunner().invoke(app, list(args))
    finally:
        os.chdir(here)


def test_cli_solves_plots_and_validates_a_team_and_rejects_a_collision(tmp_path: Path) -> None:
    example = str(EXAMPLES / "team-swap.yaml")
    run = _cli(
        "reach", "solve", example, "--out", "plan.json", "--plot", "plan.png", "--animate", "plan.gif", cwd=tmp_path
    )
    assert run.exit_code == 0, run.output
    assert all((tmp_path / f).stat().st_size > 1000 for f in ("plan.json", "plan.png", "plan.gif"))
    doc = json.loads((tmp_path / "plan.json").read_text())
    assert doc["status"] == "found" and doc["validated"] is True and [r["name"] for r in doc["robots"]] == ["A", "B"]
    assert _cli("reach", "validate", example, "plan.json", cwd=tmp_path).exit_code == 0
    assert _cli("reach", "plot", example, "plan.json", "-o", "again.png", cwd=tmp_path).exit_code == 0
    # the robot that stayed in the corridor, mirrored end for end, in place of the other: a
    # valid plan for that one alone, which meets the first head-on
    p = load_problem(example)
    trajs, _ = team_trajectories_from_dict(doc, "plan.json", ["A", "B"])
    low = min(range(2), key=lambda r: trajs[r].states[:, 1].max())
    assert trajs[low].states[:, 1].max() <= 1.0
    mirrored = trajs[low].states.copy()
    mirrored[:, 0] = 10.0 - mirrored[:, 0]
    mirrored[:, 2] = -mirrored[:, 2]
    swap = {**doc, "robots": [dict(r) for r in doc["robots"]]}
    swap["robots"][1 - low]["states"] = mirrored.tolist()
    swap["robots"][1 - low]["inputs"] = (trajs[low].inputs * np.array([-1.0, 1.0])).tolist()
    (tmp_path / "bad.json").write_text(json.dumps(swap))
    bad = _cli("reach", "validate", example, "bad.json", cwd=tmp_path)
    assert bad.exit_code == 1
    assert "robots A and B" in bad.output and "separation at step" in bad.output
    assert validate_team(p, trajs).ok


def test_a_team_planner_refuses_a_problem_with_a_disturbance() -> None:
    """The team planners plan no disturbance: a reach problem with one is refused, not
    planned without it."""
    p = load_reach_problem(EXAMPLES / "maze-3-windy.yaml")
    assert p.disturbance is not None
    with pytest.raises(InvalidOption, match="disturbances"):
        solve(p, "lazy-smt-team", Budget(seconds=30))


def test_a_reused_component_lps_time_limit_is_relative_to_its_run_time():
    """HiGHS compares ``time_limit`` with the instance's run time summed over its runs;
    the joint CON-PLAN reuses its instances, so ``run_lp`` sets the limit past that sum:
    with the seconds left as the limit, an instance that had run longer than them in all
    stopped at once (a ``BudgetExhausted`` though each solve takes milliseconds)."""
    import highspy

    from plansynth.reach.team.component_lp import run_lp

    class Left:  # a clock with a fixed number of seconds left
        seconds = 1.0

        def remaining(self) -> float:
            return self.seconds

    class Stats:
        lp_calls = 0

    rng = np.random.default_rng(0)
    h = highspy.Highs()
    h.silent()
    n = 400
    for _ in range(n):
        h.addVariable(0.0, 10.0)
    for _ in range(120):
        idx = np.nonzero(rng.uniform(size=n) > 0.6)[0].astype(np.int32)
        h.addRow(-highspy.kHighsInf, 50.0, len(idx), idx, rng.uniform(size=len(idx)))
    h.changeColsCost(n, np.arange(n, dtype=np.int32), -rng.uniform(size=n))
    clock, stats = Left(), Stats()
    while h.getRunTime() < 0.05:
        h.clearSolver()  # a cold solve each time
        assert run_lp(h, clock, stats)[0] == "feasible"
    clock.seconds = 0.5 * h.getRunTime()  # less than the instance has run, more than a solve
    for _ in range(3):
        h.clearSolver()
        assert run_lp(h, clock, stats)[0] == "feasible"

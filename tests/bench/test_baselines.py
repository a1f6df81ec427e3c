"""The reach baselines: OMPL kinodynamic RRT and the one-shot big-M MILP."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from plansynth.budget import Budget
from plansynth.reach.dynamics import double_integrator, single_integrator
from plansynth.reach.geometry import Box, Polygon, shape_to_shapely
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus
from plansynth.reach.validate import validate


def _open_problem(obstacles=()):
    dyn = double_integrator(2, 0.5)
    return ReachProblem(
        workspace=Box((0.0, 0.0), (10.0, 10.0)),
        obstacles=tuple(obstacles),
        goal=Box((8.0, 8.0), (9.0, 9.0)),
        dynamics=dyn,
        start=np.array([1.0, 1.0, 0.0, 0.0]),
        input_bound=1.0,
        state_bounds=Box((0.0, 0.0, -2.0, -2.0), (10.0, 10.0, 2.0, 2.0)),
        max_horizon=60,
        name="open",
    )


def test_rrt_finds_a_valid_trajectory_in_an_open_workspace():
    from plansynth.reach.solve import solve

    p = _open_problem()
    r = solve(p, "rrt", Budget(seconds=20), seed=3)  # solve() validates, the planner does not
    assert r.status == ReachStatus.FOUND and r.validated is True
    assert r.planner == "rrt" and r.guarantee == "segments"
    assert r.horizon == r.trajectory.horizon > 0
    assert validate(p, r.trajectory).ok  # the same independent check, once more
    assert r.counters["propagations"] >= r.horizon
    assert r.options["planner"] == "RRT" and r.options["seed"] == 3


def test_kpiece_and_est_are_offered():
    import subprocess
    import sys

    from plansynth.reach.planners.ompl import PLANNERS

    assert set(PLANNERS) == {"rrt", "est", "kpiece"}
    # OMPL takes its seed once per process, so a run that depends on it gets a process of
    # its own (in this one an earlier test may have seeded it otherwise)
    code = (
        "from plansynth.budget import Budget\n"
        "from plansynth.reach.result import ReachStatus\n"
        "from plansynth.reach.solve import solve\n"
        "from tests.bench.test_baselines import _open_problem\n"
        "r = solve(_open_problem(), 'kpiece', Budget(seconds=20), seed=1)\n"
        "assert r.status == ReachStatus.FOUND and r.validated is True, r.message\n"
        "assert r.options['seed_applied'], r.options\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=Path(__file__).resolve().parents[2],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-2000:]


def test_rrt_gives_unknown_never_infeasible_when_the_goal_is_walled_off():
    from plansynth.reach.planners.ompl import plan_rrt

    # the goal (8..9)^2 is cut off by an L of walls 2.5 m thick (one step covers at most
    # 1.25 m, so sampled positions cannot hop over them)
    p = _open_problem([Box((4.0, 4.0), (10.0, 6.5)), Box((4.0, 4.0), (6.5, 10.0))])
    r = plan_rrt(p, Budget(seconds=0.5), seed=1)
    assert r.status == ReachStatus.UNKNOWN and r.trajectory is None


def test_bigm_milp_finds_a_valid_trajectory_around_a_nonconvex_obstacle():
    from plansynth.reach.solve import solve

    L = Polygon(((3.0, 3.0), (7.0, 3.0), (7.0, 4.0), (4.0, 4.0), (4.0, 7.0), (3.0, 7.0)))
    p = _open_problem([L])
    r = solve(p, "milp-bigm", Budget(seconds=30))
    assert r.status == ReachStatus.FOUND and r.validated is True
    assert r.planner == "milp-bigm"
    rep = validate(p, r.trajectory)
    assert rep.ok and rep.segment_safe and r.guarantee == "segments"
    poly = shape_to_shapely(L)
    pos = r.trajectory.states[:, :2]
    assert not any(poly.contains(shapely.Point(*q)) for q in pos)
    assert r.counters["binaries"] > 0


def test_bigm_milp_fixed_horizon_too_short_is_unknown():
    from plansynth.reach.planners.milp_bigm import plan_milp_bigm

    r = plan_milp_bigm(_open_problem(), Budget(seconds=10), horizon=2)
    assert r.status == ReachStatus.UNKNOWN
    assert r.counters["horizons_infeasible"] == 1


def test_convex_pieces_cover_a_nonconvex_polygon_exactly():
    from plansynth.reach.planners.milp_bigm import convex_pieces

    L = Polygon(((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)))
    pieces = convex_pieces(L)
    rng = np.random.default_rng(0)
    for q in rng.uniform(-0.5, 2.5, size=(300, 2)):
        inside_piece = any(np.all(H @ q < h - 1e-9) for H, h in pieces)
        in_poly = shape_to_shapely(L).contains(shapely.Point(*q))
        if inside_piece:
            assert in_poly
    assert sum(shapely.Polygon(_vertices(H, h)).area for H, h in pieces) == pytest.approx(3.0)


def _vertices(H, h):
    # vertices of a 2-D convex polygon {H p <= h}: pairwise line intersections that satisfy all
    pts = []
    for i in range(len(h)):
        for j in range(i + 1, len(h)):
            M = np.array([H[i], H[j]])
            if abs(np.linalg.det(M)) < 1e-12:
                continue
            p = np.linalg.solve(M, [h[i], h[j]])
            if np.all(H @ p <= h + 1e-9):
                pts.append(tuple(p))
    c = np.mean(pts, axis=0)
    return sorted(set(pts), key=lambda p: np.arctan2(p[1] - c[1], p[0] - c[0]))


def test_single_integrator_is_supported_by_both():
    from plansynth.reach.planners.milp_bigm import plan_milp_bigm
    from plansynth.reach.planners.ompl import plan_rrt

    p = ReachProblem(
        workspace=Box((0.0, 0.0), (5.0, 5.0)),
        obstacles=(Box((2.0, 0.0), (3.0, 4.0)),),
        goal=Box((4.0, 0.0), (5.0, 1.0)),
        dynamics=single_integrator(2, 1.0),
        start=np.array([0.5, 0.5]),
        input_bound=1.0,
        name="wall",
    )
    for r in (plan_milp_bigm(p, Budget(seconds=20)), plan_rrt(p, Budget(seconds=20), seed=2)):
        assert r.status == ReachStatus.FOUND and validate(p, r.trajectory).ok


def test_rrt_edges_do_not_hop_over_a_thin_wall_unless_asked():
    from plansynth.reach.planners.ompl import plan_rrt

    # a 0.2 m wall with a gap at the top: one step can carry the robot across it
    p = _open_problem([Box((5.0, 0.0), (5.2, 9.0))])
    safe = plan_rrt(p, Budget(seconds=20), seed=4)
    assert safe.status == ReachStatus.FOUND and validate(p, safe.trajectory).segment_safe
    assert safe.guarantee == "segments"
    loose = plan_rrt(p, Budget(seconds=20), seed=4, segment_safe=False)
    assert loose.status == ReachStatus.FOUND and loose.guarantee == "samples"
    assert validate(p, loose.trajectory).ok


def test_baselines_are_planners_of_reach_solve():
    import plansynth.reach.planners.milp_bigm  # noqa: F401 - registers on import
    import plansynth.reach.planners.ompl  # noqa: F401
    from plansynth.reach.solve import planners, solve

    assert {"rrt", "est", "kpiece", "milp-bigm"} <= set(planners())
    p = _open_problem()
    for name in ("rrt", "milp-bigm"):
        r = solve(p, planner=name, budget=Budget(seconds=20))
        assert r.planner == name and r.status == ReachStatus.FOUND and r.validated is True


@pytest.mark.parametrize("planner", ["lazy-smt-paper", "milp-bigm", "rrt"])
def test_bench_runs_every_planner_through_solve(planner: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """One path: bench's run of any planner is reach.solve()'s answer, validated there."""
    import importlib

    from plansynth.bench.execute import execute
    from plansynth.bench.families import family

    reach_solve = importlib.import_module("plansynth.reach.solve")  # the module (plansynth.reach.solve is the function)
    calls: list[tuple[str, object]] = []
    real = reach_solve.solve

    def spy(problem, planner_name, budget, options=None, **kw):
        calls.append((planner_name, options))
        return real(problem, planner_name, budget, options, **kw)

    monkeypatch.setattr(reach_solve, "solve", spy)
    inst = family("reach", "maze", [1])[0]
    attrs = execute(
        {"instance": inst.to_dict(), "solver": planner, "repeat": 0, "timeout": 60, "seed": 5, "options": {}}
    )
    assert [name for name, _ in calls] == [planner]
    assert attrs["status"] == "solved" and attrs["valid"] == 1, attrs.get("message")
    # the version the run reports (the planner's own), not one guessed from its name
    # (which made lazy-smt-paper a "plansynth" run)
    package = {"lazy-smt-paper": "python-sat", "milp-bigm": "highspy", "rrt": "ompl"}[planner]
    assert attrs["solver_version"].split()[0] == package, attrs["solver_version"]
    if planner == "rrt":  # the sampling planners get the run's seed in their options value
        assert calls[0][1].seed == 5


@pytest.mark.parametrize("planner", ["lazy-smt", "milp-ltl"])
def test_bench_runs_a_mission_and_records_it_solved(planner: str) -> None:
    """The missions family through the bench: solved and validated, no oracle
    LP (the reach-avoid oracle indexes the unlabelled abstraction and has no loop closure;
    it crashed every mission run)."""
    from plansynth.bench.execute import execute
    from plansynth.bench.families import family

    inst = next(i for i in family("reach", "missions", [1]) if i.name == "maze-1-avoid-until")
    attrs = execute(
        {"instance": inst.to_dict(), "solver": planner, "repeat": 0, "timeout": 120, "seed": 0, "options": {}}
    )
    assert attrs["status"] == "solved" and attrs["valid"] == 1, attrs.get("message")
    assert attrs["horizon"] == 30 and attrs["attributes"]["oracle_lp"] is None  # (a finite plan ends at rest)
    # milp-ltl solves with HiGHS (its version was guessed as plansynth's from the name)
    assert attrs["solver_version"].split()[0] == {"lazy-smt": "python-sat", "milp-ltl": "highspy"}[planner]


def test_bench_records_the_version_a_reach_result_reports():
    """The version of a reach run is the result's ``solver_version`` when it reports one,
    else the registered planner's ``version()``; never a name-to-package guess."""
    from plansynth.bench.execute.reach import reported_version
    from plansynth.reach.planners import get_planner

    class Reports:
        def to_json_dict(self):
            return {"solver_version": "highspy 0.0-test"}

    class Silent:
        def to_json_dict(self):
            return {"versions": {"highspy": "0.0"}}

    assert reported_version(Reports(), "lazy-smt-paper") == "highspy 0.0-test"
    for name in ("lazy-smt-paper", "milp-ltl", "milp-ltl-oneshot", "lazy-smt-minimal"):
        assert reported_version(Silent(), name) == get_planner(name).version()
    assert reported_version(Silent(), "milp-ltl").startswith("highspy")
    assert reported_version(Silent(), "lazy-smt-paper").startswith("python-sat")

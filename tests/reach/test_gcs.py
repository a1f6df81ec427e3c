"""The GCS baseline (Marcucci et al., Science Robotics 2023, through Drake): a validated
continuous-time curve on maze-1, the convex variant, the budget, the guarantee."""

from __future__ import annotations

import numpy as np
import pytest

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus
from plansynth.reach.solve import planners, solve
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import validate


@pytest.fixture(scope="module")
def maze1_gcs():
    return solve(maze(1), "gcs", Budget(seconds=120))


def test_gcs_is_a_planner_of_solve():
    assert "gcs" in planners()


def test_gcs_finds_a_validated_curve_on_maze_1(maze1_gcs):
    r = maze1_gcs
    assert r.status is ReachStatus.FOUND, r.message
    assert r.planner == "gcs" and r.guarantee == "curve" and r.validated is True
    assert r.validation.dynamics == "curve" and r.curve_validation.dynamics == "curve"
    assert r.curve_validation.ok and r.curve_validation.segment_safe  # the dense curve, segment by segment
    X, U = r.trajectory.states, r.trajectory.inputs
    assert r.horizon == r.trajectory.horizon and np.allclose(X[0], maze(1).start)
    assert np.abs(X[:, 2:]).max() <= 2.0 + 1e-6 and np.abs(U).max() <= 1.0 + 1e-6
    assert "NOT a trajectory of the exact discrete dynamics" in r.message
    # the samples are not a trajectory of x' = A x + B u: the exact validator says so
    exact = validate(maze(1), r.trajectory)
    assert not exact.ok and "dynamics" in exact.counts
    assert r.to_json_dict()["curve_validation"]["ok"] is True


def test_like_for_like_is_not_over_constrained(maze1_gcs):
    """Velocity continuity only, not also dr/ds continuity (which would force equal piece
    durations or a stop at every junction): the curve is the issue's 32.5 s on maze-1, not
    the 38.9 s of the over-constrained form, and its velocity is continuous at every
    junction of pieces (checked on the dense curve, which includes every piece's ends)."""
    r = maze1_gcs
    assert 32.0 <= r.counters["gcs_duration"] <= 33.0, r.counters
    assert r.counters["curve_seconds"] == pytest.approx(32.5)
    t = np.array(r.curve_times)
    V = np.asarray(r.curve.states)[:, 2:]
    jumps = np.abs(np.diff(V, axis=0)).max(axis=1) / np.maximum(np.diff(t), 1e-12)
    assert jumps.max() <= 1.0 + 1e-3  # |dv/dt| <= |a| bound: no velocity jump anywhere


def test_the_gcs_curve_is_collision_free_by_our_validator(maze1_gcs):
    """Cross-check: every dense sample and every segment between them avoid the walls,
    checked by the validator's own geometry (it does not know the regions)."""
    p = maze(1)
    dense = maze1_gcs.curve
    rep = validate(p, dense, require_segment_safe=True, dynamics="curve", times=np.array(maze1_gcs.curve_times))
    assert rep.ok and rep.segment_safe
    # the same curve pushed into a wall fails
    moved = np.array(dense.states)
    mid = len(moved) // 2
    moved[mid, 1] = 15.0
    moved[mid, 0] = 10.0
    bad = validate(p, Trajectory(moved, dense.inputs), dynamics="curve")
    assert not bad.ok and "obstacle" in bad.counts


def test_the_derivative_check_catches_a_velocity_jump(maze1_gcs):
    dense = maze1_gcs.curve
    X = np.array(dense.states)
    k = len(X) // 3
    X[k:, 2] = np.clip(X[k:, 2] + 0.5, -2, 2)  # velocity jumps by 0.5 in one sample gap
    rep = validate(maze(1), Trajectory(X, dense.inputs), dynamics="curve", times=np.array(maze1_gcs.curve_times))
    assert not rep.ok and "derivative" in rep.counts


def test_the_derivative_check_catches_a_position_that_moves_against_its_velocity(maze1_gcs):
    """Positions against the sampled velocities (found by a review: only each block's own
    change was bounded, so the curve could shift sideways, within |v| <= 2 per sample
    gap, while its velocity samples said it moved along)."""
    dense = maze1_gcs.curve
    X = np.array(dense.states)
    t = np.array(maze1_gcs.curve_times)
    k = len(X) // 3
    X[k:, 1] += 0.05  # y shifted by 5 cm at one sample gap, the velocities left as they are
    rep = validate(maze(1), Trajectory(X, dense.inputs), dynamics="curve", times=t)
    assert not rep.ok and "derivative" in rep.counts
    assert any("derivative 1 allows" in v.detail for v in rep.violations if v.kind == "derivative")


def test_the_convex_variant_runs_and_is_not_a_peer_of_the_dynamics():
    r = solve(maze(1), "gcs", Budget(seconds=120), variant="convex")
    assert r.options["variant"] == "convex"
    # its curve jumps in velocity and exceeds |a| <= 1: the validator refuses it
    assert r.curve is not None and r.curve_validation is not None
    assert r.status is ReachStatus.UNKNOWN and r.validated is False
    assert {"input", "derivative"} & set(r.curve_validation.counts)


def test_gcs_budget_gives_unknown():
    r = solve(maze(3), "gcs", Budget(seconds=0.05))
    assert r.status is ReachStatus.UNKNOWN
    assert "budget" in r.message or "no curve" in r.message


def test_gcs_refuses_dynamics_it_cannot_pose():
    with pytest.raises(SolverUnavailable, match="single- and double-integrator"):
        solve(maze(1, order=3), "gcs", Budget(seconds=10))


def test_gcs_unknown_variant():
    with pytest.raises(ValueError, match="variant"):
        solve(maze(1), "gcs", Budget(seconds=10), variant="fast")


def test_single_integrator_gcs():
    from plansynth.reach.dynamics import single_integrator

    p = ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Box((3, 0), (4, 7)),),
        goal=Box((8, 1), (9, 2)),
        dynamics=single_integrator(2, 1.0),
        start=[1, 1],
        input_bound=1.0,
    )
    r = solve(p, "gcs", Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.validated, r.message
    assert np.abs(r.trajectory.inputs).max() <= 1.0 + 1e-6


def test_the_surrogate_variant_jumps_in_velocity_and_is_refused():
    """Drake's convex surrogate of velocity continuity (dr/ds continuous) is velocity
    continuity only at equal piece durations: the derivative check catches the jump."""
    r = solve(maze(1), "gcs", Budget(seconds=120), variant="surrogate")
    assert r.options["variant"] == "surrogate" and r.curve_validation is not None
    assert r.status is ReachStatus.UNKNOWN and "derivative" in r.curve_validation.counts


def test_cli_solves_with_gcs_and_validates_the_curve_result(tmp_path):
    import yaml
    from typer.testing import CliRunner

    from plansynth.cli import app
    from plansynth.reach.fileformat import reach_problem_to_dict

    f = tmp_path / "maze-1.yaml"
    f.write_text(yaml.safe_dump(reach_problem_to_dict(maze(1))))
    out = tmp_path / "r.json"
    run = CliRunner().invoke(app, ["reach", "solve", str(f), "--planner", "gcs", "--timeout", "120", "--out", str(out)])
    assert run.exit_code == 0, run.output
    assert "curve" in run.output
    ok = CliRunner().invoke(app, ["reach", "validate", str(f), str(out)])
    assert ok.exit_code == 0 and "dynamics: curve" in ok.output, ok.output
    exact = CliRunner().invoke(app, ["reach", "validate", str(f), str(out), "--dynamics", "exact"])
    assert exact.exit_code == 1 and "dynamics" in exact.output
    bad = CliRunner().invoke(app, ["reach", "solve", str(f), "--planner", "lazy-smt", "--variant", "convex"])
    assert bad.exit_code != 0


def test_large_graphs_round_to_one_path(maze1_gcs):
    """Beyond PREPROCESS_MAX_REGIONS regions one rounded path gets the whole restriction
    share (five shares left the 20 x 20 GCS maze's IPOPT restriction 10 s of the 40 s it
    needs); an explicit request wins, and maze-1 keeps Drake's five."""
    from plansynth.reach.planners import gcs

    assert maze1_gcs.options["max_rounded_paths"] == gcs.DEFAULT_MAX_ROUNDED_PATHS == 5
    assert gcs.rounded_paths(gcs.PREPROCESS_MAX_REGIONS) == 5
    assert gcs.rounded_paths(gcs.PREPROCESS_MAX_REGIONS + 1) == gcs.LARGE_MAX_ROUNDED_PATHS == 1
    assert gcs.rounded_paths(1571, 3) == 3
    with pytest.raises(ValueError, match="at least 1"):
        gcs.rounded_paths(10, 0)


def test_gcs_plans_through_overlapping_boxes_by_default():
    """GCS as its users set it up: the maximal free boxes (overlapping), not the lazy
    planner's decomposition; the decomposition stays an option (sets=decomposition)."""
    r = solve(maze(2), "gcs", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.validated, r.message
    assert r.options["sets"] == "boxes" and r.counters["regions"] == 5 and r.counters["set_edges"] == 4
    assert r.regions is None and len(r.counters["set_sequence"]) == r.counters["pieces"]
    d = solve(maze(2), "gcs", Budget(seconds=120), sets="decomposition")
    assert d.status is ReachStatus.FOUND and d.validated, d.message
    assert d.options["sets"] == "decomposition" and d.regions is not None and d.counters["regions"] == 5
    with pytest.raises(Exception, match="sets"):
        solve(maze(2), "gcs", Budget(seconds=10), sets="voronoi")


def test_gcs_over_iris_regions_where_obstacles_are_polygons():
    from plansynth.reach.dynamics import double_integrator
    from plansynth.reach.geometry import Polygon

    p = ReachProblem(
        workspace=Box((0, 0), (10, 10)),
        obstacles=(Polygon(((3, 0), (5, 0), (4, 7))), Polygon(((6, 10), (7, 3), (8, 10)))),
        goal=Box((8.5, 1), (9.5, 2)),
        dynamics=double_integrator(2, 0.5),
        start=[1, 1, 0, 0],
        input_bound=1.0,
        state_bounds=Box((0, 0, -2, -2), (10, 10, 2, 2)),
    )
    r = solve(p, "gcs", Budget(seconds=120))
    assert r.options["sets"] == "iris" and r.counters["regions"] >= 3
    assert r.status is ReachStatus.FOUND and r.validated, r.message
    assert r.curve_validation.ok and r.curve_validation.segment_safe

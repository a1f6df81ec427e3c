"""The independent validator: good trajectories pass, each kind of violation is caught."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString
from shapely.geometry import box as sh_box

from plansynth.reach.dynamics import double_integrator, single_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import VIOLATION_KINDS, _segment_enters_open_box, validate

# A 10 x 10 room, a box obstacle, an L-shaped polygon, goal at the top right.
ROOM = dict(
    workspace=Box((0, 0), (10, 10)),
    obstacles=(Box((2, 2), (4, 4)), Polygon(((6, 1), (9, 1), (9, 2), (7, 2), (7, 5), (6, 5)))),
    goal=Box((8, 8), (9.5, 9.5)),
)


def single(**kw) -> ReachProblem:
    return ReachProblem(**{**ROOM, "dynamics": single_integrator(2, 1.0), "start": [1, 1], "input_bound": 2.0, **kw})


def path_trajectory(points, dt: float = 1.0) -> Trajectory:
    """Single integrator through ``points``: u_t = (p_{t+1} - p_t) / dt."""
    P = np.array(points, dtype=float)
    return Trajectory(states=P, inputs=np.diff(P, axis=0) / dt)


GOOD = [(1, 1), (1, 3), (1, 5), (3, 5), (5, 5), (5, 7), (7, 7), (8.5, 8.5)]


def kinds(report) -> list[str]:
    return [v.kind for v in report.violations]


def test_good_trajectory_passes() -> None:
    r = validate(single(), path_trajectory(GOOD))
    assert r.ok and r.segment_safe and r.violations == ()
    assert r.max_dynamics_error == 0.0 and r.max_input == 2.0 and r.horizon == 7
    assert validate(single(), path_trajectory(GOOD), require_segment_safe=True).ok
    assert "valid" in r.summary()


def test_report_has_no_truth_value() -> None:
    r = validate(single(), path_trajectory(GOOD))
    with pytest.raises(TypeError):
        bool(r)


def test_double_integrator_rollout_passes() -> None:
    p = maze(1)
    # a rollout of the exact dynamics inside the bottom corridor of maze-1, with the goal
    # moved to where it ends
    fields = {k: getattr(p, k) for k in p.__dataclass_fields__}
    x = p.start.copy()
    X, U = [x], []
    for t in range(8):
        u = np.array([0.5, 1.0]) if t < 4 else np.array([-0.5, -1.0])
        x = p.dynamics.step(x, u)
        X.append(x)
        U.append(u)
    end = X[-1][:2]
    q = ReachProblem(**{**fields, "goal": Box(tuple(end - 0.5), tuple(end + 0.5))})
    r = validate(q, Trajectory(np.array(X), np.array(U)))
    assert r.ok, r.violations
    assert r.max_dynamics_error < 1e-12


@pytest.mark.parametrize(
    "mutate, kind, step",
    [
        (lambda X, U: X.__setitem__((3, 0), X[3, 0] + 0.01), "dynamics", 2),
        (lambda X, U: X.__setitem__((0, 1), 1.5), "start", 0),
    ],
    ids=["dynamics", "start"],
)
def test_mutations_are_caught(mutate, kind: str, step: int) -> None:
    t = path_trajectory(GOOD)
    X, U = t.states.copy(), t.inputs.copy()
    mutate(X, U)
    r = validate(single(), Trajectory(X, U))
    assert not r.ok and kind in kinds(r)
    assert any(v.kind == kind and v.step == step for v in r.violations)


def test_input_bound() -> None:
    r = validate(single(input_bound=1.5), path_trajectory(GOOD))
    assert not r.ok and set(kinds(r)) == {"input"}
    assert [v.step for v in r.violations] == [0, 1, 2, 3, 4, 5]  # every 2 m/s step; the last is 1.5
    assert "exceeds the bound" in r.violations[0].detail


def test_state_bound() -> None:
    p = single(state_bounds=Box((0, 0), (10, 6)))  # y <= 6 but the path goes to y = 8.5
    r = validate(p, path_trajectory(GOOD))
    assert not r.ok and set(kinds(r)) == {"state-bound"}
    assert [v.step for v in r.violations] == [5, 6, 7]


def test_velocity_state_bound_of_double_integrator() -> None:
    dyn = double_integrator(2, 1.0)
    p = ReachProblem(
        **ROOM, dynamics=dyn, start=[1, 1, 0, 0], input_bound=3.0, state_bounds=Box((0, 0, -2, -2), (10, 10, 2, 2))
    )
    X = [np.array([1.0, 1, 0, 0])]
    U = [np.array([0.0, 3.0])]
    X.append(dyn.step(X[0], U[0]))  # vy = 3 > 2
    r = validate(p, Trajectory(np.array(X), np.array(U)))
    assert "state-bound" in kinds(r) and "x_1[3]" in r.violations[kinds(r).index("state-bound")].detail


def test_obstacle_box_and_polygon_samples() -> None:
    r = validate(single(), path_trajectory([(1, 1), (3, 3), (6.5, 3), (8.5, 8.5)]))
    hits = [(v.step, v.detail) for v in r.violations if v.kind == "obstacle"]
    assert [s for s, _ in hits] == [1, 2]
    assert "obstacles[0]" in hits[0][1] and "obstacles[1]" in hits[1][1]


def test_workspace() -> None:
    r = validate(single(input_bound=10), path_trajectory([(1, 1), (-1, 5), (5, 11), (8.5, 8.5)]))
    assert [v.step for v in r.violations if v.kind == "workspace"] == [1, 2]


def test_goal() -> None:
    r = validate(single(), path_trajectory(GOOD[:-1]))
    assert not r.ok and kinds(r) == ["goal"] and r.violations[0].step == 6


def test_segment_cutting_a_box_corner_while_samples_are_free() -> None:
    pts = [(1, 1), (1, 3), (3, 4.6), (5, 5), (5, 7), (7, 7), (8.5, 8.5)]  # (1,3)->(3,4.6) clips (2..4)^2 near (2,4)
    t = path_trajectory(pts)
    r = validate(single(), t)
    assert r.ok and not r.segment_safe  # samples are fine; the paper's guarantee
    strict = validate(single(), t, require_segment_safe=True)
    assert not strict.ok and kinds(strict) == ["segment"] and strict.violations[0].step == 1


def test_segment_cutting_a_polygon_notch() -> None:
    # both samples lie outside the L (in its notch and beside it); the segment crosses its arm
    p = single(input_bound=5)
    t = path_trajectory([(1, 1), (5, 1.5), (8, 3), (8, 6), (8.5, 8.5)])
    r = validate(p, t, require_segment_safe=True)
    assert kinds(r) == ["segment"] and [v.step for v in r.violations] == [1]
    assert "obstacles[1]" in r.violations[0].detail


def test_touching_boundaries_is_allowed() -> None:
    # samples on the box's edges and the segment sliding along its top edge
    pts = [(1, 1), (2, 1), (2, 2), (2, 3), (2, 4), (4, 4), (5, 5), (6, 6), (7, 7), (8, 8)]
    r = validate(single(), path_trajectory(pts), require_segment_safe=True)
    assert r.ok and r.segment_safe, r.violations
    # a point just inside, within tolerance
    pts2 = [(1, 1), (2, 1), (2 + 1e-9, 2.5), (2, 4), (4, 4), (5, 5), (6, 6), (7, 7), (8, 8)]
    assert validate(single(), path_trajectory(pts2), require_segment_safe=True).ok
    pts3 = [(1, 1), (2, 1), (2 + 1e-3, 2.5), (2, 4), (4, 4), (5, 5), (6, 6), (7, 7), (8, 8)]
    r3 = validate(single(), path_trajectory(pts3))
    assert kinds(r3) == ["obstacle"]


def test_shape_mismatch_and_nan() -> None:
    r = validate(single(), Trajectory(states=np.zeros((2, 3)), inputs=np.zeros((1, 2))))
    assert kinds(r) == ["shape"] and not r.ok
    X = np.array(GOOD, dtype=float)
    X[2, 0] = np.nan
    r = validate(single(), Trajectory(states=X, inputs=np.zeros((len(X) - 1, 2))))
    assert kinds(r) == ["shape"]


def test_horizon_zero_start_in_goal() -> None:
    p = single(start=[8.5, 8.5])
    r = validate(p, Trajectory(states=[[8.5, 8.5]], inputs=np.zeros((0, 2))))
    assert r.ok and r.horizon == 0


def test_3d_segment_through_a_box_corner() -> None:
    p = ReachProblem(
        workspace=Box((0, 0, 0), (6, 6, 6)),
        obstacles=(Box((2, 2, 2), (4, 4, 4)),),
        goal=Box((5, 5, 5), (6, 6, 6)),
        dynamics=single_integrator(3, 1.0),
        start=[1, 1, 1],
        input_bound=10,
    )
    t = path_trajectory([(1, 1, 1), (1, 3.5, 3.5), (3.5, 5, 5), (5.5, 5.5, 5.5)])
    r = validate(p, t)
    assert r.ok and r.segment_safe
    t2 = path_trajectory([(1, 1, 1), (1, 1, 3), (3, 5, 3), (5.5, 5.5, 5.5)])  # (1,1,3)->(3,5,3) cuts the edge x=2, y=4
    r2 = validate(p, t2, require_segment_safe=True)
    assert kinds(r2) == ["segment"] and r2.violations[0].step == 1


def test_kinds_are_documented() -> None:
    assert set(VIOLATION_KINDS) == {
        "shape",
        "start",
        "dynamics",
        "input",
        "state-bound",
        "workspace",
        "obstacle",
        "goal",
        "segment",
        "derivative",
    }


# ------------------------------------------------------- the box clipper against shapely

coord = st.floats(-2, 8, allow_nan=False).map(lambda v: round(v, 2))


@settings(max_examples=300)
@given(
    p=st.tuples(coord, coord),
    q=st.tuples(coord, coord),
    lo=st.tuples(coord, coord),
    ext=st.tuples(st.floats(0.1, 4), st.floats(0.1, 4)),
)
def test_segment_box_clipper_agrees_with_shapely(p, q, lo, ext) -> None:
    hi = (lo[0] + ext[0], lo[1] + ext[1])
    box = sh_box(lo[0], lo[1], hi[0], hi[1])
    geom = shapely.Point(p) if p == q else LineString([p, q])
    expected = bool(shapely.relate_pattern(box, geom, "T********"))
    assert _segment_enters_open_box(np.array(p), np.array(q), np.array(lo), np.array(hi)) == expected


# ------------------------------------------------------- trajectories from result files


def test_load_trajectory_round_trip(tmp_path) -> None:
    import json

    from plansynth.reach.trajectory import load_trajectory, trajectory_to_lists

    t = path_trajectory(GOOD)
    states, inputs = trajectory_to_lists(t)
    f = tmp_path / "r.json"
    f.write_text(json.dumps({"status": "found", "planner": "x", "states": states, "inputs": inputs, "extra": 1}))
    assert load_trajectory(f) == t


@pytest.mark.parametrize(
    "doc, match",
    [
        ({"status": "unknown", "states": None, "inputs": None}, "states: no trajectory in this result"),
        ({"inputs": []}, "states: missing required field"),
        ({"states": [[0, 0], [1, 1]]}, "inputs: missing required field"),
        ({"states": [], "inputs": []}, "states: expected a non-empty list"),
        ({"states": [[0, 0], [1]], "inputs": [[1, 1]]}, r"states\[1\]: has 1 components"),
        ({"states": [[0, 0], [1, 1]], "inputs": []}, "inputs: expected 1 inputs"),
        ({"states": [[0, 0], [1, 1], [2, 2]], "inputs": [[1, 1], [1]]}, r"inputs\[1\]: has 1 components"),
        ({"states": [[0, "a"]], "inputs": []}, r"states\[0\]\[1\]: expected a finite number"),
    ],
)
def test_bad_result_files(tmp_path, doc, match) -> None:
    import json

    from plansynth.errors import InvalidProblem
    from plansynth.reach.trajectory import load_trajectory

    f = tmp_path / "r.json"
    f.write_text(json.dumps(doc))
    with pytest.raises(InvalidProblem, match=match):
        load_trajectory(f)


def test_each_dynamics_row_is_held_to_its_own_size() -> None:
    """Far from the origin (positions near 1e6) a tolerance scaled by |x|_inf allowed a
    velocity error of 0.9 per step: a trajectory that gains 0.9 m/s a step with u = 0
    passed (found by a review). Each row is now held to the size of its own terms."""
    from dataclasses import replace

    o = 1e6
    dyn = double_integrator(2, 1.0)
    p = ReachProblem(
        workspace=Box((o, o), (o + 10, o + 10)),
        obstacles=(),
        goal=Box((o + 7, o), (o + 8, o + 10)),
        dynamics=dyn,
        start=[o + 1, o + 1, 0, 0],
        input_bound=0.1,
    )
    X = [np.array([o + 1, o + 1, 0, 0])]
    for _ in range(4):
        nxt = dyn.A @ X[-1]
        nxt[2] += 0.9  # a velocity nobody's input gives
        X.append(nxt)
    r = validate(p, Trajectory(np.array(X), np.zeros((4, 2))))
    assert not r.ok and r.counts.get("dynamics") == 4
    # the honest rollout at the same coordinates passes
    Y = [np.array([o + 1, o + 1, 0, 0])]
    for _ in range(12):
        Y.append(dyn.A @ Y[-1] + dyn.B @ np.array([0.1, 0.0]))
    assert validate(
        replace(p, goal=Box((o + 7, o), (o + 10, o + 10))), Trajectory(np.array(Y), np.tile([0.1, 0.0], (12, 1)))
    ).ok

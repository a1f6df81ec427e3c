"""Problem model and loader: good files load, every kind of bad input is named."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from plansynth.errors import InvalidProblem
from plansynth.reach.families import cluttered, dubins_example, maze, random_workspace
from plansynth.reach.fileformat import load_reach_problem, reach_problem_from_dict, reach_problem_to_dict
from plansynth.reach.geometry import Box, Polygon, halfspaces, is_convex
from plansynth.reach.problem import ReachProblem

SPEC_EXAMPLE = """
workspace: {min: [0, 0], max: [30, 30]}      # axis-aligned box, 2-D or 3-D
obstacles:                                   # boxes or polygons (2-D: vertex lists)
  - {min: [0, 9.5], max: [28, 10.5]}
  - [[12, 14], [16, 14], [14, 18]]
goal: {min: [27, 27], max: [29, 29]}         # a box or a convex polygon
robot:
  dynamics: {model: double-integrator, dt: 0.5}
  start: [1, 1, 0, 0]
  input_bound: 1.0                           # ||u||_inf <= input_bound
  state_bounds: {min: [0, 0, -2, -2], max: [30, 30, 2, 2]}   # optional
max_horizon: 200                             # optional
"""


def base() -> dict:
    return yaml.safe_load(SPEC_EXAMPLE)


def load(doc: dict) -> ReachProblem:
    return reach_problem_from_dict(doc, source="p.yaml")


def with_(path: str, value, doc: dict | None = None) -> dict:
    """A copy of ``doc`` (default: the spec example) with ``value`` at dotted ``path``;
    ``value=...`` deletes the key."""
    d = copy.deepcopy(base() if doc is None else doc)
    keys = path.split(".")
    cur = d
    for k in keys[:-1]:
        cur = cur[int(k)] if isinstance(cur, list) else cur[k]
    last = keys[-1]
    if value is ...:
        del cur[last]
    elif isinstance(cur, list):
        cur[int(last)] = value
    else:
        cur[last] = value
    return d


# ----------------------------------------------------------------- good input


def test_spec_example_loads(tmp_path: Path) -> None:
    f = tmp_path / "spec.yaml"
    f.write_text(SPEC_EXAMPLE)
    p = load_reach_problem(f)
    assert p.dim == 2 and p.name == "spec" and p.source == str(f)
    assert p.dynamics.model == "double-integrator" and p.dynamics.n_states == 4 and p.dynamics.n_inputs == 2
    assert p.start.tolist() == [1, 1, 0, 0] and p.max_horizon == 200
    assert isinstance(p.obstacles[0], Box) and isinstance(p.obstacles[1], Polygon)
    assert p.state_bounds == Box((0, 0, -2, -2), (30, 30, 2, 2))
    assert not p.start.flags.writeable and not p.dynamics.A.flags.writeable


def test_json_is_the_same_structure(tmp_path: Path) -> None:
    f = tmp_path / "spec.json"
    f.write_text(json.dumps(base()))
    g = tmp_path / "spec.yaml"
    g.write_text(SPEC_EXAMPLE)
    assert load_reach_problem(f) == load_reach_problem(g)


def test_optional_fields_default() -> None:
    d = with_("max_horizon", ...)
    d = with_("robot.state_bounds", ..., d)
    d = with_("obstacles", ..., d)
    p = load(d)
    assert p.max_horizon == 200 and p.state_bounds is None and p.obstacles == ()


@pytest.mark.parametrize(
    "problem",
    [
        maze(1),
        maze(4),
        maze(2, order=5),
        cluttered(),
        dubins_example(),
        random_workspace(7, 6),
        random_workspace(2, 4, dim=3),
    ],
)
def test_round_trip(problem: ReachProblem, tmp_path: Path) -> None:
    doc = reach_problem_to_dict(problem)
    assert reach_problem_from_dict(doc) == problem
    f = tmp_path / f"{problem.name}.yaml"
    f.write_text(yaml.safe_dump(doc))
    assert load_reach_problem(f) == problem
    assert hash(load_reach_problem(f)) == hash(problem)


def test_explicit_matrices_and_3d() -> None:
    doc = {
        "workspace": {"min": [0, 0, 0], "max": [5, 5, 5]},
        "obstacles": [{"min": [1, 1, 1], "max": [2, 2, 2]}],
        "goal": {"min": [4, 4, 4], "max": [5, 5, 5]},
        "robot": {
            "dynamics": {"A": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "B": [[1], [1], [1]], "position": [2, 0, 1]},
            "start": [0, 0, 0],
            "input_bound": 0.5,
        },
    }
    p = load(doc)
    assert p.dim == 3 and p.dynamics.model == "explicit" and p.dynamics.dt is None
    assert p.dynamics.position == (2, 0, 1) and p.dynamics.B.shape == (3, 1)
    assert reach_problem_from_dict(reach_problem_to_dict(p)) == p


def test_integrator_chain_and_polygon_goal() -> None:
    d = with_("robot.dynamics", {"model": "integrator-chain", "order": 3, "dt": 0.5})
    d = with_("robot.start", [1, 1, 0, 0, 0, 0], d)
    d = with_("robot.state_bounds", ..., d)
    d = with_("goal", [[27, 27], [29, 27], [28, 29]], d)
    p = load(d)
    assert p.dynamics.n_states == 6 and p.dynamics.order == 3
    assert isinstance(p.goal, Polygon) and is_convex(p.goal)


def test_polygons_are_stored_ccw_and_may_be_nonconvex() -> None:
    d = with_("obstacles.1", [[12, 14], [12, 18], [13, 15], [16, 14]])  # clockwise, non-convex
    p = load(d)
    poly = p.obstacles[1]
    assert poly.area() > 0 and not is_convex(poly)
    with pytest.raises(ValueError, match="convex"):
        halfspaces(poly)


def test_halfspaces_describe_the_shape() -> None:
    tri = Polygon(((0, 0), (4, 0), (0, 2)))
    H, h = halfspaces(tri)
    assert np.allclose(np.linalg.norm(H, axis=1), 1)
    for pt, inside in [((1, 0.5), True), ((0, 0), True), ((3, 1), False), ((-0.1, 1), False)]:
        assert bool(np.all(H @ np.array(pt) <= h + 1e-12)) == inside


# ----------------------------------------------------------------- bad input: one test per kind

BAD = [
    # semantics named by the spec
    ("start inside an obstacle", with_("robot.start", [5, 10, 0, 0]), "robot.start", "inside obstacles\\[0\\]"),
    ("start inside a polygon", with_("robot.start", [14, 15, 0, 0]), "robot.start", "inside obstacles\\[1\\]"),
    ("start outside the workspace", with_("robot.start", [-1, 1, 0, 0]), "robot.start", "outside the workspace"),
    (
        "goal inside obstacles",
        with_("goal", {"min": [1, 9.6], "max": [2, 10.4]}),
        "goal",
        "unreachable: it lies inside obstacles",
    ),
    (
        "goal covered by two obstacles",
        with_("obstacles", [{"min": [26, 26], "max": [28, 30]}, {"min": [28, 26], "max": [30, 30]}]),
        "goal",
        "inside obstacles",
    ),
    ("goal outside the workspace", with_("goal", {"min": [31, 31], "max": [32, 32]}), "goal", "outside the workspace"),
    (
        "A not square",
        with_("robot.dynamics", {"A": [[1, 0], [0, 1], [0, 0]], "B": [[1, 0], [0, 1]], "position": [0, 1]}),
        "robot.dynamics.A",
        "square",
    ),
    (
        "B rows differ from A",
        with_("robot.dynamics", {"A": [[1, 0], [0, 1]], "B": [[1, 0]], "position": [0, 1]}),
        "robot.dynamics.B",
        "2 rows",
    ),
    (
        "ragged matrix",
        with_("robot.dynamics", {"A": [[1, 0], [0]], "B": [[1], [1]], "position": [0, 1]}),
        "robot.dynamics.A\\[1\\]",
        "row of length 1",
    ),
    (
        "position index out of range",
        with_("robot.dynamics", {"A": [[1, 0], [0, 1]], "B": [[1], [1]], "position": [0, 2]}),
        "robot.dynamics.position",
        "distinct state indices",
    ),
    ("zero input bound", with_("robot.input_bound", 0), "robot.input_bound", "must be positive"),
    ("negative input bound", with_("robot.input_bound", -1.5), "robot.input_bound", "must be positive"),
    ("zero dt", with_("robot.dynamics.dt", 0), "robot.dynamics.dt", "must be positive"),
    ("negative dt", with_("robot.dynamics.dt", -0.5), "robot.dynamics.dt", "must be positive"),
    ("degenerate polygon", with_("obstacles.1", [[1, 1], [2, 2], [3, 3]]), "obstacles\\[1\\]", "degenerate polygon"),
    ("two-vertex polygon", with_("obstacles.1", [[1, 1], [2, 2]]), "obstacles\\[1\\]", "at least 3 vertices"),
    (
        "self-intersecting polygon",
        with_("obstacles.1", [[10, 20], [12, 22], [12, 20], [10, 22]]),
        "obstacles\\[1\\]",
        "self-intersecting",
    ),
    (
        "repeated vertex",
        with_("obstacles.1", [[10, 20], [12, 20], [12, 20], [10, 22]]),
        "obstacles\\[1\\]",
        "repeated vertex",
    ),
    ("flat box", with_("obstacles.0", {"min": [0, 9.5], "max": [28, 9.5]}), "obstacles\\[0\\]", "degenerate box"),
    ("flat workspace", with_("workspace", {"min": [0, 0], "max": [30, 0]}), "workspace", "degenerate box"),
    ("non-convex goal", with_("goal", [[26, 26], [29, 26], [27, 27], [26, 29]]), "goal", "must be convex"),
    # structure: unknown keys, wrong types, dimension mismatches
    ("unknown top-level key", with_("horizon", 10), "horizon", "unknown key"),
    ("unknown robot key", with_("robot.speed", 1), "robot.speed", "unknown key"),
    ("unknown dynamics key", with_("robot.dynamics.mass", 1), "robot.dynamics.mass", "unknown key"),
    ("unknown box key", with_("goal.center", [1, 1]), "goal.center", "unknown key"),
    ("missing robot", with_("robot", ...), "robot", "missing required field"),
    ("missing goal", with_("goal", ...), "goal", "missing required field"),
    ("missing dt", with_("robot.dynamics.dt", ...), "robot.dynamics.dt", "missing required field"),
    ("unknown model", with_("robot.dynamics.model", "bicycle"), "robot.dynamics.model", "unknown model"),
    (
        "chain without order",
        with_("robot.dynamics", {"model": "integrator-chain", "dt": 0.5}),
        "robot.dynamics.order",
        "missing",
    ),
    ("wrong order for model", with_("robot.dynamics.order", 3), "robot.dynamics.order", "has order 2"),
    ("string bound", with_("robot.input_bound", "fast"), "robot.input_bound", "expected a finite number"),
    ("bool dt", with_("robot.dynamics.dt", True), "robot.dynamics.dt", "expected a finite number"),
    ("infinite coordinate", with_("workspace.max", [30, float("inf")]), "workspace.max\\[1\\]", "finite number"),
    ("string obstacle", with_("obstacles.0", "wall"), "obstacles\\[0\\]", "expected a box"),
    ("obstacles not a list", with_("obstacles", {"min": [0, 0], "max": [1, 1]}), "obstacles", "expected a list"),
    ("robot not a mapping", with_("robot", [1, 2]), "robot", "expected a mapping"),
    ("float horizon", with_("max_horizon", 2.5), "max_horizon", "expected an integer"),
    ("zero horizon", with_("max_horizon", 0), "max_horizon", "must be positive"),
    ("start of the wrong length", with_("robot.start", [1, 1]), "robot.start", "expected 4 numbers"),
    (
        "3-D obstacle in 2-D",
        with_("obstacles.0", {"min": [0, 0, 0], "max": [1, 1, 1]}),
        "obstacles\\[0\\].min",
        "expected 2 numbers",
    ),
    (
        "box corners of different lengths",
        with_("goal", {"min": [27, 27], "max": [29, 29, 1]}),
        "goal.max",
        "expected 2 numbers",
    ),
    ("1-D workspace", with_("workspace", {"min": [0], "max": [30]}), "workspace", "2-D or 3-D"),
    (
        "state bounds of the wrong dimension",
        with_("robot.state_bounds", {"min": [0, 0], "max": [30, 30]}),
        "robot.state_bounds",
        "4-dimensional",
    ),
    ("start violates state bounds", with_("robot.start", [1, 1, 3, 0]), "robot.start", "violates robot.state_bounds"),
    (
        "position of the wrong length",
        with_("robot.dynamics", {"A": [[1, 0], [0, 1]], "B": [[1], [1]], "position": [0]}),
        "robot.dynamics.position",
        "expected 2 integers",
    ),
    (
        "vertex with three coordinates",
        with_("obstacles.1", [[12, 14, 0], [16, 14, 0], [14, 18, 0]]),
        "obstacles\\[1\\]\\[0\\]",
        "expected 2 numbers",
    ),
    ("name not a string", with_("name", 3), "name", "expected a string"),
]


@pytest.mark.parametrize("doc, field, reason", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_input_is_named(doc: dict, field: str, reason: str) -> None:
    with pytest.raises(InvalidProblem, match=f"^p\\.yaml: {field}: .*{reason}"):
        load(doc)


def test_polygon_in_3d_is_rejected() -> None:
    d = {
        "workspace": {"min": [0, 0, 0], "max": [5, 5, 5]},
        "obstacles": [[[1, 1], [2, 1], [1, 2]]],
        "goal": {"min": [4, 4, 4], "max": [5, 5, 5]},
        "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [0, 0, 0], "input_bound": 1},
    }
    with pytest.raises(InvalidProblem, match=r"obstacles\[0\]: polygons are 2-D"):
        load(d)


def test_file_errors_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(InvalidProblem, match="nope.yaml: <file>: cannot read"):
        load_reach_problem(tmp_path / "nope.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("workspace: [1, 2\n")
    with pytest.raises(InvalidProblem, match="bad.yaml: <file>: not valid YAML"):
        load_reach_problem(bad)
    top = tmp_path / "list.yaml"
    top.write_text("- 1\n- 2\n")
    with pytest.raises(InvalidProblem, match="list.yaml: <document>: expected a mapping"):
        load_reach_problem(top)


def test_start_on_an_obstacle_boundary_is_allowed() -> None:
    p = load(with_("robot.start", [5, 9.5, 0, 0]))
    assert p.start_position.tolist() == [5, 9.5]


def test_constructed_problems_are_checked_too() -> None:
    p = maze(1)
    fields = {k: getattr(p, k) for k in p.__dataclass_fields__}
    with pytest.raises(InvalidProblem, match="<value>: robot.start: .*inside obstacles"):
        ReachProblem(**{**fields, "start": np.array([10.0, 15.0, 0, 0])})
    with pytest.raises(InvalidProblem, match="robot.input_bound: must be positive"):
        ReachProblem(**{**fields, "input_bound": 0.0})
    with pytest.raises(InvalidProblem, match="robot.start: must be a state of 4"):
        ReachProblem(**{**fields, "start": np.zeros(3)})

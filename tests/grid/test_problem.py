"""Loading grid problems and every rejection the spec lists (spec: grid-problem.md)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from plansynth.errors import InvalidProblem
from plansynth.grid.problem import (
    BUILTIN_MOVES,
    DEFAULT_MAX_STEPS,
    GridProblem,
    Move,
    Obstacle,
    Robot,
    grid_problem_from_dict,
    load_grid_problem,
)

from .strategies import grid_problems, problem_documents

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"


def base() -> dict[str, Any]:
    """Figure 1 of the paper as a document; tests break one field at a time."""
    return {
        "grid": [5, 7],
        "robot": {"start": [1, 1], "goal": [4, 4], "moves": ["stay", "up", "right", "down", "left"]},
        "obstacles": [{"start": [2, 5], "moves": ["up", "down"]}, {"start": [3, 5], "moves": ["stay", "up", "down"]}],
        "walls": [],
    }


def rejects(tmp_path: Path, doc: Any, field: str, reason: str) -> InvalidProblem:
    """Write ``doc`` as YAML, load it, and check the error names the file, field and reason."""
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    with pytest.raises(InvalidProblem, match=re.escape(f"{path}: {field}: ") + reason) as info:
        load_grid_problem(path)
    assert info.value.file == str(path)
    assert info.value.field == field
    return info.value


# -- loading -----------------------------------------------------------------------------


def test_figure1_example_loads() -> None:
    p = load_grid_problem(EXAMPLES / "figure1.yaml")
    assert (p.width, p.height) == (5, 7)
    assert p.robot.start == (1, 1) and p.robot.goal == (4, 4)
    assert [m.name for m in p.robot.moves] == ["stay", "up", "right", "down", "left"]
    assert [o.start for o in p.obstacles] == [(2, 5), (3, 5)]
    assert p.obstacles[1].moves[2] == BUILTIN_MOVES["down"] == Move("down", (0, -1))
    assert p.walls == frozenset() and p.steps is None and p.max_steps == 40
    assert p.name == "figure1" and p.source == str(EXAMPLES / "figure1.yaml")
    assert p.variables == ("rx", "ry", "o0x", "o0y", "o1x", "o1y")
    assert p.max_constant == 6
    assert list(p.path_lengths()) == list(range(1, 41))


def test_yaml_and_json_files_give_the_same_problem(tmp_path: Path) -> None:
    doc = base() | {"walls": [[0, 3], [1, 3]], "steps": 6}
    (tmp_path / "p.yaml").write_text(yaml.safe_dump(doc), encoding="utf-8")
    (tmp_path / "p.json").write_text(json.dumps(doc), encoding="utf-8")
    a = load_grid_problem(tmp_path / "p.yaml")
    b = load_grid_problem(tmp_path / "p.json")
    assert a == b
    assert a.walls == frozenset({(0, 3), (1, 3)})
    assert list(a.path_lengths()) == [6]


def test_custom_moves_with_via() -> None:
    doc = base()
    doc["obstacles"][0]["moves"] = [
        "up",
        {"name": "jump", "to": [0, -2], "via": [[0, -1]]},
        {"name": "hop", "to": [1, 0]},
    ]
    p = grid_problem_from_dict(doc)
    jump = p.obstacles[0].moves[1]
    assert jump == Move("jump", (0, -2), ((0, -1),))
    assert jump.offsets() == ((0, 0), (0, -2), (0, -1))
    assert p.obstacles[0].moves[2].via == ()
    assert jump.to_spec() == {"name": "jump", "to": [0, -2], "via": [[0, -1]]}
    assert p.obstacles[0].moves[2].to_spec() == {"name": "hop", "to": [1, 0]}
    assert p.obstacles[0].moves[0].to_spec() == "up"


def test_offsets_do_not_repeat_cells() -> None:
    m = Move("wiggle", (0, 0), ((1, 0), (0, 0), (1, 0)))
    assert m.offsets() == ((0, 0), (1, 0))


@given(problem_documents(), st.sampled_from([None, "problem", "fig-1"]))
def test_documents_round_trip_through_to_dict(doc: dict[str, Any], name: str | None) -> None:
    p = grid_problem_from_dict(doc if name is None else doc | {"name": name})
    again = grid_problem_from_dict(p.to_dict())
    assert again == p and again.name == p.name
    assert json.loads(json.dumps(p.to_dict())) == p.to_dict()  # plain JSON data


@given(grid_problems())
def test_with_steps_and_path_lengths(p: GridProblem) -> None:
    q = p.with_steps(3)
    assert q.steps == 3 and list(q.path_lengths()) == [3]
    free = p.with_steps(None)
    assert list(free.path_lengths()) == list(range(1, (p.max_steps or DEFAULT_MAX_STEPS) + 1))
    assert len(p.variables) == 2 + 2 * len(p.obstacles)
    assert p.max_constant == max(p.width, p.height) - 1


def test_defaults_and_max_steps() -> None:
    doc = base()
    del doc["walls"]
    p = grid_problem_from_dict(doc)
    assert p.walls == frozenset() and p.source is None and p.name == "problem"
    assert list(p.path_lengths()) == list(range(1, DEFAULT_MAX_STEPS + 1))
    assert list(grid_problem_from_dict(doc | {"max_steps": 3}).path_lengths()) == [1, 2, 3]
    assert grid_problem_from_dict(doc | {"name": "fig"}).name == "fig"
    no_obstacles = grid_problem_from_dict({k: v for k, v in doc.items() if k != "obstacles"})
    assert no_obstacles.obstacles == () and no_obstacles.variables == ("rx", "ry")


# -- every rejection the spec lists --------------------------------------------------------


@pytest.mark.parametrize(
    ("where", "key"),
    [((), "colour"), (("robot",), "speed"), (("obstacles", 0), "name"), (("obstacles", 1, "moves", 0), "cost")],
)
def test_unknown_keys(tmp_path: Path, where: tuple, key: str) -> None:
    doc = base()
    if where == ("obstacles", 1, "moves", 0):
        doc["obstacles"][1]["moves"][0] = {"name": "wait", "to": [0, 0], "cost": 3}
        field = "obstacles[1].moves[0].cost"
    else:
        target = doc
        for w in where:
            target = target[w]
        target[key] = 1
        field = {(): key, ("robot",): f"robot.{key}", ("obstacles", 0): f"obstacles[0].{key}"}[where]
    rejects(tmp_path, doc, field, "unknown key")


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda d: d["robot"].update(start=[5, 1]), "robot.start"),
        (lambda d: d["robot"].update(start=[-1, 0]), "robot.start"),
        (lambda d: d["robot"].update(goal=[4, 7]), "robot.goal"),
        (lambda d: d["obstacles"][1].update(start=[0, 9]), "obstacles[1].start"),
        (lambda d: d.update(walls=[[0, 2], [7, 7]]), "walls"),
    ],
)
def test_cells_outside_the_grid(tmp_path: Path, edit, field: str) -> None:
    doc = base()
    edit(doc)
    rejects(tmp_path, doc, field, r"\[-?\d+, -?\d+\] is outside the 5x7 grid")


@pytest.mark.parametrize(
    ("edit", "field", "reason"),
    [
        (lambda d: d["robot"].update(moves=[]), "robot.moves", "no moves given"),
        (lambda d: d["obstacles"][0].update(moves=[]), "obstacles[0].moves", "no moves given"),
        (lambda d: d["obstacles"][1].pop("moves"), "obstacles[1].moves", "missing required field"),
        (lambda d: d["robot"].pop("moves"), "robot.moves", "missing required field"),
        (lambda d: d["robot"].update(moves="up"), "robot.moves", "expected a list of moves"),
    ],
)
def test_agents_without_moves(tmp_path: Path, edit, field: str, reason: str) -> None:
    doc = base()
    edit(doc)
    rejects(tmp_path, doc, field, reason)


@pytest.mark.parametrize("which", ["start", "goal"])
def test_robot_start_or_goal_on_a_wall(tmp_path: Path, which: str) -> None:
    doc = base()
    cell = doc["robot"][which]
    doc["walls"] = [[0, 0], cell]
    rejects(tmp_path, doc, f"robot.{which}", re.escape(f"{cell} is on a wall"))


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda d: d["robot"].update(start=[1.5, 1]), "robot.start[0]"),
        (lambda d: d["robot"].update(goal=[4, "4"]), "robot.goal[1]"),
        (lambda d: d["robot"].update(start=[True, 1]), "robot.start[0]"),
        (lambda d: d["obstacles"][0].update(start=[2, 5.0]), "obstacles[0].start[1]"),
        (lambda d: d.update(walls=[[0, 0], [1, None]]), "walls[1][1]"),
        (lambda d: d.update(grid=[5, 7.5]), "grid[1]"),
        (lambda d: d.update(steps=2.5), "steps"),
        (lambda d: d.update(max_steps="ten"), "max_steps"),
        (
            lambda d: d["obstacles"][0]["moves"].append({"name": "j", "to": [0, -2], "via": [[0, 0.5]]}),
            "obstacles[0].moves[2].via[0][1]",
        ),
        (lambda d: d["obstacles"][0]["moves"].append({"name": "j", "to": [0.0, 1]}), "obstacles[0].moves[2].to[0]"),
    ],
)
def test_non_integer_coordinates(tmp_path: Path, edit, field: str) -> None:
    doc = base()
    edit(doc)
    rejects(tmp_path, doc, field, "expected an integer")


@pytest.mark.parametrize(
    ("edit", "field", "name"),
    [
        (lambda d: d["robot"]["moves"].append("up"), "robot.moves[5]", "up"),
        (lambda d: d["obstacles"][1]["moves"].append({"name": "stay", "to": [0, 0]}), "obstacles[1].moves[3]", "stay"),
        (
            lambda d: d["obstacles"][0]["moves"].extend([{"name": "j", "to": [0, 2]}, {"name": "j", "to": [0, -2]}]),
            "obstacles[0].moves[3]",
            "j",
        ),
    ],
)
def test_duplicated_move_names(tmp_path: Path, edit, field: str, name: str) -> None:
    doc = base()
    edit(doc)
    rejects(tmp_path, doc, field, re.escape(f"duplicated move name {name!r}"))


@pytest.mark.parametrize(
    ("edit", "field", "reason"),
    [
        (lambda d: d["robot"]["moves"].append("jump"), "robot.moves[5]", "unknown move 'jump'"),
        (lambda d: d["robot"]["moves"].append(3), "robot.moves[5]", "expected a move name or mapping"),
        (lambda d: d["robot"]["moves"].append({"to": [1, 1]}), "robot.moves[5].name", "missing required field"),
        (
            lambda d: d["robot"]["moves"].append({"name": "", "to": [1, 1]}),
            "robot.moves[5].name",
            "expected a non-empty string",
        ),
        (lambda d: d["robot"]["moves"].append({"name": "x"}), "robot.moves[5].to", "missing required field"),
        (
            lambda d: d["robot"]["moves"].append({"name": "x", "to": [1, 1], "via": 3}),
            "robot.moves[5].via",
            "expected a list",
        ),
        (lambda d: d.update(grid=[5]), "grid", "expected 2 integers"),
        (lambda d: d.update(grid=[0, 7]), "grid", "width and height must be >= 1"),
        (lambda d: d.update(steps=0), "steps", "must be >= 1"),
        (lambda d: d.update(max_steps=-3), "max_steps", "must be >= 1"),
        (lambda d: d.update(obstacles={"start": [0, 0]}), "obstacles", "expected a list"),
        (lambda d: d.update(obstacles=["up"]), "obstacles[0]", "expected a mapping"),
        (lambda d: d.update(walls="none"), "walls", "expected a list of cells"),
        (lambda d: d.pop("grid"), "grid", "missing required field"),
        (lambda d: d["robot"].pop("goal"), "robot.goal", "missing required field"),
    ],
)
def test_other_malformed_fields(tmp_path: Path, edit, field: str, reason: str) -> None:
    doc = base()
    edit(doc)
    rejects(tmp_path, doc, field, re.escape(reason))


def test_document_that_is_not_a_mapping(tmp_path: Path) -> None:
    rejects(tmp_path, [1, 2], "<document>", "expected a mapping")


def test_unreadable_and_unparsable_files(tmp_path: Path) -> None:
    missing = tmp_path / "missing.yaml"
    with pytest.raises(InvalidProblem, match=re.escape(f"{missing}: <file>: cannot read")):
        load_grid_problem(missing)
    broken = tmp_path / "broken.json"
    broken.write_text('{"grid": [5, 7', encoding="utf-8")
    with pytest.raises(InvalidProblem, match=re.escape(f"{broken}: <file>: not valid YAML/JSON")):
        load_grid_problem(broken)


def test_problems_built_in_code_are_validated_too() -> None:
    robot = Robot((0, 0), (1, 1), (BUILTIN_MOVES["stay"],))
    with pytest.raises(InvalidProblem, match=re.escape("<value>: robot.goal: [1, 1] is on a wall")):
        GridProblem(2, 2, robot, walls=frozenset({(1, 1)}))
    with pytest.raises(InvalidProblem, match=re.escape("<value>: obstacles[0].moves: the obstacle has no moves")):
        GridProblem(2, 2, robot, obstacles=(Obstacle((0, 1), ()),))
    with pytest.raises(InvalidProblem, match=re.escape("<value>: robot.moves: the robot has no moves")):
        GridProblem(2, 2, Robot((0, 0), (1, 1), ()))
    p = GridProblem(2, 2, robot)
    with pytest.raises(AttributeError):
        p.width = 3  # type: ignore[misc]  # frozen

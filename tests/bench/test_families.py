"""Benchmark families: every instance builds, files round-trip, reactive answers hold."""

from __future__ import annotations

from pathlib import Path

import pytest

from plansynth.bench.families import GRID_FAMILIES, family, grid_family, reach_family, write_family_files
from plansynth.budget import Budget
from plansynth.grid.problem import load_grid_problem
from plansynth.grid.result import GridStatus


@pytest.mark.parametrize("name", [f for f in GRID_FAMILIES if f != "reactive-suite"])
def test_every_grid_instance_builds_and_round_trips_through_a_file(name, tmp_path):
    insts = grid_family(name)
    assert insts
    paths = write_family_files(tmp_path, insts)
    for inst, path in zip(insts, paths):
        p = inst.build()
        q = load_grid_problem(path)
        assert (q.width, q.height, q.robot, q.obstacles, q.walls, q.steps, q.max_steps) == (
            p.width,
            p.height,
            p.robot,
            p.obstacles,
            p.walls,
            p.steps,
            p.max_steps,
        )


def test_paper_parameters():
    (o,) = grid_family("obstacles", [25])
    p = o.build()
    assert len(p.obstacles) == 25 and p.obstacles[24].start == (4, 18) and o.paper_seconds == 1816
    (d,) = grid_family("dimensions", [35])
    assert (d.build().width, d.build().height) == (35, 35)
    (s,) = grid_family("steps", [20])
    assert s.build().steps == 20 and s.paper_seconds == 798


def test_reach_instances_round_trip_through_files(tmp_path):
    from plansynth.reach.fileformat import load_reach_problem

    insts = reach_family("maze", [1, 3]) + reach_family("chain", [2], orders=[2])
    for inst, path in zip(insts, write_family_files(tmp_path, insts)):
        assert load_reach_problem(path) == inst.build()


def test_reach_instances_build():
    m = reach_family("maze", [2])[0].build()
    assert m.dynamics.n_states == 4 and len(m.obstacles) >= 2
    c = reach_family("chain", [1], orders=[3])[0].build()
    assert c.dynamics.n_states == 6
    r = family("reach", "random", [0])[0].build()
    assert r.dim == 2


@pytest.mark.parametrize(
    "name,value",
    [("crossing", 1), ("crossing-stall", 1), ("patrol-walk", 5), ("patrol", 5), ("lanes", 2), ("lanes-rush", 2)],
)
def test_reactive_families_have_the_answer_they_are_built_for(name, value):
    from plansynth.grid.programs import reads_obstacles
    from plansynth.grid.solve import solve

    (inst,) = grid_family(name, [value])
    r = solve(inst.build(), solver="native", budget=Budget(seconds=20))
    assert r.status.value == inst.expected
    if r.status == GridStatus.REALIZABLE:
        assert r.verified is True
        assert reads_obstacles(r.program)  # the controller must react to the cars


def test_scale_64_is_the_example_beyond_the_papers_sizes():
    (inst,) = grid_family("scale", [64])
    p, example = inst.build(), load_grid_problem(Path(__file__).parents[2] / "examples" / "grid" / "scale64.yaml")
    assert (p.width, p.height, p.robot, p.obstacles, p.steps) == (
        example.width,
        example.height,
        example.robot,
        example.obstacles,
        example.steps,
    )


def test_door_family_needs_the_panel_and_door_10_is_the_example():
    from plansynth.grid.programs import reads_obstacles
    from plansynth.grid.solve import solve

    (d10,) = grid_family("door", [10])
    p, example = d10.build(), load_grid_problem(Path(__file__).parents[2] / "examples" / "grid" / "door.yaml")
    assert (p.width, p.height, p.robot, p.obstacles, p.walls, p.steps) == (
        example.width,
        example.height,
        example.robot,
        example.obstacles,
        example.walls,
        example.steps,
    )
    r = solve(p, "native", Budget(seconds=60))
    assert r.status is GridStatus.REALIZABLE and r.verified and reads_obstacles(r.program)
    (d8,) = grid_family("door", [8])
    assert solve(d8.build(), "native", Budget(seconds=60)).status is GridStatus.UNREALIZABLE
    for inst in grid_family("door-stall"):
        assert solve(inst.build(), "native", Budget(seconds=60)).status is GridStatus.UNREALIZABLE


def test_the_reactive_suite_reads_problems_and_labels_from_its_folder(tmp_path, monkeypatch):
    import json

    import yaml

    (inst,) = grid_family("lanes", [1])
    (tmp_path / "r99_lanes.yaml").write_text(yaml.safe_dump(inst.document()), encoding="utf-8")
    (tmp_path / "r99_lanes.label.json").write_text(
        json.dumps({"expected": "realizable", "witness_depth": 6}), encoding="utf-8"
    )
    monkeypatch.setenv("PLANSYNTH_REACTIVE_SUITE", str(tmp_path))
    (got,) = grid_family("reactive-suite")
    assert (got.name, got.expected, got.params["witness_depth"]) == ("r99_lanes", "realizable", 6)
    assert got.build().obstacles == inst.build().obstacles


def test_a_missing_reactive_suite_is_a_clear_error(tmp_path, monkeypatch):
    from plansynth.bench.families import SuiteMissing

    monkeypatch.setenv("PLANSYNTH_REACTIVE_SUITE", str(tmp_path / "nowhere"))
    with pytest.raises(SuiteMissing, match="reactive-suite.*missing"):
        grid_family("reactive-suite")


@pytest.mark.parametrize(
    "name,value",
    [
        ("doors", 1),
        ("doors", 2),
        ("doors-rush", 1),
        ("doors-rush", 2),
        ("doors-jam", 1),
        ("doors-jam", 2),
        ("patrols", 1),
        ("patrols", 2),
        ("patrols-walk", 1),
        ("patrols-walk", 2),
        ("lanes", 1),
        ("lanes-rush", 1),
    ],
)
def test_reactive_family_labels_are_certified_by_brute_force(name, value):
    """The answer each instance is built for, by the brute-force oracles (no engine code):
    a realizable one by the reference interpreter replaying the engine's program against
    every obstacle behaviour, an unrealizable one by the time-dependent game, lost."""
    from plansynth.grid.native.reference import game_won
    from plansynth.grid.programs import reads_obstacles
    from plansynth.grid.reference import reference_wins
    from plansynth.grid.solve import solve

    (inst,) = grid_family(name, [value])
    problem = inst.build()
    if inst.expected == "realizable":
        r = solve(problem, solver="native", budget=Budget(seconds=30))
        assert r.status is GridStatus.REALIZABLE
        assert reference_wins(problem, r.program, problem.steps)
        assert reads_obstacles(r.program)  # the controller must react to the panels, guards or cars
    else:
        assert inst.expected == "unrealizable"
        assert not game_won(problem, problem.steps)  # not even a controller that sees the time wins


def test_a_door_that_may_jam_is_what_makes_doors_unrealizable():
    """doors-jam-1 is doors-1 with one more panel move, ``stay``, at the same length."""
    (free,), (jam,) = grid_family("doors", [1]), grid_family("doors-jam", [1])
    a, b = free.build(), jam.build()
    assert (a.width, a.height, a.robot, a.walls, a.steps) == (b.width, b.height, b.robot, b.walls, b.steps)
    assert [m.name for m in b.obstacles[0].moves] == ["stay"] + [m.name for m in a.obstacles[0].moves]


def test_patrols_walk_differs_from_patrols_only_by_the_robots_run():
    (run,), (walk,) = grid_family("patrols", [2]), grid_family("patrols-walk", [2])
    a, b = run.build(), walk.build()
    assert (a.width, a.height, a.obstacles, a.walls, a.steps) == (b.width, b.height, b.obstacles, b.walls, b.steps)
    assert {m.name for m in a.robot.moves} - {m.name for m in b.robot.moves} == {"fast-left", "fast-right"}

"""Every bad mission input found by generated bad inputs through the CLI, as a
regression test: deep and long formulas, huge labels, sized robots, malformed mission
results, bench arguments a mission family cannot use, YAML's booleans as label names,
and a mission that only a boundary touch read both ways would satisfy. Each ends in an
answer or a one-line error (the CLI's contract: hostile.check_contract), within its
budget, never a traceback."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

from hostile import check_contract, invoke
from plansynth import Budget
from plansynth.errors import InvalidProblem
from plansynth.reach import ReachStatus, solve
from plansynth.reach.fileformat import load_reach_problem, reach_problem_from_dict
from plansynth.reach.ltl import MAX_FORMULA_SIZE, MAX_MISSION_CHARS
from plansynth.reach.problem import MAX_LABEL_VERTICES, MAX_LABELS

ROOM = {
    "workspace": {"min": [0, 0], "max": [10, 10]},
    "labels": {"a": {"min": [6, 6], "max": [8, 8]}, "b": {"min": [2, 6], "max": [4, 8]}},
    "mission": "F a",
    "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [1, 1], "input_bound": 1.5},
    "max_horizon": 20,
}


def room(tmp: Path, name: str = "room.yaml", **changes) -> Path:
    doc = json.loads(json.dumps(ROOM))
    doc.update(changes)
    path = tmp / name
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    return path


def run(args: list) -> object:
    out = invoke([str(a) for a in args])
    check_contract(out, args)
    return out


# ------------------------------------------------------------ deep and long formulas


@pytest.mark.parametrize(
    "mission",
    [
        "(" * 165 + "F a" + ")" * 165,  # 150 worked, 165 crashed
        "(" * 20_000 + "F a" + ")" * 20_000,
        "F (b & " * 75 + "F a" + ")" * 75,  # a 150-stop tour
        "!" * 10_000 + "G !a",
        "X " * 1_000 + "true & F a",
    ],
    ids=["165-parentheses", "20000-parentheses", "150-stop-tour", "10000-not", "1000-next"],
)
def test_deep_formulas_are_read_and_planned_without_recursion(tmp_path: Path, mission: str) -> None:
    path = room(tmp_path, mission=mission)
    out = run(["reach", "solve", path, "--timeout", "20"])
    assert out.exit_code in (0, 1, 3), out.output  # an answer, never a crash


def test_long_formulas_are_refused_at_the_door_or_answered(tmp_path: Path) -> None:
    # a 100,000-character conjunction: 25,000 operators, past the documented size
    conj = " & ".join(["a"] * 25_000)
    assert len(conj) <= MAX_MISSION_CHARS
    out = run(["reach", "solve", room(tmp_path, mission=conj), "--timeout", "20"])
    assert out.exit_code == 2 and "distinct subformulas" in out.stderr
    # a 1 MB mission is refused at once (the reader is linear: no 37 s)
    t0 = time.perf_counter()
    out = run(["reach", "solve", room(tmp_path, mission="F a & " * 170_000 + "F a"), "--timeout", "20"])
    assert out.exit_code == 2 and "characters" in out.stderr and time.perf_counter() - t0 < 10
    # the longest legal conjunction is read and planned within the budget
    ok = " & ".join(["F a", "F b"] * (MAX_FORMULA_SIZE // 5))
    t0 = time.perf_counter()
    out = run(["reach", "solve", room(tmp_path, mission=ok), "--timeout", "15"])
    assert out.exit_code in (0, 3) and time.perf_counter() - t0 < 40


def test_a_400_hazard_mission_is_answered_within_its_budget() -> None:
    """``G !h1 & ... & G !h400 & F goal`` crashed after 17 s in the infeasibility proof."""
    labels = {
        f"h{i}": {
            "min": [1 + (i % 20) * 0.4, 2 + (i // 20) * 0.3],
            "max": [1.2 + (i % 20) * 0.4, 2.1 + (i // 20) * 0.3],
        }
        for i in range(400)
    }
    labels["goal"] = {"min": [9, 9], "max": [10, 10]}
    doc = {**ROOM, "labels": labels, "mission": " & ".join(f"G !h{i}" for i in range(400)) + " & F goal"}
    p = reach_problem_from_dict(doc)
    t0 = time.perf_counter()
    r = solve(p, "lazy-smt", Budget(seconds=20))
    assert time.perf_counter() - t0 < 40
    assert r.status in (ReachStatus.FOUND, ReachStatus.UNKNOWN)
    if r.status is ReachStatus.FOUND:
        assert r.mission["ok"]


# ------------------------------------------------------------ labels that cut the regions


def test_label_limits_are_checked_at_the_door(tmp_path: Path) -> None:
    ring = [
        [float(5 + 4 * np.cos(a)), float(5 + 4 * np.sin(a))] for a in np.linspace(0, 2 * np.pi, 10_000, endpoint=False)
    ]
    out = run(["reach", "solve", room(tmp_path, labels={"a": {"polygon": ring}}), "--timeout", "20"])
    assert out.exit_code == 2 and f"at most {MAX_LABEL_VERTICES} vertices" in out.stderr
    many = {
        f"l{i}": {"min": [i % 50 * 0.2, i // 50 * 0.2], "max": [i % 50 * 0.2 + 0.1, i // 50 * 0.2 + 0.1]}
        for i in range(2000)
    }
    out = run(["reach", "solve", room(tmp_path, labels={**many, "a": ROOM["labels"]["a"]}), "--timeout", "20"])
    assert out.exit_code == 2 and f"at most {MAX_LABELS} labels" in out.stderr


@pytest.mark.parametrize("what", ["jagged-label", "many-labels"])
def test_splitting_the_regions_along_labels_keeps_the_timeout(tmp_path: Path, what: str) -> None:
    """A star label of 1,000 vertices and 1,000 small labels: the refinement checks the
    budget (a 10,000-vertex label took 398 s and 4 GB, 2,000 labels 180 s)."""
    if what == "jagged-label":
        k = MAX_LABEL_VERTICES
        star = [
            [
                float(5 + (4 if i % 2 else 1.5) * np.cos(2 * np.pi * i / k)),
                float(5 + (4 if i % 2 else 1.5) * np.sin(2 * np.pi * i / k)),
            ]
            for i in range(k)
        ]
        labels = {"a": {"polygon": star}}
    else:
        labels = {
            f"l{i}": {"min": [i % 40 * 0.25, i // 40 * 0.25 + 2], "max": [i % 40 * 0.25 + 0.1, i // 40 * 0.25 + 2.1]}
            for i in range(MAX_LABELS - 1)
        }
        labels["a"] = ROOM["labels"]["a"]
    t0 = time.perf_counter()
    out = run(["reach", "solve", room(tmp_path, labels=labels, mission="F a"), "--timeout", "5"])
    assert out.exit_code in (0, 3) and time.perf_counter() - t0 < 25, out.output


# ------------------------------------------------------------ sized robots


@pytest.mark.parametrize("size", [{"radius": 0.3}, {"half_extent": [0.3, 0.2]}])
@pytest.mark.parametrize("planner", ["lazy-smt", "milp-ltl"])
def test_missions_plan_for_the_robots_size(size: dict, planner: str) -> None:
    """Both mission planners planned a point robot; the validator then rejected the plan
    and the answer was ``unknown``."""
    doc = {
        **ROOM,
        "obstacles": [{"min": [4.5, 0], "max": [5.5, 8]}],
        "robot": {**ROOM["robot"], **size},
        "mission": "F a & G !b",
    }
    p = reach_problem_from_dict(doc)
    r = solve(p, planner, Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.validated and r.mission["ok"], r.message


# ------------------------------------------------------------ reach validate on mission results


@pytest.fixture(scope="module")
def plan_file(tmp_path_factory) -> tuple[Path, dict]:
    tmp = tmp_path_factory.mktemp("plan")
    p = reach_problem_from_dict(ROOM)
    r = solve(p, "lazy-smt", Budget(seconds=60))
    path = tmp / "plan.json"
    r.write_json(path)
    return path, json.loads(path.read_text())


@pytest.mark.parametrize(
    "change, field",
    [
        ({"loop_start": 0.5}, "mission.loop_start"),
        ({"loop_start": 1.0}, "mission.loop_start"),
        ({"loop_start": "1"}, "mission.loop_start"),
        ({"loop_start": True}, "mission.loop_start"),
        ({"loop_start": -1}, "mission.loop_start"),
        ({"loop_start": 10_000}, "mission.loop_start"),
        ("F a", "mission"),
        ([1, 2], "mission"),
    ],
)
def test_bad_mission_records_are_one_line_errors(tmp_path: Path, plan_file, change, field: str) -> None:
    _, doc = plan_file
    bad = dict(doc)
    bad["mission"] = {**doc["mission"], **change} if isinstance(change, dict) else change
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    out = run(["reach", "validate", room(tmp_path), path])
    assert out.exit_code == 2 and f": {field}:" in out.stderr, out.stderr


def test_states_of_the_wrong_dimension_are_a_clean_invalid(tmp_path: Path, plan_file) -> None:
    _, doc = plan_file
    bad = {**doc, "states": [[*s, 0.0] for s in doc["states"]]}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(bad))
    out = run(["reach", "validate", room(tmp_path), path])
    assert out.exit_code == 1 and "INVALID" in out.output and "mission not checked" in out.output


def test_the_dynamics_option_is_checked_with_a_mission(tmp_path: Path, plan_file) -> None:
    path, _ = plan_file
    out = run(["reach", "validate", room(tmp_path), path, "--dynamics", "banana"])
    assert out.exit_code == 2 and "--dynamics" in out.stderr
    out = run(["reach", "validate", room(tmp_path), path, "--dynamics", "curve"])
    assert out.exit_code == 2 and "exact dynamics" in out.stderr
    assert run(["reach", "validate", room(tmp_path), path, "--dynamics", "exact"]).exit_code == 0


# ------------------------------------------------------------ bench arguments


@pytest.mark.parametrize(
    "args, flag",
    [
        (["--family", "missions", "--values=-1"], "--values"),
        (["--family", "missions", "--values=30"], "--values"),
        (["--family", "missions", "--planners", "rrt"], "--planners"),
        (["--family", "missions-literature", "--planners", "milp-bigm"], "--planners"),
        (["--family", "maze", "--planners", "milp-ltl"], "--planners"),
        (["--family", "missions-literature", "--values", "keys"], "--values"),
    ],
)
def test_bench_refuses_what_a_mission_family_cannot_run(tmp_path: Path, args: list[str], flag: str) -> None:
    out = invoke(["bench", "reach", *args, "--db", tmp_path / "r.db", "--timeout", "5"])
    assert out.exit_code == 2 and f"error: {flag}:" in out.output and "Traceback" not in out.output, out.output
    assert not (tmp_path / "r.db").exists()  # refused before anything ran


# ------------------------------------------------------------ YAML booleans, touches


def test_label_names_on_and_off_are_names(tmp_path: Path) -> None:
    path = tmp_path / "onoff.yaml"
    text = yaml.safe_dump({k: v for k, v in ROOM.items() if k not in ("labels", "mission")})
    text += "labels:\n  on: {min: [6, 6], max: [8, 8]}\n  off: {min: [2, 6], max: [4, 8]}\nmission: F on & G !off\n"
    path.write_text(text)
    p = load_reach_problem(path)
    assert sorted(dict(p.labels)) == ["off", "on"]
    assert run(["reach", "solve", path, "--timeout", "30"]).exit_code == 0
    # true and false stay booleans (and are no label names)
    path.write_text(text.replace("  off:", "  true:"))
    with pytest.raises(InvalidProblem, match="a label name must be text"):
        load_reach_problem(path)


def test_a_touch_is_never_in_and_out_at_once():
    """``G !b & F b`` ended ``unknown`` saying "some word ... satisfies the mission": a
    boundary touch had been counted as inside and outside at once. No trajectory meets it
    (a touch is read one way per step), so it is infeasible, proved by the geometry."""
    p = reach_problem_from_dict({**ROOM, "mission": "G !b & F b"})
    for planner in ("lazy-smt", "milp-ltl"):
        r = solve(p, planner, Budget(seconds=30))
        assert r.status is ReachStatus.INFEASIBLE and r.counters["label_proof"] is True, r.message
        assert "some word" not in r.message

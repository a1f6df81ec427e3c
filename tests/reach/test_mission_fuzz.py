"""The fuzz test of the door, extended to missions: mutated mission problems (labels,
margins, readings, ends, robot sizes), random mission strings (operators, bounds,
brackets, names, stray characters, deep nesting), random labels and robot sizes, and
mutated mission result files, all through the CLI's entry with a budget of at most 2 s.

Every run keeps the CLI's contract (:func:`hostile.check_contract`): exit status in
{0, 1, 2, 3}, no traceback, one ``error:`` line on status 2, and a bounded time.
``PLANSYNTH_FUZZ_SCALE=10`` runs ten times as many examples.
"""

from __future__ import annotations

import copy
import json
import os
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hostile import ROOT, invoke
from test_fuzz import _run, mutated_documents, problem_bytes

SCALE = max(1, int(os.environ.get("PLANSYNTH_FUZZ_SCALE", "1")))
FUZZ = settings(max_examples=30 * SCALE, deadline=None, suppress_health_check=list(HealthCheck))

EXAMPLES = [ROOT / "examples" / "reach" / f"mission-{n}.yaml" for n in ("visit", "patrol", "avoid-until", "unsat")]
MISSION_DOCS = [yaml.safe_load(p.read_text(encoding="utf-8")) for p in EXAMPLES]
# a document with every mission field: margins, reading, end, a polygon label, a sized robot
FULL = copy.deepcopy(MISSION_DOCS[0])
FULL["mission"] = {
    "formula": FULL["mission"],
    "reading": "sample",
    "end": "free",
    "margin": 0.1,
    "obstacle_margin": 0.05,
}
FULL["labels"]["lab"] = {"polygon": [[7, 7], [9, 7], [9, 9], [7, 9]], "margin": 0.2}
FULL["robot"]["radius"] = 0.2
MISSION_DOCS.append(FULL)


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("mission-fuzz")
    # a plan of the visit example, to validate against mutated problems
    r = invoke(["reach", "solve", str(EXAMPLES[0]), "--out", str(d / "plan.json"), "--timeout", "60"])
    assert r.exit_code == 0, r.output
    return d


@FUZZ
@given(case=problem_bytes(MISSION_DOCS), command=st.sampled_from(["solve", "solve", "milp", "validate"]))
def test_mutated_mission_problems_keep_the_contract(work: Path, case: tuple[bytes, str], command: str) -> None:
    p = work / f"case{case[1]}"
    p.write_bytes(case[0])
    if command == "solve":
        _run(["reach", "solve", p, "--max-horizon", "4", "--timeout", "2"])
    elif command == "milp":
        _run(["reach", "solve", p, "-p", "milp-ltl", "--max-horizon", "4", "--timeout", "2"])
    else:
        _run(["reach", "validate", p, work / "plan.json"])


_LTL_TOKENS = [
    "a", "b", "c", "kitchen", "lab", "stairs", "goal", "on", "X", "F", "G", "U", "R", "!", "&", "|", "->", "<->",
    "(", ")", "(", ")", "true", "false", "[", "]", ",", "0", "1", "3", "10000", "10001", "-1", "F[0,3]", "G[1,2]",
    "U[0,2]", "R[2,5]", "F[", "[5,2]", "9" * 30, "X[1]", " ", "\t", "é", "\u202e", "１", "$", "@", "\0",
]  # fmt: skip


@st.composite
def mission_strings(draw: st.DrawFn) -> str:
    kind = draw(st.sampled_from(["soup", "soup", "deep", "long"]))
    if kind == "soup":
        return " ".join(draw(st.lists(st.sampled_from(_LTL_TOKENS), min_size=0, max_size=40)))
    if kind == "deep":
        depth = draw(st.integers(100, 5000))
        op = draw(st.sampled_from(["(", "!", "X ", "F ", "G ", "F[0,1] ", "!X "]))
        close = ")" * depth if op == "(" else ""
        return op * depth + draw(st.sampled_from(["kitchen", "F lab", "G !stairs"])) + close
    term = draw(st.sampled_from(["kitchen", "F lab", "G !stairs", "X kitchen"]))
    return draw(st.sampled_from([" & ", " | ", " U ", " -> "])).join([term] * draw(st.integers(10, 30_000)))


@FUZZ
@given(mission=mission_strings(), planner=st.sampled_from(["lazy-smt", "milp-ltl"]))
def test_random_mission_strings_keep_the_contract(work: Path, mission: str, planner: str) -> None:
    doc = copy.deepcopy(MISSION_DOCS[0])
    doc["mission"] = mission
    p = work / "mission.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    _run(["reach", "solve", p, "-p", planner, "--max-horizon", "5", "--timeout", "2"])


_numbers = st.one_of(
    st.floats(-20, 40), st.sampled_from([0, 0.0, -0.0, 1e-12, 1e6, 1e7, float("nan"), float("inf"), True, "1", None])
)


@st.composite
def label_worlds(draw: st.DrawFn) -> dict:
    """The visit example with random labels (boxes, polygons, degenerate ones), margins,
    readings, ends and robot sizes."""
    doc = copy.deepcopy(MISSION_DOCS[0])
    labels: dict[str, Any] = {}
    for name in ("kitchen", "lab", "stairs"):
        shape = draw(st.sampled_from(["box", "box", "polygon", "weird"]))
        if shape == "box":
            x, y = draw(st.floats(-2, 10)), draw(st.floats(-2, 10))
            entry: Any = {"min": [x, y], "max": [x + draw(st.floats(0, 5)), y + draw(st.floats(0, 5))]}
        elif shape == "polygon":
            k = draw(st.integers(3, 12))
            entry = {"polygon": [[draw(st.floats(0, 10)), draw(st.floats(0, 10))] for _ in range(k)]}
        else:
            entry = draw(st.sampled_from([[], {}, "box", 3, {"min": [1, 1]}, {"polygon": [[0, 0]] * 2000}]))
        if isinstance(entry, dict) and draw(st.booleans()):
            entry["margin"] = draw(_numbers)
        labels[name] = entry
    doc["labels"] = labels
    how = {"formula": doc["mission"]}
    for key, values in (
        ("reading", ["segment", "sample", "Sample", 1, None]),
        ("end", ["rest", "free", "stop", None]),
    ):
        if draw(st.booleans()):
            how[key] = draw(st.sampled_from(values))
    for key in ("margin", "obstacle_margin"):
        if draw(st.booleans()):
            how[key] = draw(_numbers)
    doc["mission"] = {k: v for k, v in how.items() if v is not None}
    size = draw(st.sampled_from(["none", "radius", "half_extent"]))
    if size == "radius":
        doc["robot"]["radius"] = draw(_numbers)
    elif size == "half_extent":
        doc["robot"]["half_extent"] = draw(st.sampled_from([[0.2, 0.3], [0.5], [-1, 1], [0.1, 0.1, 0.1], "x"]))
    return doc


@FUZZ
@given(doc=label_worlds(), planner=st.sampled_from(["lazy-smt", "milp-ltl"]))
def test_random_labels_margins_and_robot_sizes_keep_the_contract(work: Path, doc: dict, planner: str) -> None:
    p = work / "labels.json"
    p.write_text(json.dumps(doc, allow_nan=True), encoding="utf-8")
    r = _run(["reach", "solve", p, "-p", planner, "--max-horizon", "6", "--timeout", "2"])
    if r.exit_code == 0:  # a plan is reported only validated and mission-checked
        assert "mission checked" in r.output


@FUZZ
@given(
    doc=mutated_documents(
        [
            {
                "states": [[1, 1, 0, 0], [1.1, 1.1, 0.2, 0.2]],
                "inputs": [[0.4, 0.4]],
                "mission": {"formula": "F a", "loop_start": 0, "reading": "sample", "end": "free"},
                "guarantee": "segments",
            }
        ]
    ),
    flags=st.sampled_from([[], ["--reading", "sample"], ["--end", "free"], ["--margin", "0.1"], ["--dynamics", "x"]]),
)
def test_mutated_mission_results_keep_the_contract(work: Path, doc: Any, flags: list[str]) -> None:
    p = work / "mutated-result.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    _run(["reach", "validate", EXAMPLES[1], p, *flags])

"""The grid problems posed to omega (plansynth.grid.syntcomp.omega_grid): on random
small safety and recurrence problems (one-cell obstacles, built-in one-step moves,
either collision rule, periods of either schedule, fairness), omega's realizability is
the brute-force oracle's."""

from __future__ import annotations

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from plansynth.grid.oracle import brute_force
from plansynth.grid.problem import grid_problem_from_dict

# omega and dd come with the baselines extra, which setup installs: no skip here
from plansynth.grid.syntcomp.omega_grid import supports, synthesize

from ..strategies import objective_documents

STEPS = ("stay", "up", "down", "left", "right")


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(data=st.data())
def test_omega_agrees_with_the_oracle(data):
    doc = data.draw(objective_documents(data.draw(st.sampled_from(["safety", "recurrence"]))))
    doc["robot"]["moves"] = [m for m in doc["robot"]["moves"] if m in STEPS] or ["stay"]
    for o in doc["obstacles"]:
        o.pop("size", None)
        o.pop("glitches", None)
        o["moves"] = [m for m in o["moves"] if m in STEPS] or ["stay"]
        if o.get("period", 1) > 1 and "stay" not in o["moves"]:
            o["moves"].insert(0, "stay")
    problem = grid_problem_from_dict(doc)
    assert supports(problem) is None
    assume(all(problem.robot.start != o.start for o in problem.obstacles))  # omega reads time 0's positions too
    status, _, _ = synthesize(problem, strategy=False)
    assert status is brute_force(problem)


def test_unsupported_problems_are_named():
    doc = {
        "grid": [3, 3],
        "objective": "safety",
        "robot": {"start": [0, 0], "moves": ["stay"]},
        "obstacles": [{"start": [1, 1], "size": [2, 2], "moves": ["stay"]}],
    }
    assert "one-cell obstacles" in supports(grid_problem_from_dict(doc))

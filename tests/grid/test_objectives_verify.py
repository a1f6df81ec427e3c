"""The verifier of every objective against the brute-force oracle, and its
counterexamples replayed through the semantics (plansynth.grid.verify.closed_loop,
plansynth.grid.oracle)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.grid.oracle import brute_force
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.programs import compile_program, parse_program
from plansynth.grid.result import GridStatus
from plansynth.grid.semantics import controller_inputs, initial_state, step
from plansynth.grid.verify import VerifyStatus, verify

from .strategies import OBJECTIVES, objective_problems, programs

SETTINGS = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def as_controller(problem, program):
    f = compile_program(program, problem.variables)
    return lambda s: f(*controller_inputs(problem, s))


def replay_loses(problem, cex, steps):
    """The counterexample's moves, replayed through step(), reach the loss it claims."""
    state = initial_state(problem)
    assert cex.states[0] == state
    for t, (k, joint) in enumerate(zip(cex.robot_moves, cex.obstacle_moves, strict=True)):
        nxt, collided = step(problem, state, k, joint)
        assert nxt == cex.states[t + 1]
        if collided:
            assert t == len(cex.robot_moves) - 1 and "collision" in cex.reason
            return
        state = nxt
    if cex.loop is not None:
        assert cex.states[-1] == cex.states[cex.loop]
        goal = problem.robot.goals[cex.states[cex.loop].mode]
        assert all(s.robot != goal for s in cex.states[cex.loop + 1 :])
        if problem.fair:
            for i in range(len(problem.obstacles)):
                assert any(
                    a.obstacles[i] != b.obstacles[i] for a, b in zip(cex.states[cex.loop :], cex.states[cex.loop + 1 :])
                )
        return
    assert problem.objective.bounded and "not on the goal" in cex.reason


@pytest.mark.parametrize("objective", OBJECTIVES)
@SETTINGS
@given(data=st.data())
def test_verifier_agrees_with_the_oracle(objective, data):
    problem = data.draw(objective_problems(objective))
    program = data.draw(programs(problem, 5))
    steps = problem.steps
    verdict = verify(problem, program, steps, budget=Budget(seconds=60))
    oracle = brute_force(problem, steps, controller=as_controller(problem, program))
    assert verdict.status is (VerifyStatus.WINS if oracle is GridStatus.REALIZABLE else VerifyStatus.LOSES)
    if verdict.status is VerifyStatus.LOSES:
        replay_loses(problem, verdict.counterexample, steps)


def test_recurrence_needs_the_mode_and_fairness_changes_the_answer():
    """A corridor: the obstacle shuttles over the only crossing; without fairness it may
    sit there forever, under fairness it must leave and the robot gets through."""
    d = {
        "grid": [3, 3],
        "objective": "recurrence",
        "walls": [[1, 0], [1, 2]],
        "robot": {"start": [0, 1], "goals": [[2, 1], [0, 1]], "moves": ["stay", "right", "left"]},
        "obstacles": [{"start": [1, 1], "moves": ["stay", "up", "down"], "keep_out": [[1, 2]]}],
    }
    prog = parse_program("(ite (= o0y 1) 0 (ite (= m 0) 1 2))")
    unfair = grid_problem_from_dict(d)
    fair = grid_problem_from_dict({**d, "fair": True})
    v = verify(unfair, prog, None)
    assert v.status is VerifyStatus.LOSES and v.counterexample.loop is not None
    replay_loses(unfair, v.counterexample, None)
    assert brute_force(unfair) is GridStatus.UNREALIZABLE
    assert verify(fair, prog, None).status is VerifyStatus.WINS
    assert brute_force(fair) is GridStatus.REALIZABLE


def test_budget_gives_unknown():
    d = {
        "grid": [6, 6],
        "objective": "safety",
        "robot": {"start": [0, 0], "moves": ["stay", "up", "right"]},
        "obstacles": [{"start": [5, 5], "moves": ["stay", "left", "down"], "period": 3}],
    }
    v = verify(grid_problem_from_dict(d), parse_program("0"), None, budget=Budget(seconds=1e-9))
    assert v.status is VerifyStatus.UNKNOWN and "budget ran out" in v.message

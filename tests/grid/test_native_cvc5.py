"""The native engine agrees with cvc5 wherever cvc5 answers within its budget."""

from __future__ import annotations

from hypothesis import given, settings

from plansynth.budget import Budget
from plansynth.grid.native.engine import Engine
from plansynth.grid.result import GridStatus, get_backend

from .strategies import grid_problems


@settings(max_examples=12)
@given(grid_problems(max_side=3, max_obstacles=1, max_obstacle_moves=2, max_robot_moves=3, max_steps=3))
def test_native_agrees_with_cvc5(problem):
    steps = problem.steps
    theirs = get_backend("cvc5").solve_length(problem, steps, Budget(seconds=10))
    ours = Engine().solve_length(problem, steps, Budget(seconds=10))
    assert ours.status is not GridStatus.UNKNOWN
    if theirs.status is not GridStatus.UNKNOWN:
        assert theirs.status is ours.status, (problem.to_dict(), theirs.message, ours.message)


def test_native_agrees_with_cvc5_on_fixed_problems():
    """Problems cvc5 decides quickly, both ways (so the comparison is never vacuous)."""
    from plansynth.grid.problem import grid_problem_from_dict

    base = {"grid": [3, 2], "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right", "up"]}}
    cases = [
        (dict(base, steps=2), GridStatus.REALIZABLE),
        (dict(base, steps=1), GridStatus.UNREALIZABLE),
        (dict(base, steps=3, obstacles=[{"start": [2, 1], "moves": ["stay", "down"]}]), GridStatus.UNREALIZABLE),
    ]
    for doc, expected in cases:
        problem = grid_problem_from_dict(doc)
        theirs = get_backend("cvc5").solve_length(problem, problem.steps, Budget(seconds=60))
        ours = Engine().solve_length(problem, problem.steps, Budget(seconds=10))
        assert theirs.status is expected, theirs.message
        assert ours.status is expected

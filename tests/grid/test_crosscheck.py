"""The SyGuS encoding against the independent verifier.

The compiler writes the spec's semantics as formulas; the verifier executes them
(:mod:`plansynth.grid.semantics`). On random small problems and random programs, the
compiled specification with the program substituted (:func:`compile_check`, decided by
cvc5) must hold exactly when the verifier says the program wins. Then the whole path:
cvc5's answers to the compiled synthesis problems must be programs the verifier accepts,
and ``infeasible`` must be right (checked where the bounded grammar is small enough to
enumerate by hand), and Figure 1 must come out realizable with a verified program.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.grid.backends.cvc5 import Cvc5Backend, run_smt_text
from plansynth.grid.problem import grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import Const, depth, parse_program
from plansynth.grid.result import GridStatus
from plansynth.grid.solve import solve
from plansynth.grid.sygus import compile_check
from plansynth.grid.verify import verify

from .strategies import grid_problems, problems_and_programs, programs

FIGURE1 = Path(__file__).parents[2] / "examples" / "grid" / "figure1.yaml"


def _case(grid, robot, goal, moves, obstacles=(), walls=(), steps=1) -> dict[str, Any]:
    return {
        "grid": list(grid),
        "robot": {"start": list(robot), "goal": list(goal), "moves": list(moves)},
        "obstacles": [{"start": list(s), "moves": list(m)} for s, m in obstacles],
        "walls": [list(w) for w in walls],
        "steps": steps,
    }


HOP = {"name": "hop", "to": [2, 0], "via": [[1, 0]]}
BACK = {"name": "back", "to": [-2, 0], "via": [[-1, 0]]}

#: One case per rule of the spec's Semantics: (problem, program, does it win?). The
#: expected answers are read off the spec; random problems rarely hit some of them.
RULES = {
    "a wall clamps an obstacle's move": (
        _case(
            (4, 1),
            (3, 0),
            (3, 0),
            ["stay"],
            [((0, 0), [{"name": "far", "to": [3, 0], "via": [[1, 0], [2, 0]]}])],
            [(2, 0)],
            steps=2,
        ),
        "0",
        True,
    ),
    "an obstacle on a wall never moves (its move would sweep the wall)": (
        _case((2, 2), (0, 0), (0, 0), ["stay"], [((1, 0), ["left"])], [(1, 0)]),
        "0",
        True,
    ),
    "a clamped robot move sweeps only its start cell": (
        _case((2, 1), (0, 0), (0, 0), [HOP], [((1, 0), ["stay"])]),
        "0",
        True,
    ),
    "a clamped obstacle move sweeps only its start cell": (
        _case((2, 1), (0, 0), (0, 0), ["stay"], [((1, 0), [BACK])]),
        "0",
        True,
    ),
    "an obstacle clamped at the border still occupies its cell": (
        _case((2, 1), (1, 0), (0, 0), ["stay", "left"], [((0, 0), ["left"])]),
        "1",
        False,
    ),
    "via cells collide": (_case((3, 1), (0, 0), (2, 0), [HOP], [((1, 0), ["stay"])]), "0", False),
    "a diagonal crossing is not a collision": (
        _case((2, 2), (0, 0), (1, 1), ["up-right"], [((1, 0), ["up-left"])]),
        "0",
        True,
    ),
    "swapping cells is a collision": (_case((2, 1), (0, 0), (1, 0), ["right"], [((1, 0), ["left"])]), "0", False),
    "a robot sweeping a wall collides": (_case((3, 1), (0, 0), (2, 0), [HOP], walls=[(1, 0)]), "0", False),
    "the adversary picks the colliding move": (
        _case((3, 1), (0, 0), (1, 0), ["right"], [((2, 0), ["stay", "left"])]),
        "0",
        False,
    ),
    "an obstacle on the robot's start cell collides at step 0": (
        _case((3, 1), (0, 0), (1, 0), ["right"], [((0, 0), ["right", "stay"])]),
        "0",
        False,
    ),
    "success is at exactly l steps": (_case((3, 1), (0, 0), (1, 0), ["stay", "right"], steps=2), "1", False),
    "waiting for an obstacle to leave wins": (
        _case((3, 2), (0, 0), (2, 0), ["stay", "right"], [((1, 0), ["up"])], steps=3),
        "(ite (= o0y 0) 0 1)",
        True,
    ),
    "not waiting collides": (_case((3, 2), (0, 0), (2, 0), ["stay", "right"], [((1, 0), ["up"])], steps=3), "1", False),
}


@pytest.mark.parametrize("rule", list(RULES))
def test_each_rule_of_the_semantics(rule: str) -> None:
    doc, text, wins = RULES[rule]
    problem = grid_problem_from_dict(doc)
    program = parse_program(text)
    assert verify(problem, program, problem.steps).wins is wins
    answer = run_smt_text(compile_check(problem, problem.steps, program)).strip()
    assert answer == ("unsat" if wins else "sat")


#: Hypothesis examples per property test below; PLANSYNTH_TEST_SCALE=N runs N times as
#: many (a longer hunt than CI's, which runs each of them in three random orders).
SCALE = max(1, int(os.environ.get("PLANSYNTH_TEST_SCALE", "1")))


@settings(max_examples=75 * SCALE)
@given(problems_and_programs(max_depth=5))
def test_compiled_check_holds_exactly_when_the_verifier_says_the_program_wins(case) -> None:
    problem, program = case
    steps = problem.steps
    answer = run_smt_text(compile_check(problem, steps, program)).strip()
    verdict = verify(problem, program, steps)
    event(f"program wins: {verdict.wins}")
    assert answer in ("sat", "unsat"), answer
    assert (answer == "unsat") == verdict.wins, (str(program), steps, verdict.counterexample)


@settings(max_examples=40 * SCALE)
@given(st.data())
def test_programs_that_win_make_the_check_unsat(data) -> None:
    # Random programs mostly lose; make sure the "wins" side is exercised too, by drawing
    # problems with a stay move and trying the constant programs as well.
    problem = data.draw(grid_problems(max_obstacles=2, max_steps=4))
    candidates = [Const(k) for k in range(len(problem.robot.moves))] + [data.draw(programs(problem, 4))]
    for program in candidates:
        wins = verify(problem, program, problem.steps).wins
        event(f"program wins: {wins}")
        answer = run_smt_text(compile_check(problem, problem.steps, program)).strip()
        assert (answer == "unsat") == wins, (str(program), problem.steps)


@settings(max_examples=10)
@given(grid_problems(max_obstacles=2, max_steps=3, max_robot_moves=4))
def test_cvc5_answers_are_right_at_depth_bound_3(problem) -> None:
    # At depth <= 3 a program is a move number or an ite on a comparison of constants:
    # in effect a constant. So "infeasible" is right iff no constant program wins.
    constants_win = any(verify(problem, Const(k), problem.steps).wins for k in range(len(problem.robot.moves)))
    outcome = Cvc5Backend().solve_length(problem, problem.steps, Budget(seconds=60), depth_bound=3)
    event(f"cvc5: {outcome.status.value}")
    assert outcome.status is not GridStatus.UNKNOWN, outcome.message
    if outcome.status is GridStatus.REALIZABLE:
        assert depth(outcome.program) <= 3
        assert verify(problem, outcome.program, problem.steps).wins
    assert (outcome.status is GridStatus.REALIZABLE) == constants_win


def test_figure1_end_to_end_with_cvc5() -> None:
    # l = 6 is Figure 1's shortest path length; the full search over l = 1..6 is in
    # test_solve.py (slow tier). sygus-enum=fast keeps this under a few seconds.
    problem = load_grid_problem(FIGURE1).with_steps(6)
    result = solve(problem, "cvc5", Budget(seconds=120), options={"sygus-enum": "fast"})
    assert result.status is GridStatus.REALIZABLE, result.message
    assert result.verified is True and result.steps == 6
    assert verify(problem, result.program, 6).wins
    assert run_smt_text(compile_check(problem, 6, result.program)).strip() == "unsat"

"""Ehlers' moving-obstacle family as an explicit game, and its solvers, against the
published answers (the description's Table I) and a brute-force oracle."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.errors import InvalidProblem
from plansynth.grid.result import GridStatus
from plansynth.grid.syntcomp.moving_obstacle import MOVES, PUBLISHED, MovingObstacle, State
from plansynth.grid.syntcomp.safety import SolutionRejected, check_solution, solve, solve_reference


def test_rules_of_the_family():
    game = MovingObstacle(8, 2)
    assert game.initial == State((0, 0), (6, 6), True, 0)
    assert len(MOVES) == 9 and (0, 0) in MOVES
    # the border: a move out of the grid leaves that coordinate unchanged
    assert game.move_robot((0, 7), (-1, 1)) == (0, 7)
    assert game.move_robot((0, 7), (1, 1)) == (1, 7)
    # the 2 x 2 block
    block = {(x, y) for x in range(8) for y in range(8) if game.is_collision(State((x, y), (3, 5), False, 0))}
    assert block == {(3, 5), (4, 5), (3, 6), (4, 6)}
    # after a move the obstacle waits, unless it spends a glitch (counter +1 or more)
    s = State((0, 0), (3, 3), True, 1)
    replies = set(game.obstacle_moves(s))
    assert ((3, 3), 1) in replies and ((3, 3), 2) in replies
    assert ((4, 4), 2) in replies and ((4, 4), 1) not in replies
    # a resting obstacle moves freely, inside the grid (corner 0..6), and may raise the counter
    assert {o for o, g in game.obstacle_moves(State((0, 0), (6, 0), False, 0)) if g == 0} == {
        (5, 0),
        (6, 0),
        (5, 1),
        (6, 1),
    }
    # no glitches left: a waiting obstacle stays
    assert set(game.obstacle_moves(State((0, 0), (3, 3), True, 2))) == {((3, 3), 2)}
    assert all(
        t.obstacle_waits == (t.obstacle != (3, 3)) for t in game.successors(State((0, 0), (3, 3), False, 0), (1, 0))
    )


def test_invalid_instances_are_named_errors():
    with pytest.raises(InvalidProblem, match="size"):
        MovingObstacle(2, 0)
    with pytest.raises(InvalidProblem, match="glitches"):
        MovingObstacle(8, -1)


@pytest.mark.parametrize("m,c", [(8, 0), (8, 1), (16, 3), (16, 4)])
def test_published_answers(m, c):
    sol = solve(MovingObstacle(m, c))
    expected = GridStatus.REALIZABLE if PUBLISHED[(m, c)][0] else GridStatus.UNREALIZABLE
    assert sol.status is expected


@pytest.mark.slow
@pytest.mark.parametrize("m,c", [(24, 7), (24, 8), (32, 11), (32, 12)])
def test_published_answers_larger(m, c):
    sol = solve(MovingObstacle(m, c))
    assert sol.status is (GridStatus.REALIZABLE if PUBLISHED[(m, c)][0] else GridStatus.UNREALIZABLE)


def test_five_by_five_is_the_smallest_grid_the_robot_evades_without_glitches():
    """Ehlers, Sect. II: "allows the robot to evade the obstacle for workspace sizes of
    5 x 5 cells or larger"."""
    assert [solve(MovingObstacle(m, 0)).status for m in (3, 4, 5, 6, 7)] == [
        GridStatus.UNREALIZABLE,
        GridStatus.UNREALIZABLE,
    ] + [GridStatus.REALIZABLE] * 3


@settings(max_examples=12)
@given(m=st.integers(3, 6), c=st.integers(0, 2))
def test_numpy_solver_is_the_brute_force_fixpoint(m, c):
    game = MovingObstacle(m, c)
    sol = solve(game)
    status, win = solve_reference(game)
    assert sol.status is status
    assert {s for s in game.states() if sol.is_winning(s)} == win


@pytest.mark.parametrize("m,c", [(5, 0), (5, 1), (8, 0), (8, 1)])
def test_certificates_check_on_every_state(m, c):
    check_solution(solve(MovingObstacle(m, c)))


@pytest.mark.parametrize("c", [3, 4])
def test_certificates_check_on_sampled_states_of_16x16(c):
    game = MovingObstacle(16, c)
    sol = solve(game)
    rng = np.random.default_rng(c)
    states = [
        State((int(a), int(b)), (int(x), int(y)), bool(w), int(g))
        for a, b, x, y, w, g in zip(
            rng.integers(0, 16, 3000),
            rng.integers(0, 16, 3000),
            rng.integers(0, 15, 3000),
            rng.integers(0, 15, 3000),
            rng.integers(0, 2, 3000),
            rng.integers(0, c + 1, 3000),
        )
    ]
    check_solution(sol, states=states)


def test_checker_rejects_a_forged_answer():
    sol = solve(MovingObstacle(8, 1))
    forged_win = sol.winning.copy()
    forged_win[(0, 0, 6, 6, 1, 0)] = True
    forged_rank = sol.rank.copy()
    forged_rank[(0, 0, 6, 6, 1, 0)] = -1
    forged = type(sol)(sol.game, GridStatus.REALIZABLE, forged_win, forged_rank, sol.iterations, sol.seconds)
    with pytest.raises(SolutionRejected, match="no robot move"):
        check_solution(forged, states=[])


def test_the_winning_moves_keep_the_robot_safe_on_random_plays():
    game = MovingObstacle(8, 0)
    sol = solve(game)
    rng = np.random.default_rng(0)
    for _ in range(50):
        s = game.initial
        for _ in range(60):
            assert not game.is_collision(s)
            moves = sol.winning_moves(s)
            assert moves
            replies = list(game.successors(s, moves[rng.integers(len(moves))]))
            s = replies[rng.integers(len(replies))]


def test_budget_runs_out_as_unknown():
    from plansynth.budget import Budget

    sol = solve(MovingObstacle(16, 4), Budget(seconds=1e-6))
    assert sol.status is GridStatus.UNKNOWN and sol.winning is None and "budget" in sol.message

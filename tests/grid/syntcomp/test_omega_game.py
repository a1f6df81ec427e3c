"""omega (TuLiP's GR(1) solver) on the moving-obstacle game, against the explicit solver."""

from __future__ import annotations

import pytest

from plansynth.budget import Budget
from plansynth.grid.result import GridStatus
from plansynth.grid.syntcomp.moving_obstacle import PUBLISHED, MovingObstacle

# omega and dd come with the baselines extra, which setup installs: no skip here
from plansynth.grid.syntcomp.omega_game import (
    _type_invariant,
    check_strategy,
    solve,
    synthesize,
    versions,
)
from plansynth.grid.syntcomp.safety import _environment_cannot_escape
from plansynth.grid.syntcomp.safety import solve as solve_explicit


def test_omega_runs_on_cudd():
    v = versions()
    assert v["bdd"] == "dd.cudd", v  # what TuLiP's users get when dd's wheel has CUDD


@pytest.mark.parametrize("m,c", [(4, 0), (5, 0), (5, 1), (6, 1), (8, 0), (8, 1)])
def test_omega_agrees_with_the_explicit_solver(m, c):
    game = MovingObstacle(m, c)
    syn = synthesize(game, strategy=False)
    assert syn.status is solve_explicit(game).status
    if (m, c) in PUBLISHED:
        assert (syn.status is GridStatus.REALIZABLE) == PUBLISHED[(m, c)][0]


@pytest.mark.slow
@pytest.mark.parametrize("m,c", [(16, 3), (16, 4), (24, 7), (24, 8)])
def test_omega_agrees_on_the_published_instances(m, c):
    a = solve(MovingObstacle(m, c), Budget(seconds=1200), strategy=False)
    assert a.status is solve_explicit(MovingObstacle(m, c)).status
    assert (a.status is GridStatus.REALIZABLE) == PUBLISHED[(m, c)][0]


@pytest.mark.parametrize("plus_one", [False, True])
def test_strict_and_plain_implication_decide_alike(plus_one):
    for c in (0, 1):
        assert synthesize(MovingObstacle(8, c), strategy=False, plus_one=plus_one).status is (
            GridStatus.REALIZABLE if c == 0 else GridStatus.UNREALIZABLE
        )


@pytest.mark.parametrize("m,c", [(5, 0), (8, 0), (8, 1)])
def test_omega_winning_set_is_the_explicit_one(m, c):
    """omega's winning set holds (state, move code, obsmove) triples of the circuit's
    form; the explicit game's counterpart is: no collision now, and whatever the
    environment replies to that move, the robot is in the explicit winning region."""
    game = MovingObstacle(m, c)
    syn = synthesize(game, strategy=False)
    aut = syn.aut
    names = ["rx", "ry", "ox", "oy", "g", "mx", "my", "obsmove"]
    got = {
        (d["rx"], d["ry"], d["ox"], d["oy"], int(not d["obsmove"]), d["g"], d["mx"], d["my"])
        for d in aut.pick_iter(syn.winning & aut.add_expr(_type_invariant(game)), care_vars=names)
    }
    sol = solve_explicit(game)
    after_env = _environment_cannot_escape(sol.winning, c)
    expected = set()
    for state in game.states():
        if game.is_collision(state):
            continue
        for mx in range(3):
            for my in range(3):
                r = game.move_robot(state.robot, (mx - 1, my - 1))
                if after_env[(*r, *state.obstacle, int(state.obstacle_waits), state.glitches)]:
                    expected.add((*state.robot, *state.obstacle, int(state.obstacle_waits), state.glitches, mx, my))
    assert got == expected
    assert len(got) > 1000


@pytest.mark.parametrize("m", [5, 8])
def test_omega_strategy_is_winning(m):
    syn = synthesize(MovingObstacle(m, 0))
    assert syn.status is GridStatus.REALIZABLE and syn.strategy is not None
    check_strategy(syn)


def test_check_strategy_rejects_a_strategy_that_leaves_the_winning_set():
    syn = synthesize(MovingObstacle(8, 0))
    aut = syn.aut
    # a "strategy" that always stands still ignores the obstacle
    syn.strategy = aut.action["sys"] & aut.add_expr(r"mx' = 1 /\ my' = 1")
    with pytest.raises(AssertionError, match="leaves the winning set"):
        check_strategy(syn)


def test_solve_in_a_child_process_with_a_budget():
    a = solve(MovingObstacle(8, 1), Budget(seconds=120), strategy=False)
    assert a.status is GridStatus.UNREALIZABLE and a.seconds > 0 and a.counters["bdd_nodes"] > 0
    timeout = solve(MovingObstacle(16, 4), Budget(seconds=0.05))
    assert timeout.status is GridStatus.UNKNOWN and "budget" in timeout.message


def test_omega_clamps_the_robot_at_the_border_as_the_circuits_do():
    syn = synthesize(MovingObstacle(5, 0), strategy=False)
    aut = syn.aut
    at_wall = aut.add_expr(r"rx = 0 /\ mx = 0")
    stays = aut.add_expr(r"rx' = 0")
    assert (at_wall & aut.action["env"] & ~stays) == aut.false
    assert (at_wall & aut.action["env"]) != aut.false

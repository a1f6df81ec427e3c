"""The moving-obstacle family written in the grid format
(:func:`plansynth.grid.syntcomp.moving_obstacle.grid_document`) is Ehlers' game, and so
the benchmark's circuits' game.

Three checks, each independent of the engine that will solve the family:

1. step by step (8 x 8 every state, 16 x 16 at random): from every state of
   :class:`MovingObstacle` the grid semantics offers the robot the same next cells, and
   every obstacle reply it allows is one of the game's; the game's extra replies only
   raise the glitch counter without a glitch (the circuits allow that, the format does
   not);
2. the circuits themselves accept every step of the grid-format game as a legal step
   without error (8 x 8 every state and reply; the controller's ``obsmove`` is what the
   game forces): so each of its plays is a play of the benchmark;
3. the winning regions are equal state for state (8 x 8 and 16 x 16, both published c):
   the explicit solver of the game (``syntcomp.safety.solve``) and the grid engine's
   safety fixpoint on the document agree on every state, so raising the counter never
   helps the environment and the published answers carry over.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.grid.native.product.fixpoints import safety as grid_safety
from plansynth.grid.native.product.space import ProductSpace
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.semantics import State as GridState
from plansynth.grid.semantics import joint_choices, robot_move, step
from plansynth.grid.syntcomp.aiger import read
from plansynth.grid.syntcomp.moving_obstacle import MovingObstacle, State, circuit_name, grid_document
from plansynth.grid.syntcomp.moving_obstacle_circuit import StepBatch, compare_step
from plansynth.grid.syntcomp.safety import solve

DATA = Path(__file__).parent / "data"


def grid_state(game: MovingObstacle, s: State) -> GridState:
    return GridState(s.robot, (s.obstacle,), (int(s.obstacle_waits),), (game.glitches - s.glitches,))


def game_state(game: MovingObstacle, g: GridState) -> State:
    return State(g.robot, g.obstacles[0], bool(g.phases[0]), game.glitches - g.glitches[0])


def compare_state(game: MovingObstacle, problem, s: State) -> None:
    gs = grid_state(game, s)
    theirs = {}
    for d in ((dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)):
        theirs.setdefault(game.move_robot(s.robot, d), set()).update(game.successors(s, d))
    ours = {}
    for k in range(len(problem.robot.moves)):
        end, _ = robot_move(problem, s.robot, k)
        ours.setdefault(end, set()).update(
            game_state(game, step(problem, gs, k, j).state) for j in joint_choices(problem, gs)
        )
    assert set(ours) == set(theirs), s
    for end, succ in ours.items():
        extra = theirs[end] - succ
        assert succ <= theirs[end], s
        # every extra reply is one of ours with the counter raised for nothing
        for t in extra:
            assert any(
                u.robot == t.robot
                and u.obstacle == t.obstacle
                and u.obstacle_waits == t.obstacle_waits
                and u.glitches < t.glitches
                for u in succ
            ), (s, t)


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_state_steps_alike(c):
    game = MovingObstacle(8, c)
    problem = grid_problem_from_dict(grid_document(8, c))
    for s in game.states():
        compare_state(game, problem, s)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 15), st.integers(0, 15), st.integers(0, 14), st.integers(0, 14), st.booleans(), st.integers(0, 3))
def test_16x16_random_states_step_alike(rx, ry, ox, oy, waits, g):
    game = MovingObstacle(16, 3)
    compare_state(game, _problem(16, 3), State((rx, ry), (ox, oy), waits, g))


_PROBLEMS: dict = {}


def _problem(m: int, c: int):
    if (m, c) not in _PROBLEMS:
        _PROBLEMS[m, c] = grid_problem_from_dict(grid_document(m, c))
    return _PROBLEMS[m, c]


@pytest.mark.parametrize("c", [0, 1])
def test_the_circuit_accepts_every_step_of_the_format(c):
    """Every (state, robot move, obstacle reply) of the grid game from a state without a
    collision, written as the circuit's inputs: the robot's displacement as its move
    code, the new cells and counter as the environment's inputs, ``obsmove`` true iff
    the obstacle stayed. The circuit must raise no error and see no broken assumption."""
    game = MovingObstacle(8, c)
    problem = grid_problem_from_dict(grid_document(8, c))
    rows: dict[str, list[int]] = {k: [] for k in StepBatch.__dataclass_fields__}
    for s in game.states():
        if game.is_collision(s):
            continue  # the game is over there; the circuit reads it a step late
        gs = grid_state(game, s)
        for k in range(len(problem.robot.moves)):
            end, _ = robot_move(problem, s.robot, k)
            dx, dy = end[0] - s.robot[0], end[1] - s.robot[1]
            for j in joint_choices(problem, gs):
                nxt = step(problem, gs, k, j).state
                nxt_game = game_state(game, nxt)
                if game.is_collision(nxt_game):
                    continue  # a loss of the robot: its err comes one step later
                row = dict(
                    rx=s.robot[0],
                    ry=s.robot[1],
                    ox=s.obstacle[0],
                    oy=s.obstacle[1],
                    waits=int(s.obstacle_waits),
                    g=s.glitches,
                    dx=dx,
                    dy=dy,
                    robx=end[0],
                    roby=end[1],
                    obsx=nxt_game.obstacle[0],
                    obsy=nxt_game.obstacle[1],
                    glitches=nxt_game.glitches,
                    movx=dx + 1,
                    movy=dy + 1,
                    obsmove=int(nxt_game.obstacle == s.obstacle),
                    first=0,
                    violated=0,
                )
                for key, v in row.items():
                    rows[key].append(v)
    q = StepBatch(**{k: np.array(v, dtype=np.int32) for k, v in rows.items()})
    report = compare_step(game, read(DATA / circuit_name(8, c)), q)
    assert report["err_mismatches"] == report["violated_mismatches"] == report["latches_mismatches"] == 0, report
    from plansynth.grid.syntcomp.moving_obstacle_circuit import expected_step

    err, violated = expected_step(game, q)
    assert not err.any() and not violated.any()
    assert len(q) > 10_000


@pytest.mark.parametrize("m, c", [(8, 0), (8, 1), (16, 3), (16, 4)])
def test_winning_regions_are_equal(m, c):
    game = MovingObstacle(m, c)
    theirs = solve(game)
    space = ProductSpace.explore(_problem(m, c))
    ours = grid_safety(space)
    index = {conf: i for i, conf in enumerate(space.configs)}
    compared = 0
    for ox, oy in ((x, y) for x in range(m - 1) for y in range(m - 1)):
        for waits in (0, 1):
            for g in range(c + 1):
                oc = index.get((((ox, oy), waits, c - g),))
                if oc is None:
                    continue  # not reachable from the start in the format's game
                for r in range(m * m):
                    rx, ry = r % m, r // m
                    if ox <= rx <= ox + 1 and oy <= ry <= oy + 1:
                        continue  # a collision: the play is over, no state of the format's game
                    assert ours.wins(r, space.node(oc)) == bool(theirs.winning[rx, ry, ox, oy, waits, g]), (
                        rx,
                        ry,
                        ox,
                        oy,
                        waits,
                        g,
                    )
                    compared += 1
    assert compared > m * m * (m - 1) ** 2
    r0, n0 = space.start()
    assert ours.wins(r0, n0) == (theirs.status.value == "realizable")

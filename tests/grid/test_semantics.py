"""One step of the grid game (spec: grid-problem.md, Semantics) and its compiled tables."""

from __future__ import annotations

import math
from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from plansynth.grid.problem import GridProblem, grid_problem_from_dict
from plansynth.grid.semantics import (
    CompiledSemantics,
    State,
    initial_state,
    obstacle_choices,
    obstacle_move,
    robot_end,
    robot_move,
    step,
)

from .strategies import grid_problems, states_of

ALL = ["stay", "up", "down", "right", "left", "up-right", "up-left", "down-right", "down-left"]


def problem(
    robot: list[Any] | None = None,
    obstacles: list[tuple[tuple[int, int], list[Any]]] = (),
    walls: list[list[int]] = (),
    grid: tuple[int, int] = (4, 4),
    start: tuple[int, int] = (0, 0),
    goal: tuple[int, int] = (3, 3),
) -> GridProblem:
    return grid_problem_from_dict(
        {
            "grid": list(grid),
            "robot": {"start": list(start), "goal": list(goal), "moves": robot or ALL},
            "obstacles": [{"start": list(c), "moves": m} for c, m in obstacles],
            "walls": [list(w) for w in walls],
        }
    )


def k(p: GridProblem, name: str) -> int:
    return [m.name for m in p.robot.moves].index(name)


# -- clamping at the border ------------------------------------------------------------


def test_moves_off_the_grid_are_clamped_and_sweep_only_the_start() -> None:
    p = problem()
    assert robot_move(p, (0, 0), k(p, "left")) == ((0, 0), ((0, 0),))
    assert robot_move(p, (0, 0), k(p, "down")) == ((0, 0), ((0, 0),))
    assert robot_move(p, (3, 3), k(p, "up-right")) == ((3, 3), ((3, 3),))
    assert robot_move(p, (3, 1), k(p, "right")) == ((3, 1), ((3, 1),))  # no aliasing to the next row
    assert robot_move(p, (0, 0), k(p, "up-right")) == ((1, 1), ((0, 0), (1, 1)))


def test_a_via_cell_off_the_grid_clamps_even_when_the_end_is_inside() -> None:
    hook = {"name": "hook", "to": [0, 1], "via": [[-1, 0], [-1, 1]]}
    p = problem(robot=["stay", hook])
    assert robot_move(p, (0, 0), 1) == ((0, 0), ((0, 0),))
    assert robot_move(p, (1, 0), 1) == ((1, 1), ((1, 0), (1, 1), (0, 0), (0, 1)))


def test_obstacles_clamp_at_the_border_too() -> None:
    p = problem(obstacles=[((3, 3), ["up", "right", "down-left"])])
    assert obstacle_move(p, 0, (3, 3), 0) == ((3, 3), ((3, 3),))
    assert obstacle_move(p, 0, (3, 3), 1) == ((3, 3), ((3, 3),))
    assert obstacle_move(p, 0, (3, 3), 2) == ((2, 2), ((3, 3), (2, 2)))


# -- via cells, diagonals, collisions ----------------------------------------------------


def test_via_cells_are_swept() -> None:
    jump = {"name": "jump", "to": [2, 0], "via": [[1, 0]]}
    leap = {"name": "leap", "to": [2, 0]}
    p = problem(robot=["stay", jump, leap], obstacles=[((1, 1), ["stay", "down"])])
    s = State((0, 0), ((1, 1),))
    assert step(p, s, 1, (1,)).collided  # the obstacle steps into the via cell (1, 0)
    assert not step(p, s, 2, (1,)).collided  # a leap without via jumps over it
    assert step(p, s, 2, (1,)).state == State((2, 0), ((1, 0),))


def test_diagonal_crossing_does_not_collide() -> None:
    p = problem(obstacles=[((1, 0), ["up-left", {"name": "ul-via", "to": [-1, 1], "via": [[0, 1]]}])])
    s = State((0, 0), ((1, 0),))
    ur = k(p, "up-right")
    # Robot (0,0)->(1,1) and obstacle (1,0)->(0,1) cross between cells: no shared cell.
    out = step(p, s, ur, (0,))
    assert out == (State((1, 1), ((0, 1),)), False)
    # The same crossing written with a via cell (1, 1) does collide.
    assert step(p, s, ur, (1,)).collided


def test_head_on_swap_collides() -> None:
    p = problem(obstacles=[((1, 0), ["left"])])
    assert step(p, State((0, 0), ((1, 0),)), k(p, "right"), (0,)) == (State((1, 0), ((0, 0),)), True)


def test_standing_still_is_not_safe_from_an_obstacle_entering() -> None:
    p = problem(obstacles=[((1, 1), ["down"])])
    assert step(p, State((1, 0), ((1, 1),)), k(p, "stay"), (0,)).collided
    assert not step(p, State((2, 0), ((1, 1),)), k(p, "stay"), (0,)).collided


def test_moving_into_the_cell_an_obstacle_leaves_collides() -> None:
    # The obstacle sweeps its start cell, so following it closely is a collision.
    p = problem(obstacles=[((1, 0), ["right"])])
    assert step(p, State((0, 0), ((1, 0),)), k(p, "right"), (0,)).collided


def test_obstacles_may_overlap_each_other() -> None:
    p = problem(obstacles=[((1, 1), ["right"]), ((3, 1), ["left"])])
    out = step(p, State((0, 3), ((1, 1), (3, 1))), k(p, "stay"), (0, 0))
    assert out == (State((0, 3), ((2, 1), (2, 1))), False)


# -- walls -------------------------------------------------------------------------------


def test_walls_clamp_obstacles() -> None:
    jump = {"name": "jump", "to": [0, 2], "via": [[0, 1]]}
    p = problem(obstacles=[((2, 0), ["up", jump])], walls=[[2, 1]])
    assert obstacle_move(p, 0, (2, 0), 0) == ((2, 0), ((2, 0),))
    assert obstacle_move(p, 0, (2, 0), 1) == ((2, 0), ((2, 0),))  # via a wall: clamped too
    assert obstacle_move(p, 0, (2, 2), 0) == ((2, 3), ((2, 2), (2, 3)))


def test_walls_collide_robots_and_do_not_clamp_them() -> None:
    jump = {"name": "jump", "to": [2, 0], "via": [[1, 0]]}
    p = problem(robot=["stay", "right", jump, "up"], walls=[[1, 0]])
    assert robot_move(p, (0, 0), 1) == ((1, 0), ((0, 0), (1, 0)))
    assert step(p, State((0, 0), ()), 1, ()) == (State((1, 0), ()), True)
    assert step(p, State((0, 0), ()), 2, ()).collided  # a via cell on a wall
    assert not step(p, State((0, 0), ()), 3, ()).collided
    assert not step(p, State((0, 0), ()), 0, ()).collided


def test_an_obstacle_standing_on_a_wall_collides_with_a_robot_entering() -> None:
    # The spec does not forbid an obstacle starting on a wall; it then stays there.
    p = problem(obstacles=[((1, 0), ["up", "stay"])], walls=[[1, 0], [1, 1]])
    assert obstacle_move(p, 0, (1, 0), 0) == ((1, 0), ((1, 0),))
    assert step(p, State((0, 0), ((1, 0),)), k(p, "stay"), (0,)) == (State((0, 0), ((1, 0),)), False)


# -- adversary choices, states -------------------------------------------------------------


@given(grid_problems())
def test_obstacle_choices_are_every_joint_move(p: GridProblem) -> None:
    choices = list(obstacle_choices(p))
    assert len(choices) == math.prod(len(o.moves) for o in p.obstacles)
    assert len(set(choices)) == len(choices)
    assert all(0 <= c[i] < len(o.moves) for c in choices for i, o in enumerate(p.obstacles))


def test_initial_state_and_inputs_order() -> None:
    p = problem(obstacles=[((2, 3), ["up"]), ((1, 2), ["down"])], start=(0, 1))
    s = initial_state(p)
    assert s == State((0, 1), ((2, 3), (1, 2)))
    assert s.inputs() == (0, 1, 2, 3, 1, 2)
    assert dict(zip(p.variables, s.inputs())) == {"rx": 0, "ry": 1, "o0x": 2, "o0y": 3, "o1x": 1, "o1y": 2}


@given(grid_problems(), st.data())
def test_every_step_stays_in_the_grid_and_sweeps_its_start(p: GridProblem, data: st.DataObject) -> None:
    s = data.draw(states_of(p))
    kk = data.draw(st.integers(0, len(p.robot.moves) - 1))
    joint = data.draw(st.tuples(*(st.integers(0, len(o.moves) - 1) for o in p.obstacles)))
    end, swept = robot_move(p, s.robot, kk)
    assert p.in_grid(end) and s.robot in swept and end in swept and all(p.in_grid(c) for c in swept)
    for i, (c, j) in enumerate(zip(s.obstacles, joint)):
        o_end, o_swept = obstacle_move(p, i, c, j)
        assert c in o_swept and o_end in o_swept and all(p.in_grid(x) for x in o_swept)
        if o_end != c:
            assert not set(o_swept) & p.walls
    out = step(p, s, kk, joint)
    assert out.state.robot == end
    expected = bool(set(swept) & p.walls) or any(
        set(swept) & set(obstacle_move(p, i, c, j)[1]) for i, (c, j) in enumerate(zip(s.obstacles, joint))
    )
    assert out.collided == expected


# -- the compiled tables agree with step() ---------------------------------------------------


@given(grid_problems(), st.data())
def test_compiled_semantics_agrees_with_step(p: GridProblem, data: st.DataObject) -> None:
    sem = CompiledSemantics(p)
    s = data.draw(states_of(p))
    kk = data.draw(st.integers(0, len(p.robot.moves) - 1))
    joint = data.draw(st.tuples(*(st.integers(0, len(o.moves) - 1) for o in p.obstacles)))
    expected = step(p, s, kk, joint)

    r_end, r_mask = sem.robot[sem.index(s.robot)][kk]
    collided = bool(r_mask & sem.walls)
    ends = []
    for i, (c, j) in enumerate(zip(s.obstacles, joint)):
        o_end, o_mask = sem.obstacle[i][sem.index(c)][j]
        ends.append(sem.cell(o_end))
        collided = collided or bool(o_mask & r_mask)
    assert State(sem.cell(r_end), tuple(ends)) == expected.state
    assert collided == expected.collided


@given(grid_problems())
def test_compiled_tables_match_the_move_functions(p: GridProblem) -> None:
    sem = CompiledSemantics(p)
    cells = [(x, y) for y in range(p.height) for x in range(p.width)]
    assert [sem.index(c) for c in cells] == list(range(p.width * p.height))
    assert all(sem.cell(sem.index(c)) == c for c in cells)
    assert sem.walls == sum(1 << sem.index(w) for w in p.walls)

    def mask(swept) -> int:
        return sum(1 << sem.index(c) for c in set(swept))

    for c in cells:
        for kk in range(len(p.robot.moves)):
            end, swept = robot_move(p, c, kk)
            assert sem.robot[sem.index(c)][kk] == (sem.index(end), mask(swept))
        for i, o in enumerate(p.obstacles):
            row = [obstacle_move(p, i, c, j) for j in range(len(o.moves))]
            assert sem.obstacle[i][sem.index(c)] == tuple((sem.index(e), mask(s)) for e, s in row)
            assert set(sem.obstacle_successors[i][sem.index(c)]) == set(sem.obstacle[i][sem.index(c)])
            assert len(set(sem.obstacle_successors[i][sem.index(c)])) == len(sem.obstacle_successors[i][sem.index(c)])


@given(grid_problems())
def test_robot_end_is_the_end_of_robot_move(p: GridProblem) -> None:
    """robot_end (the verifier's distances to the goal) agrees with robot_move on every
    cell and move, clamped moves included."""
    for x in range(p.width):
        for y in range(p.height):
            for k in range(len(p.robot.moves)):
                assert robot_end(p, (x, y), k) == robot_move(p, (x, y), k)[0]

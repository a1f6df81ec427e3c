"""Runs replayed through the single definition of a step
(:func:`plansynth.grid.semantics.step`), and why a run loses, in words."""

from __future__ import annotations

from collections.abc import Sequence

from plansynth.grid.objective import CollisionRule
from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.semantics import State, initial_state, obstacle_move, robot_move, step

__all__ = ["replay", "collision_reason"]


def replay(
    problem: GridProblem,
    robot_moves: Sequence[int],
    obstacle_moves: Sequence[Sequence[int]],
    steps: int,
) -> tuple[tuple[State, ...], str | None]:
    """Run the moves through :func:`step`; the states and why the run loses (None: it wins)."""
    state = initial_state(problem)
    states = [state]
    for t, (k, joint) in enumerate(zip(robot_moves, obstacle_moves, strict=True)):
        nxt, collided = step(problem, state, k, joint)
        states.append(nxt)
        if collided:
            return tuple(states), collision_reason(problem, state, k, joint, t)
        state = nxt
    if len(robot_moves) == steps and state.robot != problem.robot.goal:
        return tuple(states), (
            f"not on the goal {_fmt(problem.robot.goal)} after step {steps - 1}: the robot is at {_fmt(state.robot)}"
        )
    return tuple(states), None


def collision_reason(problem: GridProblem, state: State, k: int, joint: Sequence[int], t: int) -> str:
    """Why the robot collides at step ``t`` from ``state`` (a wall, or the first obstacle)."""
    end, swept = robot_move(problem, state.robot, k)
    for c in swept:
        if c in problem.walls:
            return f"collision at step {t} with the wall at {_fmt(c)}"
    position = problem.collision is CollisionRule.POSITION
    for i, (p, j) in enumerate(zip(state.obstacles, joint)):
        o_end, o_swept = obstacle_move(problem, i, p, j)
        common = (
            ([end] if end in problem.obstacles[i].block(o_end) else [])
            if position
            else [c for c in swept if c in o_swept]
        )
        if common:
            return f"collision at step {t} in cell {_fmt(common[0])} with obstacle {i}"
    raise ValueError(f"no collision at step {t}")


def _fmt(c: Cell) -> str:
    return f"({c[0]}, {c[1]})"

"""Runs of a controller against chosen obstacle behaviours, for pictures and inspection.

The verifier (:mod:`plansynth.grid.verify`) answers whether a controller wins against
*every* obstacle behaviour; this module produces *one* run to look at:

- ``obstacles="adversarial"``: if the controller loses, the verifier's counterexample;
  if it wins, a greedy adversary that moves every obstacle as close to the robot as it
  can at each step (Manhattan distance between end cells), so that the picture shows
  the controller reacting to pressure.
- ``obstacles="random"``: every obstacle takes a uniformly random move (seeded).

Steps follow :func:`plansynth.grid.semantics.step`, and a run stops at its first
collision.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [4, 1],
...     "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}]})
>>> run = simulate(p, parse_program("1"), 3)
>>> run.wins, run.collision
(False, Collision(step=1, cell=(2, 0), obstacle=0))
>>> [s.robot for s in run.states]
[(0, 0), (1, 0), (2, 0)]
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Literal

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.programs import Term, compile_program
from plansynth.grid.semantics import State, initial_state, obstacle_move, robot_move, step
from plansynth.grid.verify import check_controller, collision_reason, verify

ObstacleMode = Literal["adversarial", "random"]
MODES: tuple[str, ...] = ("adversarial", "random")


@dataclass(frozen=True)
class Collision:
    """The robot's first collision: at ``step`` in ``cell``, with ``obstacle`` (None: a wall)."""

    step: int
    cell: Cell
    obstacle: int | None


@dataclass(frozen=True)
class Run:
    """One run of a controller.

    ``states[t]`` is the state at the start of step t (``states[0]`` the initial one);
    ``robot_moves[t]`` and ``obstacle_moves[t]`` the moves taken at step t. ``wins`` is
    the verifier's verdict for the controller at ``steps`` (against every behaviour,
    not just this one); ``outcome`` says how this run ends and ``on_goal`` whether it
    took every step without collision and ended on the goal.
    """

    steps: int
    mode: str
    states: tuple[State, ...]
    robot_moves: tuple[int, ...]
    obstacle_moves: tuple[tuple[int, ...], ...]
    collision: Collision | None
    wins: bool
    outcome: str
    on_goal: bool  # every step taken without collision, ending on the goal


def simulate(
    problem: GridProblem,
    program: Term,
    steps: int,
    obstacles: ObstacleMode | str = "adversarial",
    seed: int = 0,
) -> Run:
    """A run of ``program`` on ``problem`` for ``steps`` steps (see the module docstring)."""
    if obstacles not in MODES:
        raise ValueError(f"obstacles must be one of {', '.join(MODES)}, got {obstacles!r}")
    check_controller(problem, program)
    verdict = verify(problem, program, steps)
    if obstacles == "adversarial" and verdict.counterexample is not None:
        cex = verdict.counterexample
        return run_from_moves(problem, steps, obstacles, cex.states, cex.robot_moves, cex.obstacle_moves, verdict.wins)

    controller = compile_program(program, problem.variables)
    rng = random.Random(seed)
    state = initial_state(problem)
    states, robot_moves, joint_moves = [state], [], []
    for _ in range(steps):
        k = controller(*state.inputs())
        if obstacles == "random":
            joint = tuple(rng.randrange(len(o.moves)) for o in problem.obstacles)
        else:
            joint = _greedy(problem, state, k)
        state, collided = step(problem, state, k, joint)
        states.append(state)
        robot_moves.append(k)
        joint_moves.append(joint)
        if collided:
            break
    return run_from_moves(
        problem, steps, obstacles, tuple(states), tuple(robot_moves), tuple(joint_moves), verdict.wins
    )


def _greedy(problem: GridProblem, state: State, k: int) -> tuple[int, ...]:
    """Each obstacle's move ending nearest the robot's end cell (first such move on ties)."""
    (rx, ry), _ = robot_move(problem, state.robot, k)
    joint = []
    for i, (o, cell) in enumerate(zip(problem.obstacles, state.obstacles)):

        def distance(j: int) -> int:
            (x, y), _ = obstacle_move(problem, i, cell, j)
            return abs(x - rx) + abs(y - ry)

        joint.append(min(range(len(o.moves)), key=distance))
    return tuple(joint)


def run_from_moves(
    problem: GridProblem,
    steps: int,
    mode: str,
    states: tuple[State, ...],
    robot_moves: tuple[int, ...],
    obstacle_moves: tuple[tuple[int, ...], ...],
    wins: bool,
) -> Run:
    """The :class:`Run` of these moves (``mode`` says who chose the obstacles' moves):
    the collision located by replaying them with step(), and the outcome described."""
    collision = None
    outcome = ""
    for t, (k, joint) in enumerate(zip(robot_moves, obstacle_moves)):
        if step(problem, states[t], k, joint).collided:
            collision = _collision(problem, states[t], k, joint, t)
            outcome = collision_reason(problem, states[t], k, joint, t)
            break
    end = states[-1].robot
    reached = collision is None and len(robot_moves) == steps and end == problem.robot.goal
    if collision is None:
        if reached:
            outcome = f"on the goal {_fmt(end)} after step {steps - 1}"
        else:
            outcome = f"not on the goal {_fmt(problem.robot.goal)} after step {steps - 1}: the robot is at {_fmt(end)}"
    return Run(steps, mode, states, robot_moves, obstacle_moves, collision, wins, outcome, reached)


def _collision(problem: GridProblem, state: State, k: int, joint: tuple[int, ...], t: int) -> Collision:
    _, swept = robot_move(problem, state.robot, k)
    for c in swept:
        if c in problem.walls:
            return Collision(t, c, None)
    for i, (p, j) in enumerate(zip(state.obstacles, joint)):
        _, o_swept = obstacle_move(problem, i, p, j)
        for c in swept:
            if c in o_swept:
                return Collision(t, c, i)
    raise ValueError(f"no collision at step {t}")  # pragma: no cover - callers check first


def _fmt(c: Cell) -> str:
    return f"({c[0]}, {c[1]})"

"""One step of a witness play (the obstacles' strategy against the robot's best try):
the state seen, the robot's move, the obstacles' answer and, on the last step, how the
robot lost. Both witnesses print these: the paper engine's (:mod:`.explain`) and the
product game's (:mod:`.product.witness`).

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.semantics import initial_state
>>> p = grid_problem_from_dict({"grid": [3, 1],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [2, 0], "moves": ["stay", "left"]}], "steps": 2})
>>> collision_text(p, initial_state(p), 1, (1,), 0)
'collision at step 0 in cell (1, 0) with obstacle 0'
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, obstacle_move, robot_move

__all__ = ["Turn", "collision_text"]


@dataclass(frozen=True)
class Turn:
    """One step of the play: the state seen, the robot's move, the obstacles' answer."""

    t: int
    state: State
    robot_move: int
    obstacle_moves: tuple[int, ...]
    reason: str = ""  # set on the last turn: how the robot lost


def collision_text(problem: GridProblem, state: State, k: int, joint: tuple[int, ...], t: int) -> str:
    """How robot move ``k`` against the obstacles' moves ``joint`` collides at step ``t``."""
    _, r_swept = robot_move(problem, state.robot, k)
    for c in r_swept:
        if c in problem.walls:
            return f"collision at step {t} with the wall at {c}"
    for i, j in enumerate(joint):
        _, swept = obstacle_move(problem, i, state.obstacles[i], j)
        common = sorted(set(swept) & set(r_swept))
        if common:
            return f"collision at step {t} in cell {common[0]} with obstacle {i}"
    return f"collision at step {t}"

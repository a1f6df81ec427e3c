"""Brute-force oracles for the native engine, written only in terms of
:func:`plansynth.grid.semantics.step` (no bitsets, no SAT, no cone of influence).

For tiny problems only: they enumerate every joint obstacle choice. Tests compare the
engine's answers with them.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 1],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}})
>>> stationary_exists(p, 2), stationary_exists(p, 1)
(True, False)
"""

from __future__ import annotations

from functools import cache

from plansynth.grid.oracle import TooLarge, stationary_search
from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, initial_state, obstacle_choices, step

__all__ = ["game_won", "stationary_exists", "TooLarge"]


def game_won(problem: GridProblem, steps: int) -> bool:
    """Does the robot win when its moves may depend on the time and the whole state?"""
    joints = list(obstacle_choices(problem))
    n = len(problem.robot.moves)

    @cache
    def win(t: int, s: State) -> bool:
        if t == steps:
            return s.robot == problem.robot.goal
        for k in range(n):
            ok = True
            for j in joints:
                out = step(problem, s, k, j)
                if out.collided or not win(t + 1, out.state):
                    ok = False
                    break
            if ok:
                return True
        return False

    return win(0, initial_state(problem))


def stationary_exists(problem: GridProblem, steps: int, limit: int = 200_000, max_seconds: float | None = None) -> bool:
    """Is there a map from states to moves (a controller seeing positions only) that
    wins at exactly ``steps``? Backtracking over the states the partial map reaches
    (the oracle's :func:`~plansynth.grid.oracle.stationary_search`)."""
    return stationary_search(problem, steps, limit, max_seconds)

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

from plansynth.grid.oracle import outcome_of
from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, initial_state, obstacle_choices, step


class TooLarge(Exception):
    """The brute force gave up (more nodes than its limit)."""


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
    wins at exactly ``steps``? Backtracking over the states the partial map reaches."""
    import time

    n = len(problem.robot.moves)
    nodes = [0]
    deadline = None if max_seconds is None else time.perf_counter() + max_seconds

    def search(f: dict[State, int]) -> bool:
        nodes[0] += 1
        if nodes[0] > limit:
            raise TooLarge(f"more than {limit} partial strategies")
        if deadline is not None and nodes[0] % 64 == 0 and time.perf_counter() > deadline:
            raise TooLarge(f"more than {max_seconds} s")
        r = outcome_of(problem, steps, f)
        if r is True or r is False:
            return r
        for k in range(n):
            f[r] = k
            if search(f):
                return True
            del f[r]
        return False

    return search({})

"""Brute-force oracles for tiny grid problems (STYLE.md, point 6).

Plain recursion over every joint obstacle choice, stepping with
:func:`~plansynth.grid.semantics.step` and evaluating controllers with the reference
interpreter :func:`~plansynth.grid.programs.evaluate`. No reduction of any kind except
remembering (t, state) pairs already shown safe, so the cost is exponential in the
number of obstacles: use these only as oracles in property tests, never in tools.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [3, 2],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [1, 1], "moves": ["stay", "down"]}]})
>>> reference_wins(p, parse_program("1"), 2)      # the obstacle can step into (1, 0)
False
>>> reference_wins(p, parse_program("(ite (= o0y 0) 0 1)"), 2)   # waiting does not help
False
"""

from __future__ import annotations

from collections.abc import Iterator

from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, evaluate
from plansynth.grid.semantics import State, initial_state, obstacle_choices, step


def controller_move(problem: GridProblem, program: Term, state: State) -> int:
    """The move the program chooses in ``state`` (reference interpreter)."""
    env = dict(zip(problem.variables, state.inputs(), strict=True))
    k = evaluate(program, env)
    if isinstance(k, bool) or not 0 <= k < len(problem.robot.moves):
        raise ValueError(f"the program returned {k!r}, not a move number of the robot")
    return k


def reference_wins(problem: GridProblem, program: Term, steps: int) -> bool:
    """True iff ``program`` wins ``problem`` at exactly ``steps`` steps (spec semantics)."""
    joint = list(obstacle_choices(problem))
    safe: set[tuple[int, State]] = set()

    def wins_from(t: int, state: State) -> bool:
        if t == steps:
            return state.robot == problem.robot.goal
        if (t, state) in safe:
            return True
        k = controller_move(problem, program, state)
        for choice in joint:
            nxt, collided = step(problem, state, k, choice)
            if collided or not wins_from(t + 1, nxt):
                return False
        safe.add((t, state))
        return True

    return wins_from(0, initial_state(problem))


def all_runs(problem: GridProblem, program: Term, steps: int) -> Iterator[tuple[tuple[State, ...], bool]]:
    """Every run of the program against every obstacle behaviour, as (states, lost).

    A run stops at its first collision. Exponential: for tests on tiny problems only.
    """
    joint = list(obstacle_choices(problem))

    def runs(t: int, states: tuple[State, ...]) -> Iterator[tuple[tuple[State, ...], bool]]:
        state = states[-1]
        if t == steps:
            yield states, state.robot != problem.robot.goal
            return
        k = controller_move(problem, program, state)
        for choice in joint:
            nxt, collided = step(problem, state, k, choice)
            if collided:
                yield (*states, nxt), True
            else:
                yield from runs(t + 1, (*states, nxt))

    yield from runs(0, (initial_state(problem),))


def reachable_cells(problem: GridProblem, i: int, steps: int) -> list[frozenset[tuple[int, int]]]:
    """The cells obstacle ``i`` can occupy at times 0..steps, by breadth-first search."""
    from plansynth.grid.semantics import obstacle_move

    cur = frozenset((problem.obstacles[i].start,))
    out = [cur]
    for _ in range(steps):
        cur = frozenset(obstacle_move(problem, i, c, k)[0] for c in cur for k in range(len(problem.obstacles[i].moves)))
        out.append(cur)
    return out

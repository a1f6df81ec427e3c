"""GIF of the obstacles' witness play (``plansynth grid explain --gif``), drawn by the
shared renderer :mod:`plansynth.grid.render` so it looks like every other grid run."""

from __future__ import annotations

from pathlib import Path

from plansynth.grid.problem import GridProblem


def witness_run(problem: GridProblem, explanation):
    """The play of an :class:`~plansynth.grid.native.explain.Explanation` as a
    :class:`~plansynth.grid.simulate.Run` (mode ``witness``; the robot loses)."""
    from plansynth.grid.simulate import run_from_moves

    states = tuple(turn.state for turn in explanation.play) + (explanation.final,)
    robot_moves = tuple(turn.robot_move for turn in explanation.play)
    obstacle_moves = tuple(tuple(turn.obstacle_moves) for turn in explanation.play)
    return run_from_moves(problem, explanation.steps, "witness", states, robot_moves, obstacle_moves, False)


def animate_play(problem: GridProblem, explanation, path_gif: str | Path, fps: float = 2) -> Path:
    """Animate the witness play with :func:`plansynth.grid.render.animate`."""
    from plansynth.grid.render import animate

    return animate(problem, witness_run(problem, explanation), path_gif, fps=fps)
